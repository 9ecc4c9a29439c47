"""NeighborList.compute_batch: every structure's slice equals its own compute() call, array for
array and in order (full and half, sorted or not, any thread count, periodicity per structure
or shared), in the list form and in the concatenated form (batch_ptr, global i and j), and
errors name the argument and the structure."""
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


def concatenated(points, boxes, pbcs):
    """The concatenated format of a list-form batch: (points, boxes, periodic, batch_ptr)."""
    ptr = np.concatenate([[0], np.cumsum([len(x) for x in points])]).astype(np.int64)
    x = np.concatenate(points) if points else np.zeros((0, 3))
    return x, np.array(boxes).reshape(-1, 3, 3), np.array(pbcs, dtype=bool).reshape(-1, 3), ptr


@pytest.mark.parametrize("seed", range(40))
def test_concatenated_batch_equals_one_call_per_structure_with_global_indices(seed):
    points, boxes, pbcs, cutoff = random_batch(seed)
    rng = np.random.default_rng(seed + 11)
    full, sorted_ = bool(rng.integers(2)), bool(rng.integers(2))
    threads, copy = int(rng.integers(0, 3)), bool(rng.integers(2))
    batch = tricell.NeighborList(cutoff, full=full, sorted=sorted_, threads=threads)
    one = tricell.NeighborList(cutoff, full=full, sorted=sorted_)
    x, h, pbc, ptr = concatenated(points, boxes, pbcs)
    offsets, *columns = batch.compute_batch(x, h, pbc, LETTERS + "P", batch_ptr=ptr, copy=copy)
    assert offsets.dtype == np.int64 and offsets.shape == (len(points) + 1,)
    assert offsets[0] == 0 and offsets[-1] == len(columns[0])
    for s in range(len(points)):
        alone = one.compute(points[s], boxes[s], pbcs[s], LETTERS + "P")
        shift = {"i": ptr[s], "j": ptr[s], "P": ptr[s]}
        for letter, mine, expected in zip(LETTERS + "P", columns, alone):
            got = mine[offsets[s]:offsets[s + 1]]
            assert got.dtype == expected.dtype, f"seed {seed} structure {s} {letter}"
            assert np.array_equal(got, expected + shift.get(letter, 0)), \
                f"seed {seed} structure {s} {letter}"


def test_both_forms_agree_and_periodic_takes_every_shape():
    points, boxes, pbcs, cutoff = random_batch(3)
    x, h, per_structure, ptr = concatenated(points, boxes, pbcs)
    nl = tricell.NeighborList(cutoff, grouped=True)
    for pbc in (True, False, [True, False, True], per_structure, per_structure.astype(int)):
        listed = nl.compute_batch(points, boxes, pbc, "ijSdo")
        offsets, i, j, S, d, o = nl.compute_batch(x, h, pbc, "ijSdo", batch_ptr=ptr)
        assert np.array_equal(offsets, listed[0]) and np.array_equal(o, listed[5])
        atom_first = np.repeat(ptr[:-1], np.diff(offsets))
        assert np.array_equal(i, listed[1] + atom_first)
        assert np.array_equal(j, listed[2] + atom_first)
        assert np.array_equal(S, listed[3]) and np.array_equal(d, listed[4])


def test_no_pair_joins_two_structures_that_overlap_in_space():
    """The same atoms three times over, one structure each, and an empty structure between."""
    cell, positions, pbc, cutoff, _ = random_system(4, pbc=(True, True, False))
    x = np.concatenate([positions, positions, positions])
    n = len(positions)
    ptr = np.array([0, n, n, 2 * n, 3 * n])
    h = np.array([cell] * 4)
    offsets, i, j = tricell.NeighborList(cutoff).compute_batch(x, h, pbc, "ij", batch_ptr=ptr)
    alone = len(tricell.NeighborList(cutoff).compute(positions, cell, pbc, "i"))
    assert list(np.diff(offsets)) == [alone, 0, alone, alone]
    for s in range(4):
        rows = slice(offsets[s], offsets[s + 1])
        assert np.all((i[rows] >= ptr[s]) & (i[rows] < ptr[s + 1]))
        assert np.all((j[rows] >= ptr[s]) & (j[rows] < ptr[s + 1]))


def test_empty_concatenated_batches():
    nl = tricell.NeighborList(1.0)
    for x, h in ((np.zeros((0, 3)), np.zeros((0, 3, 3))), ([], [])):
        offsets, i, d = nl.compute_batch(x, h, True, "id", batch_ptr=[0])
        assert list(offsets) == [0] and i.shape == (0,) and d.shape == (0,)
    offsets, i = nl.compute_batch(np.zeros((0, 3)), np.array([np.eye(3)] * 2), True, "i",
                                  batch_ptr=[0, 0, 0])
    assert list(offsets) == [0, 0, 0] and i.shape == (0,)


def test_views_of_a_concatenated_batch_outlive_the_next_call():
    points, boxes, pbcs, cutoff = random_batch(6)
    x, h, pbc, ptr = concatenated(points, boxes, pbcs)
    nl = tricell.NeighborList(cutoff)
    first = nl.compute_batch(x, h, pbc, "Sd", batch_ptr=ptr, copy=False)
    kept = [a.copy() for a in first]
    nl.compute_batch(x + 0.1, h, pbc, "Sd", batch_ptr=ptr, copy=False)
    assert all(np.array_equal(a, b) for a, b in zip(first, kept))


def test_arrays_of_a_batch_are_the_callers_whatever_comes_next():
    """copy=True hands the columns over without a copy, and their buffers come back for reuse
    when dropped: arrays kept stay as they were through later calls (of either copy mode, the
    caller writing into them), dropped ones give the next call the same lists, and a letter
    asked twice gives two arrays."""
    points, boxes, pbcs, cutoff = random_batch(7)
    x, h, pbc, ptr = concatenated(points, boxes, pbcs)
    nl = tricell.NeighborList(cutoff)
    expected = nl.compute_batch(x, h, pbc, "ijSdDd", batch_ptr=ptr, copy=False)
    expected = [a.copy() for a in expected]
    assert np.array_equal(expected[4], expected[6])
    kept = nl.compute_batch(x, h, pbc, "ijSdDd", batch_ptr=ptr)
    for round in range(4):
        copy = round % 2 == 0
        moved = nl.compute_batch(x + 0.5 * (round + 1), h, pbc, "ijSdDd", batch_ptr=ptr,
                                 copy=copy)
        for a in moved[1:]:
            a[...] = 0  # the caller's to change
        del moved  # its buffers go back to the next call
        again = nl.compute_batch(x, h, pbc, "ijSdDd", batch_ptr=ptr, copy=copy)
        assert all(np.array_equal(a, b) for a, b in zip(again, expected)), round
    assert all(np.array_equal(a, b) for a, b in zip(kept, expected))
    kept[4][...] = -1.0
    assert not np.shares_memory(kept[4], kept[6]) and np.array_equal(kept[6], expected[6])


def test_concatenated_errors_name_the_argument_and_the_structure():
    rng = np.random.default_rng(0)
    x = rng.random((40, 3)) * 3
    ptr = np.arange(0, 41, 2)  # 20 structures of 2 atoms
    h = np.array([np.eye(3) * 3] * 20)
    nl = tricell.NeighborList(2.0)
    call = lambda **changes: nl.compute_batch(  # noqa: E731
        **{"points": x, "boxes": h, "periodic": True, "quantities": "ij", "batch_ptr": ptr,
           **changes})
    with pytest.raises(ValueError, match=r"^batch_ptr must start at 0 \(got batch_ptr\[0\] = 1\)$"):
        call(batch_ptr=np.concatenate([[1], ptr[1:]]))
    bad = ptr.copy()
    bad[5] = 3
    with pytest.raises(ValueError, match=r"^batch_ptr must not decrease \(got batch_ptr\[4\] = 8 > "
                                         r"batch_ptr\[5\] = 3: structure 4 would have -5 atoms\)$"):
        call(batch_ptr=bad)
    with pytest.raises(ValueError, match=r"^batch_ptr must end at the number of points, 40 \(got "
                                         r"batch_ptr\[20\] = 38\)$"):
        call(batch_ptr=np.concatenate([ptr[:-1], [38]]))
    with pytest.raises(ValueError, match=r"^batch_ptr must have B \+ 1 entries"):
        call(batch_ptr=[])
    with pytest.raises(TypeError, match=r"^batch_ptr must be integers, not float"):
        call(batch_ptr=ptr.astype(float))
    with pytest.raises(ValueError, match=r"^boxes must have shape \(20, 3, 3\): one box per "
                                         r"structure of batch_ptr.*\(got shape \(19, 3, 3\)\)$"):
        call(boxes=h[:19])
    with pytest.raises(ValueError, match=r"^periodic must be one bool, three, or one row of three "
                                         r"per structure, shape \(20, 3\) \(got shape \(2, 3\)\)$"):
        call(periodic=[[True] * 3] * 2)
    with pytest.raises(ValueError, match=r"^points must be an array of shape \(N, 3\)"):
        call(points=x[:, :2])
    singular = h.copy()
    singular[17] = [[3, 0, 0], [6, 0, 0], [0, 0, 3]]
    with pytest.raises(ValueError, match=r"^structure 17, boxes\[17\]: "):
        call(boxes=singular)
    nan = x.copy()
    nan[7, 2] = np.nan
    with pytest.raises(ValueError, match=r"^structure 3, points\[6:8\]: position 1 is not finite"):
        call(points=nan)
    with pytest.raises(ValueError, match=r"max_pairs"):
        tricell.NeighborList(2.0, max_pairs=3).compute_batch(x, h, True, "ij", batch_ptr=ptr)
