"""NeighborList.compute_batch: every structure's slice equals its own compute() call, array for
array and in order (full and half, sorted or not, any thread count, periodicity per structure
or shared), and errors name the structure."""
import numpy as np
import pytest

import tricell
from conftest import random_system

LETTERS = "ijSdD"


def random_batch(seed):
    """(points, boxes, pbcs, cutoff): 0 to 10 random systems sharing the first one's cutoff."""
    rng = np.random.default_rng(seed)
    count = int(rng.integers(0, 11))
    systems = [random_system(1000 * seed + k) for k in range(count)]
    cutoff = systems[0][3] if systems else 1.0
    return ([s[1] for s in systems], [s[0] for s in systems], [s[2] for s in systems], cutoff)


@pytest.mark.parametrize("seed", range(40))
def test_batch_equals_one_call_per_structure(seed):
    points, boxes, pbcs, cutoff = random_batch(seed)
    rng = np.random.default_rng(seed + 7)
    full, sorted_ = bool(rng.integers(2)), bool(rng.integers(2))
    threads = int(rng.integers(0, 3))
    batch = tricell.NeighborList(cutoff, full=full, sorted=sorted_, threads=threads)
    one = tricell.NeighborList(cutoff, full=full, sorted=sorted_)
    offsets, *columns = batch.compute_batch(points, boxes, pbcs, LETTERS)
    assert offsets.dtype == np.int64 and offsets.shape == (len(points) + 1,)
    assert offsets[0] == 0 and offsets[-1] == len(columns[0])
    for s, (x, h, pbc) in enumerate(zip(points, boxes, pbcs)):
        alone = one.compute(x, h, pbc, LETTERS)
        for letter, mine, expected in zip(LETTERS, columns, alone):
            got = mine[offsets[s]:offsets[s + 1]]
            assert got.dtype == expected.dtype, f"seed {seed} structure {s} {letter}"
            assert np.array_equal(got, expected), f"seed {seed} structure {s} {letter}"


def test_shared_periodicity_and_single_letter():
    points, boxes, _, cutoff = random_batch(5)
    nl = tricell.NeighborList(cutoff)
    for pbc in (True, False, (True, False, True)):
        offsets, d = nl.compute_batch(points, boxes, pbc, "d")
        for s, (x, h) in enumerate(zip(points, boxes)):
            assert np.array_equal(d[offsets[s]:offsets[s + 1]], nl.compute(x, h, pbc, "d"))


def test_empty_batch():
    offsets, i, j = tricell.NeighborList(1.0).compute_batch([], [], True, "ij")
    assert list(offsets) == [0] and i.shape == (0,) and j.shape == (0,)


def test_batch_errors_name_the_structure():
    x = np.random.default_rng(0).random((4, 3))
    nl = tricell.NeighborList(2.0)
    with pytest.raises(ValueError, match=r"boxes has 1 entries for 2 structures"):
        nl.compute_batch([x, x], [np.eye(3)])
    with pytest.raises(ValueError, match=r"periodic has 1 entries for 2 structures"):
        nl.compute_batch([x, x], [np.eye(3)] * 2, [[True, True, True]])
    with pytest.raises(ValueError, match=r"points must be a sequence with one entry per structure"):
        nl.compute_batch(3.0, [np.eye(3)])
    with pytest.raises(ValueError, match=r"structure 1: points must be an array of shape \(N, 3\)"):
        nl.compute_batch([x, x[:, :2]], [np.eye(3)] * 2)
    with pytest.raises(ValueError, match=r"structure 1: boxes must be a 3 x 3 array"):
        nl.compute_batch([x, x], [np.eye(3), np.eye(2)])
    with pytest.raises(ValueError, match=r"structure 0: "):
        nl.compute_batch([x, x], [np.zeros((3, 3)), np.eye(3)])
    bad = x.copy()
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match=r"structure 2: position 2 is not finite"):
        nl.compute_batch([x, x, bad, bad], [np.eye(3) * 3] * 4)
    with pytest.raises(ValueError, match=r"unknown quantity 'x'"):
        nl.compute_batch([x], [np.eye(3)], True, "ix")
    with pytest.raises(ValueError, match=r"compute_batch needs a NeighborList made with one float cutoff"):
        tricell.NeighborList(None).compute_batch([x], [np.eye(3)])
