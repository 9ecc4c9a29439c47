"""tricell.ase against ASE's own neighbor_list, primitive_neighbor_list and first_neighbors,
in the same process, over seeded random systems."""
import numpy as np
import pytest
from ase import Atoms
from ase import neighborlist as ase_nl

import tricell.ase
from conftest import ALL_PBC, assert_same_pairs, drop_near, random_system, sort_pairs

SEEDS = range(96)  # 12 per periodicity combination, cycling through the cell kinds


def atoms_for(seed, **kwargs):
    cell, positions, pbc, cutoff, numbers = random_system(seed, **kwargs)
    return Atoms(numbers=numbers, positions=positions, cell=cell, pbc=pbc), cutoff


def both(quantities, atoms, cutoff, **kwargs):
    return (tricell.ase.neighbor_list(quantities, atoms, cutoff, **kwargs),
            ase_nl.neighbor_list(quantities, atoms, cutoff, **kwargs))


@pytest.mark.parametrize("seed", SEEDS)
def test_neighbor_list_matches_ase(seed):
    atoms, cutoff = atoms_for(seed)
    mine, theirs = both("ijSdD", atoms, cutoff)
    # Both grouped by i, each atom's pairs in its own code's order.
    assert np.all(np.diff(mine[0]) >= 0), f"seed {seed}: not grouped by i"
    assert np.all(np.diff(theirs[0]) >= 0)
    mine = sort_pairs(*mine[:3], *mine[3:])
    theirs = sort_pairs(*theirs[:3], *theirs[3:])
    mine = drop_near(cutoff, 1e-9, *mine)
    theirs = drop_near(cutoff, 1e-9, *theirs)
    assert_same_pairs(mine, theirs, f"seed {seed}, pbc {tuple(atoms.pbc)}")


@pytest.mark.parametrize("pbc", ALL_PBC)
def test_one_atom_cell_with_cutoff_beyond_the_box(pbc):
    atoms = Atoms("Si", positions=[[0.3, -7.0, 40.0]], pbc=pbc,
                  cell=[[2.0, 0.1, 0.0], [0.7, 1.9, 0.0], [-0.4, 0.3, 2.2]])
    mine, theirs = both("ijSdD", atoms, 5.5)
    assert_same_pairs(drop_near(5.5, 1e-9, *sort_pairs(*mine)),
                      drop_near(5.5, 1e-9, *sort_pairs(*theirs)), f"pbc {pbc}")
    if any(pbc):
        assert len(mine[0]) > 0


@pytest.mark.parametrize("seed", range(16))
def test_self_interaction_and_letter_order(seed):
    atoms, cutoff = atoms_for(seed)
    mine, theirs = both("DSjdi", atoms, cutoff, self_interaction=True)
    assert len(mine) == 5
    D, S, j, d, i = mine
    rD, rS, rj, rd, ri = theirs
    assert np.all(np.diff(i) >= 0), f"seed {seed}: not grouped by i"
    # Each atom's pair with itself comes first among its pairs.
    firsts = np.flatnonzero(np.r_[True, np.diff(i) > 0])
    np.testing.assert_array_equal(i[firsts], j[firsts])
    assert not S[firsts].any()
    mine = drop_near(cutoff, 1e-9, *sort_pairs(i, j, S, d, D))
    theirs = drop_near(cutoff, 1e-9, *sort_pairs(ri, rj, rS, rd, rD))
    assert_same_pairs(mine, theirs, f"seed {seed}")
    assert np.sum((i == j) & (S == 0).all(axis=1)) == len(atoms)


@pytest.mark.parametrize("seed", range(8))
def test_self_interaction_with_radii_and_dicts_follows_each_atoms_own_cutoff(seed):
    atoms, cutoff = atoms_for(seed, atoms=12)
    rng = np.random.default_rng(3000 + seed)
    radii = rng.uniform(0.1, 0.5, len(atoms)) * cutoff
    radii[::3] = 0.0  # atoms with radius 0 are not their own neighbours in ASE
    table = {("H", "H"): cutoff, ("O", "Si"): 0.8 * cutoff, ("O", "O"): 0.0}
    for c in (radii, table):
        mine, theirs = both("ijSd", atoms, c, self_interaction=True)
        assert np.all(np.diff(mine[0]) >= 0), f"seed {seed}: not grouped by i"
        keep = lambda cols: drop_near(cutoff, 1e-9, *cols)
        assert_same_pairs(keep(sort_pairs(*mine)), keep(sort_pairs(*theirs)), f"seed {seed}")


def test_dtypes_shapes_and_single_letters():
    atoms, cutoff = atoms_for(5, atoms=12)
    for q in "ijdDS":
        mine, theirs = both(q, atoms, cutoff)
        assert isinstance(mine, np.ndarray) and isinstance(theirs, np.ndarray)
        assert mine.dtype == theirs.dtype and mine.shape == theirs.shape, q
    mine, theirs = both("ijdDS", atoms, cutoff)
    assert isinstance(mine, tuple)
    assert [a.dtype for a in mine] == [a.dtype for a in theirs]


@pytest.mark.parametrize("atoms", [Atoms(), Atoms("H2", positions=[[0, 0, 0], [5, 0, 0]])])
def test_empty_results_have_ases_dtypes_and_shapes(atoms):
    mine, theirs = both("ijdDS", atoms, 1.0)
    for m, t, q in zip(mine, theirs, "ijdDS"):
        assert m.dtype == t.dtype and m.shape == t.shape, q
    assert tricell.ase.neighbor_list("D", atoms, 1.0).shape == (0, 3)


def test_cutoff_of_zero_finds_nothing_as_in_ase():
    atoms, _ = atoms_for(3, atoms=5)
    mine, theirs = both("ij", atoms, 0.0)
    assert len(mine[0]) == len(theirs[0]) == 0


@pytest.mark.parametrize("seed", range(32))
def test_per_atom_radii_match_ase(seed):
    atoms, cutoff = atoms_for(seed)
    rng = np.random.default_rng(1000 + seed)
    radii = rng.uniform(0.1, 0.6, len(atoms)) * cutoff
    mine, theirs = both("ijSdD", atoms, radii)
    i, j = theirs[0], theirs[1]
    limit = radii[i] + radii[j]
    keep = np.abs(theirs[3] - limit) >= 1e-9
    theirs = sort_pairs(*(c[keep] for c in theirs))
    limit = radii[mine[0]] + radii[mine[1]]
    keep = np.abs(mine[3] - limit) >= 1e-9
    mine = sort_pairs(*(c[keep] for c in mine))
    assert_same_pairs(mine, theirs, f"seed {seed}")


@pytest.mark.parametrize("seed", range(32))
def test_dict_cutoffs_by_symbol_and_number_match_ase(seed):
    atoms, cutoff = atoms_for(seed)
    rng = np.random.default_rng(2000 + seed)
    c = rng.uniform(0.4, 1.0, 4) * cutoff
    # Symbols and numbers mixed; O-O is absent so those pairs never count.
    table = {("H", "H"): c[0], (1, 8): c[1], ("Si", 14): c[2], (14, "O"): c[3]}
    mine, theirs = both("ijSdD", atoms, table)
    mine = sort_pairs(*mine)
    theirs = sort_pairs(*theirs)
    assert_same_pairs(mine, theirs, f"seed {seed}")
    numbers = atoms.numbers
    assert not np.any((numbers[mine[0]] == 8) & (numbers[mine[1]] == 8))


def test_a_later_key_for_the_same_elements_replaces_an_earlier_one_as_in_ase():
    atoms, _ = atoms_for(7, atoms=20)
    table = {("H", "O"): 3.0, ("O", "H"): 1.5, ("Si", "Si"): 2.0}
    mine, theirs = both("ijS", atoms, table)
    assert_same_pairs(sort_pairs(*mine), sort_pairs(*theirs), "later key wins")


@pytest.mark.parametrize("seed", range(8))
def test_primitive_neighbor_list_with_scaled_positions(seed):
    cell, positions, pbc, cutoff, numbers = random_system(seed)
    scaled = positions @ np.linalg.inv(cell)
    args = ("ijSd", pbc, cell, scaled, cutoff)
    mine = tricell.ase.primitive_neighbor_list(*args, use_scaled_positions=True)
    theirs = ase_nl.primitive_neighbor_list(*args, use_scaled_positions=True)
    assert_same_pairs(drop_near(cutoff, 1e-9, *sort_pairs(*mine)),
                      drop_near(cutoff, 1e-9, *sort_pairs(*theirs)), f"seed {seed}")


def test_molecule_without_a_cell():
    atoms = Atoms("H2O", positions=[[0, 0, 0.12], [0, 0.76, -0.47], [0, -0.76, -0.47]])
    mine, theirs = both("ijdD", atoms, 1.6)
    mine_order = np.lexsort((mine[1], mine[0]))
    order = np.lexsort((theirs[1], theirs[0]))
    for m, t in zip(mine, theirs):
        np.testing.assert_allclose(m[mine_order], t[order])


@pytest.mark.parametrize("seed", range(8))
def test_first_neighbors_matches_ase(seed):
    atoms, cutoff = atoms_for(seed)
    i = tricell.ase.neighbor_list("i", atoms, cutoff)
    mine = tricell.ase.first_neighbors(len(atoms), i)
    theirs = ase_nl.first_neighbors(len(atoms), i)
    assert mine.dtype == theirs.dtype
    np.testing.assert_array_equal(mine, theirs)


def test_errors():
    atoms, _ = atoms_for(1, atoms=4)
    with pytest.raises(ValueError, match="Unsupported quantity"):
        tricell.ase.neighbor_list("ijx", atoms, 1.0)
    with pytest.raises(ValueError, match="one value per atom"):
        tricell.ase.neighbor_list("ij", atoms, [1.0, 2.0])
    with pytest.raises(ValueError, match="numbers"):
        tricell.ase.primitive_neighbor_list("ij", atoms.pbc, atoms.cell, atoms.positions,
                                            {("H", "H"): 1.0})
    bad = atoms.positions.copy()
    bad[2, 0] = np.nan
    with pytest.raises(ValueError, match="position 2 is not finite"):
        tricell.ase.primitive_neighbor_list("ij", atoms.pbc, atoms.cell, bad, 1.0)
