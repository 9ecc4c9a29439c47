"""Several cutoffs from one search: tricell.neighbor_shells and tricell.neighbor_lists (the
requests of a model, a cutoff and full or half each, for one structure and for a concatenated
batch). Each requested list must hold exactly the pairs of a separate call at its cutoff with
bit-identical d and D, compared after sorting by (i, j, S); errors name the request."""
import types

import numpy as np
import pytest

import tricell
from conftest import random_system, sort_pairs

LETTERS = "ijSdD"


def random_requests(rng, cutoff):
    """1 to 5 requests around `cutoff`, mixed full and half, some cutoffs repeated."""
    count = int(rng.integers(1, 6))
    cutoffs = cutoff * rng.uniform(0.3, 1.2, count)
    if count > 2:
        cutoffs[-1] = cutoffs[0]
    return [(float(r), bool(rng.integers(2))) for r in cutoffs]


def same_list(mine, theirs, context):
    mine, theirs = sort_pairs(*mine), sort_pairs(*theirs)
    for letter, a, b in zip(LETTERS, mine, theirs):
        assert a.dtype == b.dtype and np.array_equal(a, b), f"{context}: {letter}"


@pytest.mark.parametrize("seed", range(60))
def test_each_request_equals_a_separate_call(seed):
    cell, positions, pbc, cutoff, _ = random_system(seed)
    rng = np.random.default_rng(seed)
    requests = random_requests(rng, cutoff)
    lists = tricell.neighbor_lists(positions, cell, pbc, requests, LETTERS,
                                   threads=int(rng.integers(0, 3)), copy=bool(seed % 2))
    assert len(lists) == len(requests)
    for k, ((r, full), got) in enumerate(zip(requests, lists)):
        alone = tricell.NeighborList(r, full=full).compute(positions, cell, pbc, LETTERS)
        same_list(got, alone, f"seed {seed} request {k} ({r}, {full})")


@pytest.mark.parametrize("seed", range(20))
def test_shells_are_prefixes_of_one_ordered_list(seed):
    cell, positions, pbc, cutoff, _ = random_system(seed)
    cutoffs = sorted(set(cutoff * np.random.default_rng(seed).uniform(0.2, 1.0, 3)))
    full = bool(seed % 2)
    offsets, i, j, S, d = tricell.neighbor_shells(positions, cell, pbc, cutoffs, "ijSd", full)
    assert offsets[0] == 0 and offsets[-1] == len(i) and np.all(np.diff(offsets) >= 0)
    for k, r in enumerate(cutoffs):
        shell = d[offsets[k]:offsets[k + 1]]
        assert np.all(shell < r) and (k == 0 or np.all(shell >= cutoffs[k - 1]))
        alone = tricell.NeighborList(r, full=full).compute(positions, cell, pbc, "ijSd")
        prefix = (i[:offsets[k + 1]], j[:offsets[k + 1]], S[:offsets[k + 1]], d[:offsets[k + 1]])
        for a, b in zip(sort_pairs(*prefix), sort_pairs(*alone)):
            assert np.array_equal(a, b), f"seed {seed} cutoff {k}"


@pytest.mark.parametrize("seed", range(30))
def test_batch_requests_equal_one_call_per_structure(seed):
    rng = np.random.default_rng(seed)
    systems = [random_system(40 * seed + k) for k in range(int(rng.integers(0, 6)))]
    cutoff = systems[0][3] if systems else 1.0
    requests = random_requests(rng, cutoff)
    ptr = np.concatenate([[0], np.cumsum([len(s[1]) for s in systems])]).astype(np.int64)
    points = np.concatenate([s[1] for s in systems]) if systems else np.zeros((0, 3))
    boxes = np.array([s[0] for s in systems]).reshape(-1, 3, 3)
    pbc = np.array([s[2] for s in systems], dtype=bool).reshape(-1, 3)
    lists = tricell.neighbor_lists(points, boxes, pbc, requests, LETTERS, batch_ptr=ptr)
    for k, ((r, full), (offsets, *columns)) in enumerate(zip(requests, lists)):
        assert offsets.shape == (len(systems) + 1,) and offsets[-1] == len(columns[0])
        for s, (cell, positions, periodic, _, _) in enumerate(systems):
            rows = slice(offsets[s], offsets[s + 1])
            mine = [c[rows] for c in columns]
            mine[0], mine[1] = mine[0] - ptr[s], mine[1] - ptr[s]
            alone = tricell.NeighborList(r, full=full).compute(positions, cell, periodic,
                                                                LETTERS)
            same_list([m.astype(a.dtype) for m, a in zip(mine, alone)], alone,
                      f"seed {seed} request {k} structure {s}")


def test_requests_as_metatomic_options_and_single_letters():
    cell, positions, pbc, cutoff, _ = random_system(2)
    options = [types.SimpleNamespace(cutoff=cutoff, full_list=True, strict=True),
               types.SimpleNamespace(cutoff=0.5 * cutoff, full_list=False, strict=True)]
    d_full, d_half = tricell.neighbor_lists(positions, cell, pbc, options, "d")
    assert np.array_equal(np.sort(d_full), np.sort(
        tricell.NeighborList(cutoff).compute(positions, cell, pbc, "d")))
    assert np.array_equal(np.sort(d_half), np.sort(
        tricell.NeighborList(0.5 * cutoff, full=False).compute(positions, cell, pbc, "d")))
    P, = tricell.neighbor_lists(positions, cell, pbc, [(cutoff, True)], "P")
    assert P.shape[1] == 2


def test_bad_requests_name_the_request():
    points, box = np.zeros((2, 3)), np.eye(3)
    with pytest.raises(ValueError, match=r"^requests must hold at least one request"):
        tricell.neighbor_lists(points, box, True, [])
    with pytest.raises(ValueError, match=r"^requests\[1\] must be \(cutoff, full\) or have "
                                         r"cutoff and full_list \(got 3.0\)"):
        tricell.neighbor_lists(points, box, True, [(1.0, True), 3.0])
    with pytest.raises(ValueError, match=r"^requests\[0\]: cutoff must be > 0 \(got -1\)"):
        tricell.neighbor_lists(points, box, True, [(-1.0, True)])
    with pytest.raises(ValueError, match=r"^requests\[2\]: cutoff must be finite \(got nan\)"):
        tricell.neighbor_lists(points, box, True, [(1.0, True), (2.0, False), (np.nan, True)])
    with pytest.raises(ValueError, match=r"^requests must be a sequence"):
        tricell.neighbor_lists(points, box, True, "1.0")
    with pytest.raises(ValueError, match=r"unknown quantity 'o'"):
        tricell.neighbor_lists(points, box, True, [(1.0, True)], "ijo")
    with pytest.raises(ValueError, match=r"cutoffs must increase strictly"):
        tricell.neighbor_shells(points, box, True, [2.0, 1.0])
    with pytest.raises(ValueError, match=r"quantity 'o' \(per-atom offsets\) does not apply"):
        tricell.neighbor_shells(points, box, True, [1.0], "io")
