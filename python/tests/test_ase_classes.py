"""tricell.ase's NeighborList, PrimitiveNeighborList and NewPrimitiveNeighborList against ASE's
own classes in the same process: builds over seeded random systems (every periodicity,
skewed cells, per-atom cutoffs, every combination of bothways, self_interaction and sorted),
trajectories of updates (rebuild decisions against an independent brute-force check of the
rule, completeness against a fresh brute-force pair list, equality with ASE after each
rebuild), connectivity matrices, errors, ASE's calculators and ASE's own test files run
with tricell's classes."""
import importlib.util
import itertools
import os
import re

import numpy as np
import pytest
from ase import Atoms
from ase import neighborlist as ase_nl

import tricell.ase
from conftest import ALL_PBC, random_cell

SEEDS = range(48)  # 6 per periodicity
FLAGS = list(itertools.product([False, True], repeat=3))  # bothways, self_interaction, sorted
CLASSES = [("Primitive", tricell.ase.PrimitiveNeighborList, ase_nl.PrimitiveNeighborList),
           ("NewPrimitive", tricell.ase.NewPrimitiveNeighborList,
            ase_nl.NewPrimitiveNeighborList)]
ASE_TEST_DIR = os.path.join(os.path.dirname(ase_nl.__file__), "test", "neighbor")
ASE_TEST_FILES = ["test_neighbor.py", "test_neighbor_initialization.py"]


def system(seed, atoms=None):
    """(pbc, cell, positions, cutoffs, skin) of one seed: a random or skewed cell, some atoms
    several cells away, radii spread over a factor of four."""
    rng = np.random.default_rng(seed)
    cell = random_cell(rng, ["triclinic", "skewed"][seed % 2])
    pbc = ALL_PBC[seed % 8]
    n = atoms if atoms is not None else int(rng.integers(1, 16))
    fractional = rng.uniform(0, 1, (n, 3))
    far = rng.random(n) < 0.2
    fractional[far] += rng.integers(-3, 4, (int(far.sum()), 3))
    widths = 1.0 / np.linalg.norm(np.linalg.inv(cell), axis=0)
    cutoffs = rng.uniform(0.1, 0.4, n) * widths.min() * rng.uniform(0.5, 2.0)
    skin = float(rng.choice([0.0, 0.05, 0.2]))
    return pbc, cell, fractional @ cell, cutoffs, skin


def lists(nl, n):
    """Per atom, the sorted list of (index, offset) tuples of nl.get_neighbors(a)."""
    out = []
    for a in range(n):
        indices, offsets = nl.get_neighbors(a)
        out.append(sorted(zip(indices.tolist(), map(tuple, offsets.tolist()))))
    return out


def sets(nl, n):
    return [sorted(set(entries)) for entries in lists(nl, n)]


def check_types(nl, n, context):
    for a in range(n):
        indices, offsets = nl.get_neighbors(a)
        assert indices.dtype == np.int64 and indices.ndim == 1, context
        assert offsets.dtype == np.int64 and offsets.shape == (len(indices), 3), context


def brute_force_pairs(pbc, cell, positions, radii):
    """Every (i, j, S) with |positions[j] + S @ cell - positions[i]| < r_i + r_j, except
    (i, i, 0), by trying every shift up to the reach of the largest pair cutoff."""
    reach = 2 * radii.max() if len(radii) else 0
    widths = 1.0 / np.linalg.norm(np.linalg.inv(cell), axis=0)
    # Positions may lie several cells away: reach over their spread too.
    spread = np.abs(positions @ np.linalg.inv(cell)).max() if len(positions) else 0
    bounds = [int(np.ceil(reach / widths[k] + 2 * spread)) + 1 if pbc[k] else 0
              for k in range(3)]
    shifts = np.array(list(itertools.product(*[range(-b, b + 1) for b in bounds])))
    found = set()
    for i in range(len(positions)):
        vectors = (positions[None, :, :] + (shifts @ cell)[:, None, :]) - positions[i]
        d = np.linalg.norm(vectors, axis=2)
        hit = d < radii[i] + radii[None, :]
        for s, j in zip(*np.nonzero(hit)):
            if j == i and not shifts[s].any():
                continue
            found.add((i, int(j), tuple(int(v) for v in shifts[s])))
    return found


def contains_pairs(nl, n, pairs, bothways, context):
    """Every pair of `pairs` (a full list) is in nl's list: at i, or (without bothways) at j
    with the opposite offset."""
    listed = [set(entries) for entries in lists(nl, n)]
    for i, j, s in pairs:
        back = tuple(-v for v in s)
        here = (j, s) in listed[i]
        there = (i, back) in listed[j]
        assert (here and there) if bothways else (here or there), (
            f"{context}: pair {(i, j, s)} within the cutoffs is missing")


# -- builds --------------------------------------------------------------------------------------


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("name, mine_class, ase_class", CLASSES, ids=[c[0] for c in CLASSES])
def test_build_matches_ase(seed, name, mine_class, ase_class):
    pbc, cell, positions, cutoffs, skin = system(seed)
    n = len(positions)
    for bothways, self_interaction, sorted_ in FLAGS:
        context = (f"seed {seed}, {name}, pbc {pbc}, bothways {bothways}, self "
                   f"{self_interaction}, sorted {sorted_}")
        kwargs = dict(skin=skin, sorted=sorted_, self_interaction=self_interaction,
                      bothways=bothways)
        mine = mine_class(cutoffs, **kwargs)
        theirs = ase_class(cutoffs, **kwargs)
        assert mine.update(pbc, cell, positions) and theirs.update(pbc, cell, positions)
        check_types(mine, n, context)
        # tricell lists each pair once; ASE's sets (its old class repeats some pairs).
        assert lists(mine, n) == sets(mine, n), f"{context}: a pair listed twice"
        if name == "NewPrimitive" and sorted_:
            # ASE's sort key i * pairs + j is an order by (i, j) only when every j < pairs.
            unsorted = ase_class(cutoffs, **dict(kwargs, sorted=False))
            unsorted.update(pbc, cell, positions)
            assert sets(mine, n) == sets(unsorted, n), context
            if len(theirs.pair_second) > n:
                for a in range(n):
                    np.testing.assert_array_equal(
                        mine.get_neighbors(a)[0], theirs.get_neighbors(a)[0],
                        err_msg=f"{context}: order of atom {a}")
        else:
            assert sets(mine, n) == sets(theirs, n), context
        if sorted_:
            for a in range(n):
                indices, offsets = mine.get_neighbors(a)
                keys = [(int(j), tuple(s)) for j, s in zip(indices, offsets.tolist())]
                assert keys == sorted(keys), f"{context}: atom {a} not sorted"
        if name == "Primitive":
            assert (mine.nneighbors, mine.npbcneighbors) == (
                theirs.nneighbors, theirs.npbcneighbors), context


@pytest.mark.parametrize("seed", SEEDS[:16])
@pytest.mark.parametrize("primitive", ["Primitive", "NewPrimitive"])
def test_neighbor_list_class_matches_ase(seed, primitive):
    pbc, cell, positions, cutoffs, skin = system(seed)
    atoms = Atoms(numbers=np.ones(len(positions), int), positions=positions, cell=cell, pbc=pbc)
    mine_primitive = getattr(tricell.ase, primitive + "NeighborList")
    ase_primitive = getattr(ase_nl, primitive + "NeighborList")
    for bothways, self_interaction, sorted_ in FLAGS:
        context = f"seed {seed}, {primitive}, {bothways}, {self_interaction}, {sorted_}"
        kwargs = dict(skin=skin, sorted=sorted_, self_interaction=self_interaction,
                      bothways=bothways)
        mine = tricell.ase.NeighborList(cutoffs, primitive=mine_primitive, **kwargs)
        theirs = ase_nl.NeighborList(cutoffs, primitive=ase_primitive, **kwargs)
        assert mine.update(atoms) and theirs.update(atoms)
        assert isinstance(mine.nl, mine_primitive)
        np.testing.assert_allclose(mine.nl.cutoffs, theirs.nl.cutoffs)
        assert mine.nl.skin == theirs.nl.skin
        if not (primitive == "NewPrimitive" and sorted_):
            assert sets(mine, len(atoms)) == sets(theirs, len(atoms)), context
        assert mine.nupdates == theirs.nupdates == 1
        dense = mine.get_connectivity_matrix(sparse=False)
        sparse = mine.get_connectivity_matrix(sparse=True)
        expected = theirs.get_connectivity_matrix(sparse=False)
        # (ASE's sorted new class misgroups its pairs when some j >= the pair count.)
        if not (primitive == "NewPrimitive" and sorted_
                and len(theirs.nl.pair_second) <= len(atoms)):
            np.testing.assert_array_equal(dense, expected, err_msg=context)
        assert dense.dtype == np.int8 and sparse.dtype == np.int8
        assert type(sparse) is type(theirs.get_connectivity_matrix(sparse=True))
        np.testing.assert_array_equal(sparse.toarray(), dense, err_msg=context)


@pytest.mark.parametrize("seed", range(16))
@pytest.mark.parametrize("name, mine_class, ase_class", CLASSES, ids=[c[0] for c in CLASSES])
def test_zero_cell_rows_on_open_axes(seed, name, mine_class, ase_class):
    """A cell with zero rows along open axes is completed, as ASE's NeighborList completes it
    before calling a primitive class: the pairs are the brute-force ones and ASE's class's
    given the completed cell (ASE's new class given the zero rows misses some)."""
    from ase.geometry import complete_cell

    rng = np.random.default_rng(3000 + seed)
    pbc = ALL_PBC[seed % 7]  # not all periodic
    cell = np.eye(3) * rng.uniform(1.5, 3.0) + rng.normal(0, 0.4, (3, 3))
    cell[~np.array(pbc)] = 0
    n = int(rng.integers(1, 7))
    positions = rng.uniform(0, 1, (n, 3)) @ complete_cell(cell)
    cutoffs = rng.uniform(0.3, 1.5, n)
    mine = mine_class(cutoffs, skin=0.0, bothways=True, self_interaction=False)
    mine.update(pbc, cell, positions)
    found = {(a, j, tuple(s)) for a in range(n)
             for j, s in zip(*[c.tolist() for c in mine.get_neighbors(a)])}
    assert found == brute_force_pairs(pbc, complete_cell(cell), positions, cutoffs)
    theirs = ase_class(cutoffs, skin=0.0, bothways=True, self_interaction=False)
    theirs.update(pbc, complete_cell(cell), positions)
    assert sets(mine, n) == sets(theirs, n)


def test_ase_classes_given_as_primitive_are_replaced():
    nl = tricell.ase.NeighborList([1.0], primitive=ase_nl.NewPrimitiveNeighborList)
    assert isinstance(nl.nl, tricell.ase.NewPrimitiveNeighborList)
    nl = tricell.ase.NeighborList([1.0], primitive=ase_nl.PrimitiveNeighborList)
    assert isinstance(nl.nl, tricell.ase.PrimitiveNeighborList)
    assert isinstance(tricell.ase.NeighborList([1.0]).nl, tricell.ase.PrimitiveNeighborList)


@pytest.mark.parametrize("name, mine_class, ase_class", CLASSES, ids=[c[0] for c in CLASSES])
def test_scaled_positions_and_empty_lists(name, mine_class, ase_class):
    pbc, cell, positions, cutoffs, skin = system(3, atoms=9)
    fractional = positions @ np.linalg.inv(cell)
    mine = mine_class(cutoffs, skin=skin, use_scaled_positions=True)
    theirs = ase_class(cutoffs, skin=skin, use_scaled_positions=True)
    mine.update(pbc, cell, fractional)
    theirs.update(pbc, cell, fractional)
    assert sets(mine, 9) == sets(theirs, 9)
    # No atoms; one atom with nothing near.
    empty = mine_class([])
    assert empty.update([True] * 3, np.eye(3) * 7.56, np.zeros((0, 3)))
    lonely = mine_class([0.1], self_interaction=False)
    lonely.update(True, np.eye(3) * 5, [[1.0, 2.0, 3.0]])
    indices, offsets = lonely.get_neighbors(0)
    assert indices.shape == (0,) and offsets.shape == (0, 3)
    assert indices.dtype == np.int64 and offsets.dtype == np.int64


# -- updates -------------------------------------------------------------------------------------


def min_image_displacement(build_cell, build_fractional, cell, positions, pbc):
    """Largest displacement since the build, each the shortest over lattice jumps (tried up
    to 3 along periodic axes) of build_cell @ (s + m - s0): an independent check of the rule's
    measure."""
    u = positions @ np.linalg.inv(cell) - build_fractional
    u[:, np.asarray(pbc)] -= np.rint(u[:, np.asarray(pbc)])
    ranges = [range(-3, 4) if p else [0] for p in pbc]
    jumps = np.array(list(itertools.product(*ranges)))
    best = np.full(len(u), np.inf)
    for m in jumps:
        best = np.minimum(best, np.linalg.norm((u + m) @ build_cell, axis=1))
    return best.max() if len(best) else 0.0


def strain(build_cell, cell):
    """eps = max(0, ||H0 H^-1|| - 1), rows as lattice vectors (the transpose of the library's
    columns; the spectral norm is the same)."""
    return max(0.0, np.linalg.norm(np.linalg.inv(cell) @ build_cell, 2) - 1)


@pytest.mark.parametrize("seed", range(32))
@pytest.mark.parametrize("name, mine_class, ase_class", CLASSES, ids=[c[0] for c in CLASSES])
def test_trajectory_rebuilds_and_completeness(seed, name, mine_class, ase_class):
    rng = np.random.default_rng(1000 + seed)
    pbc, cell, positions, cutoffs, _ = system(seed, atoms=int(rng.integers(4, 12)))
    skin = float(rng.uniform(0.05, 0.3))
    n = len(positions)
    bothways, self_interaction, sorted_ = FLAGS[seed % 8]
    kwargs = dict(skin=skin, sorted=sorted_, self_interaction=self_interaction,
                  bothways=bothways)
    mine = mine_class(cutoffs, **kwargs)
    builds = 0
    build = None
    for step in range(25):
        kind = rng.choice(["small", "large", "wrap", "lattice", "strain", "none"],
                          p=[0.4, 0.15, 0.1, 0.1, 0.15, 0.1])
        if step > 0:
            if kind == "small":
                positions = positions + rng.normal(0, 0.2 * skin, positions.shape)
            elif kind == "large":
                positions = positions.copy()
                positions[rng.integers(n)] += rng.normal(0, 2 * skin, 3)
            elif kind == "wrap":
                fractional = positions @ np.linalg.inv(cell)
                fractional[:, list(pbc)] %= 1.0
                positions = fractional @ cell
            elif kind == "lattice":
                positions = positions.copy()
                positions[rng.integers(n)] += rng.integers(-2, 3, 3) * np.array(pbc) @ cell
            elif kind == "strain":
                deformation = np.eye(3) + rng.normal(0, 0.01, (3, 3))
                fractional = positions @ np.linalg.inv(cell)
                cell = cell @ deformation
                positions = fractional @ cell  # atoms move with the cell
        context = f"seed {seed}, {name}, step {step} ({kind}), flags {kwargs}"
        rebuilt = mine.update(pbc, cell, positions)
        if build is not None:
            # The rule, checked independently: a rebuild exactly when some atom moved more
            # than skin - eps * max(r) (away from the threshold, where rounding decides).
            build_cell, build_fractional = build
            moved = min_image_displacement(build_cell, build_fractional, cell, positions, pbc)
            budget = skin - strain(build_cell, cell) * cutoffs.max()
            if abs(moved - budget) > 1e-9:
                assert rebuilt == (moved > budget), (
                    f"{context}: moved {moved}, budget {budget}, rebuilt {rebuilt}")
        if rebuilt:
            builds += 1
            build = (cell.copy(), positions @ np.linalg.inv(cell))
            theirs = ase_class(cutoffs, **kwargs)
            theirs.update(pbc, cell, positions)
            if not (name == "NewPrimitive" and sorted_):
                assert sets(mine, n) == sets(theirs, n), f"{context}: differs from ASE"
        assert mine.nupdates == builds, context
        # Complete: every pair within the real cutoffs, with offsets relative to the
        # positions as given (wrapped or not).
        # (ASE's PrimitiveNeighborList with sorted=True lists a pair of two atoms at the lower
        # index only, bothways or not.)
        both = bothways and not (name == "Primitive" and sorted_)
        contains_pairs(mine, n, brute_force_pairs(pbc, cell, positions, cutoffs), both,
                       context)
        # And nothing far beyond the candidates' radius: a wrongly moved offset would be
        # a lattice vector away.
        for a in range(n):
            indices, offsets = mine.get_neighbors(a)
            d = np.linalg.norm(positions[indices] + offsets @ cell - positions[a], axis=1)
            limit = cutoffs[a] + cutoffs[indices] + 4 * skin + 0.1
            assert np.all(d < limit), f"{context}: atom {a} has a neighbour at {d.max()}"
    assert builds >= 1


@pytest.mark.parametrize("seed", range(16))
@pytest.mark.parametrize("primitive", ["Primitive", "NewPrimitive"])
def test_same_rebuilds_as_ase_in_a_fixed_cell(seed, primitive):
    """Fixed cell, atoms never wrapped: tricell rebuilds at the same steps as ASE."""
    rng = np.random.default_rng(2000 + seed)
    pbc, cell, positions, cutoffs, _ = system(seed, atoms=8)
    atoms = Atoms(numbers=np.ones(8, int), positions=positions, cell=cell, pbc=pbc)
    skin = 0.1
    mine = tricell.ase.NeighborList(cutoffs, skin=skin,
                                    primitive=getattr(tricell.ase, primitive + "NeighborList"))
    theirs = ase_nl.NeighborList(cutoffs, skin=skin,
                                 primitive=getattr(ase_nl, primitive + "NeighborList"))
    decisions = []
    for step in range(40):
        atoms.positions += rng.normal(0, 0.02, atoms.positions.shape)
        decision = mine.update(atoms)
        assert decision == theirs.update(atoms), f"seed {seed}, step {step}"
        decisions.append(decision)
    assert mine.nupdates == theirs.nupdates == sum(decisions)
    assert 1 < mine.nupdates < 40  # the trajectory really exercised both outcomes


def test_changes_that_rebuild():
    pbc, cell, positions, cutoffs, skin = system(5, atoms=6)
    nl = tricell.ase.NewPrimitiveNeighborList(cutoffs, skin=0.2)
    numbers = np.arange(1, 7)
    assert nl.update(pbc, cell, positions, numbers)
    assert not nl.update(pbc, cell, positions, numbers)
    assert nl.update(pbc, cell, positions, numbers[::-1])  # numbers changed
    assert nl.update(tuple(not p for p in pbc), cell, positions, numbers[::-1])  # pbc changed
    assert nl.update(tuple(not p for p in pbc), cell * 1.5, positions * 0.9, numbers[::-1])
    assert nl.nupdates == 4
    nl.build(pbc, cell, positions)
    assert nl.nupdates == 5


def test_connectivity_before_update_and_counts():
    nl = tricell.ase.NeighborList([1.0, 1.0], skin=0, self_interaction=False)
    with pytest.raises(RuntimeError, match="Must call update"):
        nl.get_neighbors(0)
    with pytest.raises(RuntimeError, match="Must call update"):
        nl.get_connectivity_matrix()
    atoms = Atoms("H2", positions=[[0, 0, 0], [0, 0, 1.5]])
    assert nl.update(atoms) and not nl.update(atoms)
    np.testing.assert_array_equal(nl.get_connectivity_matrix(sparse=False), [[0, 1], [0, 0]])
    assert nl.nupdates == 1 and nl.nneighbors == 1 and nl.npbcneighbors == 0


# -- errors --------------------------------------------------------------------------------------


def test_errors_name_the_argument():
    with pytest.raises(ValueError, match=r"cutoffs has 2 radii for 3 atoms \(positions\)"):
        tricell.ase.PrimitiveNeighborList([1.0, 1.0]).update(True, np.eye(3) * 4, np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"cutoffs has 1 radii for 2 atoms"):
        tricell.ase.NeighborList([1.0]).update(Atoms("H2", positions=[[0, 0, 0], [0, 0, 1]]))
    with pytest.raises(ValueError, match=r"cutoffs must be one radius per atom.*shape \(2, 2\)"):
        tricell.ase.NewPrimitiveNeighborList([[1.0, 1.0], [1.0, 1.0]])
    with pytest.raises(ValueError, match=r"cutoffs\[1\] must be finite \(got nan\)"):
        tricell.ase.NewPrimitiveNeighborList([1.0, np.nan])
    with pytest.raises(ValueError, match=r"cutoffs must be a sequence of numbers"):
        tricell.ase.NewPrimitiveNeighborList(["a", 1.0])
    with pytest.raises(ValueError, match=r"skin must be finite and >= 0 \(got -0.1\)"):
        tricell.ase.NeighborList([1.0], skin=-0.1)
    with pytest.raises(ValueError, match=r"cutoffs\[0\] \+ skin must be >= 0"):
        tricell.ase.PrimitiveNeighborList([-1.0], skin=0.3)
    nl = tricell.ase.NewPrimitiveNeighborList([1.0, 1.0])
    with pytest.raises(ValueError, match=r"cell must be 3 x 3.*shape \(2, 3\)"):
        nl.update(True, np.eye(3)[:2], np.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"positions must be N x 3 \(got shape \(2, 2\)\)"):
        nl.update(True, np.eye(3), np.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"pbc must be one bool or three \(got shape \(2,\)\)"):
        nl.update([True, False], np.eye(3), np.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"position 1 is not finite"):
        nl.update(True, np.eye(3) * 4, [[0, 0, 0], [np.nan, 0, 0]])
    nl.update(True, np.eye(3) * 4, np.zeros((2, 3)))
    with pytest.raises(IndexError, match=r"atom index 2 is out of range for 2 atoms \(a\)"):
        nl.get_neighbors(2)


def test_tracker_arguments_and_rule():
    with pytest.raises(ValueError, match=r"skin must be finite and >= 0"):
        tricell.DisplacementTracker(-1.0, 1.0)
    with pytest.raises(ValueError, match=r"cutoff must be finite and >= 0"):
        tricell.DisplacementTracker(1.0, float("inf"))
    tracker = tricell.DisplacementTracker(0.4, 2.0)
    box = np.eye(3) * 5
    x = np.array([[0.1, 0.2, 0.3], [4.9, 4.9, 4.9]])
    assert tracker.needs_rebuild(x, box) and tracker.jumps(x, box) is None
    tracker.record(x, box)
    assert tracker.budget(box) == pytest.approx(0.2)
    assert not tracker.needs_rebuild(x + [0.19, 0, 0], box)
    assert tracker.needs_rebuild(x + [0.21, 0, 0], box)
    # Wrapping is no motion; the jumps say which lattice vector each atom crossed.
    wrapped = x + [[0, 0, 0], [-5.0, 0, 5.0]]
    assert tracker.max_displacement(wrapped, box) == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_array_equal(tracker.jumps(wrapped, box), [[0, 0, 0], [1, 0, -1]])
    # A 1% larger box keeps the budget; a 1% smaller one shrinks it by eps * cutoff / 2.
    assert tracker.budget(box * 1.01) == pytest.approx(0.2)
    eps = 1 / 0.99 - 1
    assert tracker.budget(box * 0.99) == pytest.approx(0.5 * (0.4 - eps * 2.0))
    assert tracker.needs_rebuild(x, box, [True, True, False])


@pytest.mark.parametrize("calculator", ["lj", "emt"])
def test_ase_calculators_with_tricell_classes(calculator, monkeypatch):
    """ASE's LJ and EMT calculators, whose modules bind ase.neighborlist.NeighborList, give
    the same energies, forces and stress along an MD-like trajectory with tricell's class."""
    import importlib

    from ase.build import bulk

    module = importlib.import_module("ase.calculators." + calculator)
    rng = np.random.default_rng(7)
    atoms = bulk("Cu", "fcc", a=3.6, cubic=True) * (2, 2, 2)
    atoms.rattle(0.05, seed=3)
    results = {}
    for which in ["ase", "tricell"]:
        if which == "tricell":
            monkeypatch.setattr(module, "NeighborList", tricell.ase.NeighborList)
        calc = module.LennardJones(sigma=2.3, rc=5.0) if calculator == "lj" else module.EMT()
        trajectory = atoms.copy()
        trajectory.calc = calc
        values = []
        for step in range(12):
            trajectory.positions += rng.normal(0, 0.03, trajectory.positions.shape)
            if step == 6:
                trajectory.set_cell(trajectory.cell * 1.01, scale_atoms=True)
            values.append((trajectory.get_potential_energy(), trajectory.get_forces(),
                           trajectory.get_stress()))
        assert isinstance(calc.nl, tricell.ase.NeighborList) == (which == "tricell")
        results[which] = values
        rng = np.random.default_rng(7)
    for (e0, f0, s0), (e1, f1, s1) in zip(results["ase"], results["tricell"]):
        assert e1 == pytest.approx(e0, rel=1e-10, abs=1e-10)
        np.testing.assert_allclose(f1, f0, rtol=1e-9, atol=1e-10)
        np.testing.assert_allclose(s1, s0, rtol=1e-9, atol=1e-10)


# -- ASE's own tests -----------------------------------------------------------------------------


def counting(cls, counts):
    """A subclass of cls that counts its constructions in counts[cls.__name__]."""

    def __init__(self, *args, **kwargs):
        counts[cls.__name__] += 1
        cls.__init__(self, *args, **kwargs)

    return type(cls.__name__, (cls,), {"__init__": __init__, "__doc__": cls.__doc__})


def ase_tests():
    """(file, test function) of ASE's test files of its neighbour-list classes."""
    found = []
    for name in ASE_TEST_FILES:
        with open(os.path.join(ASE_TEST_DIR, name)) as f:
            found += [(name, test) for test in re.findall(r"^def (test_\w+)", f.read(), re.M)]
    return found


@pytest.mark.filterwarnings("ignore::pytest.PytestUnknownMarkWarning")  # its mark "slow"
@pytest.mark.filterwarnings("ignore:the matrix subclass")
@pytest.mark.parametrize("file_name, test_name", ase_tests())
def test_ase_test_files_with_tricell_classes(file_name, test_name, monkeypatch):
    """Each test function of ASE's test files, run with ase.neighborlist's classes replaced
    by tricell's (counted, so that a test that built none fails)."""
    counts = {"NeighborList": 0, "PrimitiveNeighborList": 0, "NewPrimitiveNeighborList": 0}
    patched = {name: counting(getattr(tricell.ase, name), counts) for name in counts}
    for name, cls in patched.items():
        monkeypatch.setattr(ase_nl, name, cls)
    # The files import the classes by name from ase.neighborlist, so they bind the patched ones.
    spec = importlib.util.spec_from_file_location("_ase_" + test_name,
                                                  os.path.join(ASE_TEST_DIR, file_name))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    for name, cls in patched.items():
        assert getattr(module, name, cls) is cls
    np.random.seed(42)  # test_supercell draws from numpy's global generator
    getattr(module, test_name)()
    assert sum(counts.values()) > 0, f"{test_name} built no tricell list: {counts}"
