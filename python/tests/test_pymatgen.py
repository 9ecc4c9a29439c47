"""tricell.pymatgen.get_neighbor_list against pymatgen's Structure.get_neighbor_list, in the
same process, over seeded random structures (pymatgen keeps d <= r + numerical_tol)."""
import numpy as np
import pytest
from pymatgen.core import Lattice, Structure

import tricell.pymatgen
from conftest import assert_same_pairs, drop_near, random_system, sort_pairs


def structure_for(seed, **kwargs):
    # pymatgen sizes its grid by the extent of the positions (22 GB for atoms 40 cells out in
    # a skewed box), so its atoms stay within two cells of the box.
    cell, positions, pbc, cutoff, numbers = random_system(seed, far=2, **kwargs)
    lattice = Lattice(cell, pbc=pbc)
    return Structure(lattice, list(numbers), positions, coords_are_cartesian=True), cutoff


def compare(structure, r, context, **kwargs):
    mine = tricell.pymatgen.get_neighbor_list(structure, r, **kwargs)
    theirs = structure.get_neighbor_list(r, **kwargs)
    assert [a.dtype for a in mine] == [a.dtype for a in theirs], context
    assert [a.shape[1:] for a in mine] == [a.shape[1:] for a in theirs], context
    # Both with images as floats; compare them as the integers they are.
    mine = drop_near(r, 1e-6, mine[0], mine[1], mine[2], mine[3])
    theirs = drop_near(r, 1e-6, *sort_pairs(theirs[0], theirs[1], theirs[2], theirs[3]))
    assert_same_pairs(mine, theirs, context)
    return mine


@pytest.mark.parametrize("seed", range(64))
def test_get_neighbor_list_matches_pymatgen(seed):
    structure, r = structure_for(seed)
    compare(structure, r, f"seed {seed}, pbc {structure.lattice.pbc}")


@pytest.mark.parametrize("seed", range(8))
def test_exclude_self_false_adds_each_site_at_image_zero(seed):
    structure, r = structure_for(seed)
    mine = compare(structure, r, f"seed {seed}", exclude_self=False)
    i, j, S = mine[0], mine[1], mine[2]
    assert np.sum((i == j) & (S == 0).all(axis=1)) == len(structure)


def test_d_equal_to_r_counts_as_in_pymatgen():
    structure = Structure(Lattice.cubic(3.0), ["Si", "Si"], [[0, 0, 0], [0.5, 0, 0]])
    for r in (1.5, 3.0):
        i = tricell.pymatgen.get_neighbor_list(structure, r)[0]
        assert len(i) == len(structure.get_neighbor_list(r)[0]), r
    assert len(tricell.pymatgen.get_neighbor_list(structure, 1.5, numerical_tol=0)[0]) > 0


def test_empty_structure_and_no_pairs():
    structure = Structure(Lattice.cubic(10.0), ["Si"], [[0, 0, 0]])
    mine = tricell.pymatgen.get_neighbor_list(structure, 2.0)
    theirs = structure.get_neighbor_list(2.0)
    for m, t in zip(mine, theirs):
        assert m.dtype == t.dtype and m.shape == t.shape
