"""tricell.vesin: vesin's interface over tricell. The pairs against the native module and a
brute force over lattice images (full and half, sorted, every algorithm name, float32 and
integer inputs), the Verlet list (skin) over seeded trajectories with a deforming box against a
direct call at every step, ase_neighbor_list against ASE, vesin's output types and the errors
(vesin's types, a message naming the value). test_vesin_torch.py has the torch parts.

vesin's own test files run against this front too (with their import redirected; outside the
repository): docs/python.md says which pass."""
import numpy as np
import pytest
from ase import Atoms
from ase.neighborlist import neighbor_list as ase_neighbor_list

import tricell
import tricell.vesin as vesin
from conftest import ALL_PBC, brute_force_pairs, random_system, sort_pairs


def pair_set(i, j, S):
    return set(zip(np.asarray(i).tolist(), np.asarray(j).tolist(),
                   map(tuple, np.asarray(S).tolist())))


@pytest.mark.parametrize("seed", range(48))
def test_pairs_equal_the_native_module_and_a_brute_force(seed):
    cell, positions, pbc, cutoff, _ = random_system(seed, far=3)
    rng = np.random.default_rng(seed)
    full, sorted_ = bool(rng.integers(2)), bool(rng.integers(2))
    algorithm = ["auto", "cell_list", "brute_force"][seed % 3]
    nl = vesin.NeighborList(cutoff, full_list=full, sorted=sorted_, algorithm=algorithm)
    i, j, S, d, D, P = nl.compute(positions, cell, pbc, "ijSdDP")
    assert [a.dtype for a in (i, j, S, d, D, P)] == [np.uint64, np.uint64, np.int32, np.float64,
                                                     np.float64, np.uint64]
    assert np.array_equal(P, np.stack([i, j], axis=1))
    native = tricell.NeighborList(cutoff, full=full).compute(positions, cell, pbc, "ijSdD")
    mine = sort_pairs(i.astype(np.int64), j.astype(np.int64), S, d, D)
    theirs = sort_pairs(*native)
    for k, name in enumerate("ijSdD"):
        assert np.array_equal(mine[k], theirs[k]), f"seed {seed}: {name}"
    if full:
        assert pair_set(i, j, S) == brute_force_pairs(positions, cell, pbc, cutoff), f"seed {seed}"
    if sorted_:
        assert np.all(np.diff(i.astype(np.int64)) >= 0), f"seed {seed}: not sorted by i"


def test_output_types_follow_vesin():
    cell, positions, pbc, cutoff, _ = random_system(4, pbc=(True, True, True))
    nl = vesin.NeighborList(cutoff, full_list=True)
    (i,) = nl.compute(positions, cell, pbc, "i")  # a tuple, also for one letter
    assert i.dtype == np.uint64
    D, d = nl.compute(positions.astype(np.float32), cell.astype(np.float32), pbc, "Dd")
    assert D.dtype == np.float32 and d.dtype == np.float32
    D, d = nl.compute(np.rint(positions).astype(np.int64), np.rint(cell * 3).astype(np.int64),
                      pbc, "Dd")
    assert D.dtype == np.float64 and d.dtype == np.float64
    assert nl.compute(positions, cell, pbc, "") == ()
    empty = vesin.NeighborList(1e-3, full_list=True).compute([[0.0, 0, 0], [1, 0, 0]],
                                                             np.eye(3) * 5, False, "ijSDd")
    assert [a.shape for a in empty] == [(0,), (0,), (0, 3), (0, 3), (0,)]
    views = nl.compute(positions, cell, pbc, "Sd", copy=False)
    assert all(np.array_equal(a, b) for a, b in zip(views, nl.compute(positions, cell, pbc, "Sd")))


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("full", [True, False])
def test_verlet_list_over_a_trajectory_with_a_deforming_box(seed, full):
    rng = np.random.default_rng(100 + seed)
    pbc = ALL_PBC[seed]
    cell, positions, _, _, _ = random_system(200 + seed, pbc=pbc, kind="triclinic", atoms=30)
    cutoff = 0.4 * min(1.0 / np.linalg.norm(np.linalg.inv(cell), axis=0)) + 1.0
    direct = vesin.NeighborList(cutoff, full_list=full)
    verlet = vesin.NeighborList(cutoff, full_list=full, skin=0.5)
    for step in range(40):
        positions = positions + rng.normal(0, 0.05, positions.shape)
        box = cell + rng.normal(0, 0.05, (3, 3))
        expected = direct.compute(positions, box, pbc, "ijS")
        got = verlet.compute(positions, box, pbc, "ijS")
        if full:
            assert pair_set(*got) == pair_set(*expected), f"seed {seed} step {step}"
        else:  # each pair once, oriented as the Verlet list keeps it
            canonical = lambda i, j, S: {  # noqa: E731
                min((a, b, s), (b, a, tuple(-v for v in s))) for a, b, s in pair_set(i, j, S)}
            assert canonical(*got) == canonical(*expected), f"seed {seed} step {step}"
            assert len(got[0]) == len(expected[0])


@pytest.mark.parametrize("seed", range(12))
def test_ase_neighbor_list_equals_ase(seed):
    cell, positions, pbc, cutoff, _ = random_system(seed, far=2)
    atoms = Atoms(positions=positions, cell=cell, pbc=pbc)
    i, j, S, d = vesin.ase_neighbor_list("ijSd", atoms, cutoff)
    assert i.dtype == np.uint64 and np.all(np.diff(i.astype(np.int64)) >= 0)
    theirs = ase_neighbor_list("ijSd", atoms, cutoff)
    near = lambda d: np.abs(d - cutoff) < 1e-9  # noqa: E731
    assert pair_set(*(a[~near(d)] for a in (i, j, S))) == \
        pair_set(*(a[~near(theirs[3])] for a in theirs[:3])), f"seed {seed}"
    assert vesin.ase_neighbor_list("ij", atoms, 2)[0].dtype == np.uint64  # an integer cutoff


def test_errors_have_vesins_types_and_name_the_value():
    points, box = np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.5]]), np.eye(3)
    for cutoff, shown in ((0.0, "0"), (-12.0, "-12"), (float("inf"), "inf"),
                          (float("nan"), "nan")):
        nl = vesin.NeighborList(cutoff, full_list=True)  # refused when computing, as vesin does
        with pytest.raises(RuntimeError, match=rf"cutoff must be .*\(got {shown}\)"):
            nl.compute(points, box, True, "ij")
    nl = vesin.NeighborList(1.2, full_list=True)
    with pytest.raises(RuntimeError, match=r"lattice vector a is zero but axis a is periodic"):
        nl.compute(points, np.zeros((3, 3)), True, "ij")
    with pytest.raises(RuntimeError, match=r"position 1 is not finite"):
        nl.compute([[0.0, 0, 0], [np.nan, 0, 0]], box, True, "ij")
    with pytest.raises(ValueError, match=r"`box` must be a 3x3 matrix"):
        nl.compute(points, np.eye(2), True, "ij")
    with pytest.raises(ValueError, match=r"`points` must be a nx3 array"):
        nl.compute(points[:, :2], box, True, "ij")
    with pytest.raises(ValueError, match=r"`periodic` must be a single boolean or a sequence of "
                                         r"three booleans"):
        nl.compute(points, box, [True, False], "ij")
    with pytest.raises(RuntimeError, match=r"`points` and `box` must have the same dtype, got "
                                           r"float32 and float64"):
        nl.compute(points.astype(np.float32), box, True, "ij")
    with pytest.raises(ValueError, match=r"unexpected character in `quantities`: x"):
        nl.compute(points, box, True, "ijx")
    with pytest.raises(TypeError, match=r"points must hold real numbers"):
        nl.compute(points.astype(complex), box.astype(complex), True, "ij")
    with pytest.raises(ValueError, match=r"n_threads must be zero or a positive integer"):
        vesin.NeighborList(1.0, full_list=True, n_threads=-1)
    with pytest.raises(ValueError, match=r"Unknown algorithm 'fast'"):
        vesin.NeighborList(1.0, full_list=True, algorithm="fast")
    atoms = Atoms("H2", positions=points)
    with pytest.raises(ValueError, match=r"self_interaction=True is not implemented"):
        vesin.ase_neighbor_list("ij", atoms, 1.0, self_interaction=True)
    with pytest.raises(ValueError, match=r"only a single float cutoff is supported"):
        vesin.ase_neighbor_list("ij", atoms, {(1, 1): 1.0})
    with pytest.raises(TypeError, match=r"`a` should be ase.Atoms"):
        vesin.ase_neighbor_list("ij", points, 1.0)

