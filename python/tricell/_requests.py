"""tricell.neighbor_lists: the neighbour lists a model requests (a cutoff and full or half each,
as metatomic's NeighborListOptions give them) from one search at the largest cutoff.

One structure: tricell.neighbor_shells orders the pairs of that search by shell, so the list
of each cutoff is a prefix of its columns. Requests of one kind (all full or all half) are
those prefixes; when full and half lists are both asked for, the search is a half list and a
full list is its prefix followed by each pair reversed, (j, i, -S) with -D and the same d.
A batch (batch_ptr=): one NeighborList.compute_batch at the largest cutoff, then each list
keeps the pairs with d < its cutoff (the search's own test, include/tricell/analysis/
shells.hpp), a full list derived from a half one holding each structure's pairs then their
reversals. Every list holds exactly the pairs, d and D of a separate call at its cutoff.
"""
import numpy as np

from ._tricell import NeighborList, neighbor_shells

_REVERSED = {"i": "j", "j": "i", "P": "P"}


def _parsed(requests):
    """[(cutoff, full)] of `requests`: (cutoff, full) pairs or objects with `cutoff` and
    `full_list` (metatomic's NeighborListOptions); ValueError naming the entry otherwise."""
    if isinstance(requests, (str, bytes)) or not hasattr(requests, "__len__"):
        raise ValueError(f"requests must be a sequence of (cutoff, full) or of options with "
                         f"cutoff and full_list (got {requests!r:.80})")
    if len(requests) == 0:
        raise ValueError("requests must hold at least one request (got none)")
    parsed = []
    for k, request in enumerate(requests):
        if hasattr(request, "cutoff") and hasattr(request, "full_list"):
            cutoff, full = request.cutoff, request.full_list
        elif isinstance(request, (tuple, list)) and len(request) == 2:
            cutoff, full = request
        else:
            raise ValueError(f"requests[{k}] must be (cutoff, full) or have cutoff and "
                             f"full_list (got {request!r:.80})")
        try:
            cutoff = float(cutoff)
            NeighborList(cutoff)  # the library's rule for a cutoff
        except (TypeError, ValueError) as error:
            raise ValueError(f"requests[{k}]: {error}") from None
        parsed.append((cutoff, bool(full)))
    return parsed


def _reversed_columns(letters, columns):
    """The columns of each pair reversed: (j, i, -S), -D, the same d; P with its ends swapped."""
    by_letter = dict(zip(letters, columns))
    out = []
    for letter in letters:
        if letter in "ij":
            out.append(by_letter[_REVERSED[letter]])
        elif letter == "P":
            out.append(by_letter["P"][:, ::-1])
        elif letter in "SD":
            out.append(-by_letter[letter])
        else:
            out.append(by_letter[letter])
    return out


def _single(points, box, periodic, requests, letters, threads, copy):
    cutoffs = sorted({cutoff for cutoff, _ in requests})
    kinds = {full for _, full in requests}
    search_full = kinds == {True}
    offsets, *columns = neighbor_shells(points, box, periodic, cutoffs, letters, search_full,
                                        threads, copy=False)
    out = []
    for cutoff, full in requests:
        n = offsets[cutoffs.index(cutoff) + 1]
        prefix = [c[:n] for c in columns]
        if full and not search_full:
            prefix = [np.concatenate([a, b]) for a, b in
                      zip(prefix, _reversed_columns(letters, prefix))]
        elif copy:
            prefix = [c.copy() for c in prefix]
        out.append(prefix[0] if len(letters) == 1 else tuple(prefix))
    return out


def _batch(points, boxes, periodic, batch_ptr, requests, letters, threads):
    largest = max(cutoff for cutoff, _ in requests)
    kinds = {full for _, full in requests}
    search_full = kinds == {True}
    asked = letters + "".join(q for q in "ijd" if q not in letters)
    search = NeighborList(largest, full=search_full, threads=threads)
    offsets, *columns = search.compute_batch(points, boxes, periodic, asked,
                                             batch_ptr=batch_ptr, copy=False)
    by_letter = dict(zip(asked, columns))
    count = len(offsets) - 1
    system = np.repeat(np.arange(count), np.diff(offsets))
    out = []
    for cutoff, full in requests:
        keep = by_letter["d"] < cutoff
        kept = [by_letter[q][keep] for q in letters]
        kept_system = system[keep]
        if full and not search_full:
            # Each structure's pairs, then their reversals: a stable sort by structure.
            order = np.argsort(np.concatenate([kept_system, kept_system]), kind="stable")
            kept = [np.concatenate([a, b])[order] for a, b in
                    zip(kept, _reversed_columns(letters, kept))]
            kept_system = np.concatenate([kept_system, kept_system])[order]
        counts = np.bincount(kept_system, minlength=count)
        kept_offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        out.append((kept_offsets, *kept))
    return out


def neighbor_lists(points, box, periodic, requests, quantities="ijSd", threads=1, copy=True,
                   batch_ptr=None):
    """The neighbour lists of several requests from one search at the largest cutoff.

    requests: a sequence of (cutoff, full) pairs, or of objects with `cutoff` and `full_list`
    (metatomic's NeighborListOptions). Returns one entry per request, in their order: as
    NeighborList(cutoff, full).compute(points, box, periodic, quantities) returns its columns
    (one array for one letter, else a tuple), with exactly its pairs, d and D (in the order of
    the shells of the one search). With batch_ptr, points, box and periodic are the
    concatenated batch of NeighborList.compute_batch (box: B x 3 x 3) and each entry is a tuple
    (offsets, *columns) as compute_batch returns it, i and j indexing the rows of points.
    Letters: i, j, S, d, D, P. threads: of the search (0: every core); copy=False may return
    views of the one search's columns.
    """
    parsed = _parsed(requests)
    letters = str(quantities)
    for letter in letters:
        if letter not in "ijSdDP":
            raise ValueError(f"unknown quantity '{letter}' in quantities='{letters}' (expected "
                             "letters among i, j, S, d, D, P)")
    if not letters:
        raise ValueError("quantities must name at least one of i, j, S, d, D, P (got '')")
    if batch_ptr is None:
        return _single(points, box, periodic, parsed, letters, threads, copy)
    return _batch(points, box, periodic, batch_ptr, parsed, letters, threads)
