"""Drop-in replacements for MDAnalysis's capped_distance, self_capped_distance and FastNS,
computed by tricell, and install() / uninstall(), which route MDAnalysis's own analyses to them.

    from tricell.mdanalysis import capped_distance, self_capped_distance, FastNS
    pairs, distances = capped_distance(reference, configuration, 5.0, box=u.dimensions)

    import tricell.mdanalysis
    tricell.mdanalysis.install()     # InterRDF, contacts, hydrogen bonds, around selections...
    tricell.mdanalysis.uninstall()   # MDAnalysis's own functions again

The signatures and results are MDAnalysis 2.4's: pairs (n_pairs x 2, intp) of indices into
`reference` and `configuration` (or twice into `reference`, i < j, for the self search) whose
minimum-image distance d satisfies min_cutoff < d <= max_cutoff, and the distances (float64);
`box` is [a, b, c, alpha, beta, gamma] in MDAnalysis's frame (a along x, b in the xy plane; the
matrix is MDAnalysis's own triclinic_vectors, in float64) or None for no periodicity; positions
are arrays of shape (n, 3) or (3,), or AtomGroups. The order of the pairs is the search's (the
same for the same input; MDAnalysis's order, too, depends on the method its automatic choice
takes). `method` is accepted and ignored: every method is tricell's search. FastNS(cutoff,
coords, box, pbc=True) has search(search_coords) and self_search(), whose results have
get_pairs() and get_pair_distances(), as MDAnalysis.lib.nsgrid.FastNS.

Two things differ from MDAnalysis, both on purpose: any cutoff works, also beyond half the box
(where FastNS refuses; the distance is still the minimum image's), and the distances are
computed in float64 from the positions as given (MDAnalysis rounds them to float32 first, and
FastNS computes in float32), so that d <= max_cutoff is decided exactly on the distance
returned. Bad input raises ValueError or TypeError naming the argument (reference,
configuration, coords, search_coords, max_cutoff, min_cutoff, cutoff, box, method), also for
non-finite positions, which MDAnalysis accepts.

How it works: the search is tricell's list (tricell.NeighborList) with the cutoff raised to the
next double above max_cutoff, so that the library's strict d < cutoff is d <= max_cutoff. Within
one set it is the half list. Between two sets, the smaller set is the query of a half list over
both sets together, and only its pairs into the other set are kept; the same set twice (InterRDF
of a group with itself) is its full list plus each point with itself. Below half the cell's
smallest width every pair comes once; beyond, the list is sorted, so that the images of a pair
are neighbours, and the nearest is kept. The search reaches no farther than any pair can be:
half the cell's longest diagonal in a box, the diagonal of the points' bounding box without one.
Like MDAnalysis it sets no limit on the number of pairs; a list that would not fit in the memory
this process may use (tricell's max_bytes) raises MemoryError. This module only translates
arguments and results.
"""
import sys

import numpy as np

from ._tricell import NeighborList as _Search
from ._tricell import _as_array

try:
    from MDAnalysis.lib.mdamath import triclinic_vectors as _triclinic_vectors
except ImportError as error:  # pragma: no cover (the tests need MDAnalysis)
    raise ImportError("tricell.mdanalysis needs MDAnalysis (Debian: python3-mdanalysis; "
                      "pip: MDAnalysis)") from error

__all__ = ["capped_distance", "self_capped_distance", "FastNS", "NSResults", "install",
           "uninstall"]

_METHODS = ("bruteforce", "nsgrid", "pkdtree")


def _positions(value, name, single=True):
    """value (an array of shape (n, 3), or (3,) when single, or an AtomGroup) as float64 n x 3,
    finite."""
    if hasattr(value, "positions") and hasattr(value, "universe"):  # an AtomGroup
        value = value.positions
    array = _as_array(value, name, "real")
    if single and array.shape == (3,):
        array = array.reshape(1, 3)
    if array.ndim != 2 or array.shape[1] != 3:
        shapes = "(n, 3) or (3,)" if single else "(n, 3)"
        raise ValueError(f"{name} must be an array of shape {shapes} (got shape {array.shape})")
    finite = np.isfinite(array).all(axis=1)
    if not finite.all():
        k = int(np.flatnonzero(~finite)[0])
        raise ValueError(f"{name}[{k}] is not finite (got {array[k].tolist()})")
    return array


def _cutoff(value, name):
    """A finite number >= 0."""
    array = _as_array(value, name, "real")
    if array.ndim != 0:
        raise ValueError(f"{name} must be one number (got shape {array.shape})")
    number = float(array)
    if not (np.isfinite(number) and number >= 0):
        raise ValueError(f"{name} must be a finite number >= 0 (got {number})")
    return number


def _min_cutoff(value):
    if value is None:
        return None
    array = _as_array(value, "min_cutoff", "real")
    if array.ndim != 0 or not np.isfinite(array):
        raise ValueError(f"min_cutoff must be one finite number or None (got {value!r})")
    return float(array)


def _method(value):
    if value is not None and (not isinstance(value, str) or value.lower() not in _METHODS):
        raise ValueError(f"method must be None or one of {', '.join(_METHODS)} (got {value!r})")


def _box(value):
    """(matrix with the lattice vectors as rows, periodic) for [a, b, c, alpha, beta, gamma] or
    None: MDAnalysis's own matrix, in float64; the identity, not periodic, for None."""
    if value is None:
        return np.eye(3), False
    box = _as_array(value, "box", "real")
    if box.shape != (6,):
        raise ValueError("box must be None or [a, b, c, alpha, beta, gamma], six numbers "
                         f"(got shape {box.shape})")
    if not np.isfinite(box).all():
        raise ValueError(f"box must hold finite numbers (got {box.tolist()})")
    if not (box[:3] > 0).all():
        raise ValueError(f"box lengths a, b, c must be > 0 (got {box[:3].tolist()})")
    if not ((box[3:] > 0) & (box[3:] < 180)).all():
        raise ValueError("box angles alpha, beta, gamma must be in (0, 180) degrees "
                         f"(got {box[3:].tolist()})")
    with np.errstate(invalid="ignore"):  # its square root of a negative number, for such angles
        matrix = _triclinic_vectors(box, dtype=np.float64)
    if not matrix.any():  # MDAnalysis's answer for angles that close no cell
        raise ValueError(f"box angles alpha, beta, gamma = {box[3:].tolist()} do not form a cell")
    return matrix, True


def _select(i, j, d, keep):
    """The pairs where the mask `keep` holds (through their indices: faster than the mask)."""
    rows = np.flatnonzero(keep)
    return i.take(rows), j.take(rows), d.take(rows)


def _nearest_images(i, j, d):
    """The pairs of a list sorted by (i, j, S), each (i, j) once at its nearest image, without
    the pairs of an atom with its own images."""
    i, j, d = _select(i, j, d, i != j)
    if len(i) < 2:
        return i, j, d
    first = np.empty(len(i), dtype=bool)
    first[0] = True
    np.not_equal(i[1:], i[:-1], out=first[1:])
    first[1:] |= j[1:] != j[:-1]
    starts = np.flatnonzero(first)
    return i.take(starts), j.take(starts), np.minimum.reduceat(d, starts)


def _search(points, max_cutoff, box, full, query=None):
    """i, j, d of tricell's list (full or half; query: the pairs of those points only), each
    pair (i, j) once, with the distance of its nearest image, when that is <= max_cutoff; no
    atom paired with its own image."""
    matrix, periodic = box
    if periodic:
        # No pair's nearest image is farther than the farthest point of the cell centred on a
        # lattice point, a corner; a search beyond it would only list more images.
        a, b, c = matrix
        reach = 0.5 * max(np.linalg.norm(a + b + c), np.linalg.norm(a + b - c),
                          np.linalg.norm(a - b + c), np.linalg.norm(b + c - a))
    else:  # no pair is farther apart than the diagonal of the points' bounding box
        reach = np.linalg.norm(points.max(axis=0) - points.min(axis=0))
    cutoff = float(np.nextafter(min(max_cutoff, reach * (1 + 1e-9)), np.inf))
    # Two images of one pair within the cutoff (or an atom and its own image) are two lattice
    # points within twice the cutoff, and lattice points are no closer than the cell's smallest
    # width: below that every pair comes once. Beyond, the list is sorted so that the images of
    # a pair are neighbours.
    images = periodic and 2 * cutoff >= 1 / np.linalg.norm(np.linalg.inv(matrix), axis=0).max()
    # MDAnalysis sets no limit on the pairs; the memory limit (max_bytes) stays.
    search = _Search(cutoff, full=full, sorted=images, max_pairs=0)
    try:
        i, j, d = search.compute(points, matrix, periodic, "ijd", copy=False, query=query)
    except ValueError as error:
        if "max_bytes" not in str(error):
            raise
        raise MemoryError(f"max_cutoff {max_cutoff} gives more pairs than fit in the memory "
                          f"this process may use ({error})") from None
    return _nearest_images(i, j, d) if images else (i, j, d)


def _result(first, second, distances, min_cutoff, return_distances):
    if min_cutoff is not None:
        first, second, distances = _select(first, second, distances, distances > min_cutoff)
    pairs = np.empty((len(first), 2), dtype=np.intp)
    pairs[:, 0] = first
    pairs[:, 1] = second
    if return_distances:
        return pairs, np.array(distances, dtype=np.float64)
    return pairs


def _between(reference, configuration, max_cutoff, box):
    """(reference index, configuration index, distance) of the pairs with d <= max_cutoff, at
    their nearest image."""
    n, m = len(reference), len(configuration)
    if n == 0 or m == 0:
        return np.zeros(0, np.intp), np.zeros(0, np.intp), np.zeros(0)
    if n == m and np.array_equal(reference, configuration):
        # One set twice (InterRDF of a group with itself, contact matrices): its full list, and
        # each point with itself.
        i, j, d = _search(reference, max_cutoff, box, full=True)
        every = np.arange(n)
        return np.concatenate([i, every]), np.concatenate([j, every]), np.concatenate(
            [d, np.zeros(n)])
    swap = m < n  # the smaller set is the query
    first, second = (configuration, reference) if swap else (reference, configuration)
    nq = len(first)
    i, j, d = _search(np.concatenate([first, second]), max_cutoff, box, full=False,
                      query=np.arange(nq))
    i, j, d = _select(i, j, d, j >= nq)  # pairs into the other set; those within the query go
    j = j - nq
    return (j, i, d) if swap else (i, j, d)


def _within(reference, max_cutoff, box):
    """(i, j, distance) of the pairs i < j of one set with d <= max_cutoff, at their nearest
    image."""
    if len(reference) < 2:
        return np.zeros(0, np.intp), np.zeros(0, np.intp), np.zeros(0)
    return _search(reference, max_cutoff, box, full=False)


def capped_distance(reference, configuration, max_cutoff, min_cutoff=None, box=None,
                    method=None, return_distances=True):
    """MDAnalysis.lib.distances.capped_distance, computed by tricell (see the module's doc):
    pairs [i, j] of reference[i] and configuration[j] with min_cutoff < d <= max_cutoff (d the
    minimum-image distance for a box), and with return_distances their distances."""
    reference = _positions(reference, "reference")
    configuration = _positions(configuration, "configuration")
    max_cutoff = _cutoff(max_cutoff, "max_cutoff")
    min_cutoff = _min_cutoff(min_cutoff)
    box = _box(box)
    _method(method)
    return _result(*_between(reference, configuration, max_cutoff, box), min_cutoff,
                   return_distances)


def self_capped_distance(reference, max_cutoff, min_cutoff=None, box=None, method=None,
                         return_distances=True):
    """MDAnalysis.lib.distances.self_capped_distance, computed by tricell (see the module's
    doc): pairs [i, j], i < j, of reference with min_cutoff < d <= max_cutoff, and with
    return_distances their distances."""
    reference = _positions(reference, "reference")
    max_cutoff = _cutoff(max_cutoff, "max_cutoff")
    min_cutoff = _min_cutoff(min_cutoff)
    box = _box(box)
    _method(method)
    return _result(*_within(reference, max_cutoff, box), min_cutoff, return_distances)


class NSResults:
    """The pairs a FastNS search found: get_pairs() (n_pairs x 2, intp) and
    get_pair_distances() (float64), as MDAnalysis.lib.nsgrid.NSResults."""

    def __init__(self, pairs, distances):
        self._pairs = pairs
        self._distances = distances

    def get_pairs(self):
        return self._pairs

    def get_pair_distances(self):
        return self._distances


class FastNS:
    """MDAnalysis.lib.nsgrid.FastNS, computed by tricell: FastNS(cutoff, coords, box, pbc=True)
    with search(search_coords) (pairs [i, j] of search_coords[i] and coords[j]) and
    self_search() (pairs i < j of coords), both with d <= cutoff. box is [a, b, c, alpha, beta,
    gamma]; with pbc=False it is not used (MDAnalysis asks for a bounding box there, tricell
    needs none) and may be None. Any cutoff works, also beyond half the box."""

    def __init__(self, cutoff, coords, box, pbc=True):
        self._cutoff = _cutoff(cutoff, "cutoff")
        self._coords = _positions(coords, "coords", single=False)
        if pbc:
            if box is None:
                raise ValueError("box must be [a, b, c, alpha, beta, gamma] with pbc=True "
                                 "(got None)")
            self._box = _box(box)
        else:
            if box is not None:
                _as_array(box, "box", "real")  # a number array, as MDAnalysis asks; not used
            self._box = _box(None)

    @property
    def cutoff(self):
        return self._cutoff

    def search(self, search_coords):
        search_coords = _positions(search_coords, "search_coords", single=False)
        i, j, d = _between(search_coords, self._coords, self._cutoff, self._box)
        return NSResults(*_result(i, j, d, None, True))

    def self_search(self):
        return NSResults(*_result(*_within(self._coords, self._cutoff, self._box), None, True))


# install(): the names routed, and MDAnalysis's own objects they replace (kept at the first
# install(), for uninstall()).
_ROUTED = {"capped_distance": capped_distance, "self_capped_distance": self_capped_distance,
           "FastNS": FastNS}
_originals = {}


def _replace(old, new):
    """In every loaded module of the MDAnalysis package, each attribute that is old[name]
    becomes new[name]."""
    for module_name, module in list(sys.modules.items()):
        if module is None or not (module_name == "MDAnalysis"
                                  or module_name.startswith("MDAnalysis.")):
            continue
        for name, value in old.items():
            if getattr(module, name, None) is value:
                setattr(module, name, new[name])


def install():
    """Routes MDAnalysis's capped_distance, self_capped_distance and FastNS to this module's.

    Replaces them in MDAnalysis.lib.distances and MDAnalysis.lib.nsgrid, from which analyses
    look them up at each call (InterRDF, selections such as "around", the bond guesser) or take
    them when they are imported later, and in every MDAnalysis module already imported that
    took its own reference at import (MDAnalysis.lib.NeighborSearch,
    MDAnalysis.analysis.distances, the hydrogen-bond analyses). MDAnalysis's private
    _nsgrid_capped and _nsgrid_capped_self, which build FastNS, use tricell's as well.
    Calling it again changes nothing; uninstall() undoes it."""
    import MDAnalysis.lib.distances
    import MDAnalysis.lib.nsgrid

    if not _originals:
        _originals.update(capped_distance=MDAnalysis.lib.distances.capped_distance,
                          self_capped_distance=MDAnalysis.lib.distances.self_capped_distance,
                          FastNS=MDAnalysis.lib.nsgrid.FastNS)
    _replace(_originals, _ROUTED)


def uninstall():
    """Gives MDAnalysis its own capped_distance, self_capped_distance and FastNS back, in every
    loaded MDAnalysis module holding this module's (also those imported after install()).
    Without an earlier install() it changes nothing."""
    if _originals:
        _replace(_ROUTED, _originals)
