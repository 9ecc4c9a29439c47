"""Boxes as data sets give them for open axes: a molecule's all-zero cell, a slab's or a wire's
zero rows (and open rows parallel to a periodic one) are accepted by the native API, its batch
call and the torch op, with the pairs of the same positions in any box large enough (ASE's,
given the system's own cell); a zero or parallel row along a periodic axis is refused, naming
it."""
import numpy as np
import pytest

import tricell
from conftest import ALL_PBC, assert_same_pairs, drop_near, random_system, sort_pairs
from ase import neighborlist as ase_nl


def open_system(seed):
    """(given rows with the open axes zero or degenerate, the system's own rows, positions,
    pbc, cutoff) for a molecule, a wire or a slab."""
    pbc = ALL_PBC[seed % 7]  # never all periodic
    cell, positions, pbc, cutoff, _ = random_system(seed, pbc=pbc)
    given = cell.copy()
    rng = np.random.default_rng(seed + 11)
    for k in range(3):
        if not pbc[k]:
            other = next((m for m in ((k + 1) % 3, (k + 2) % 3) if pbc[m]), (k + 1) % 3)
            given[k] = 2.5 * cell[other] if rng.random() < 0.25 else 0.0
    return given, cell, positions, pbc, cutoff


@pytest.mark.parametrize("seed", range(42))
@pytest.mark.parametrize("full", [True, False])
def test_zero_rows_of_open_axes_give_the_pairs_of_any_large_box(seed, full):
    given, cell, positions, pbc, cutoff = open_system(seed)
    found = tricell.NeighborList(cutoff, full=full, sorted=True).compute(
        positions, given, pbc, "ijSdD")
    assert not np.any(found[2][:, ~np.array(pbc)]), f"seed {seed}: a shift along an open axis"
    reference = sort_pairs(*ase_nl.primitive_neighbor_list("ijSdD", pbc, cell, positions, cutoff))
    if not full:
        i, j, S = reference[:3]
        first = np.argmax(S != 0, axis=1)
        keep = (i < j) | ((i == j) & (S[np.arange(len(S)), first] > 0))
        reference = tuple(c[keep] for c in reference)
    assert_same_pairs(drop_near(cutoff, 1e-9, *found), drop_near(cutoff, 1e-9, *reference),
                      f"seed {seed}")


def test_the_batch_call_takes_zero_rows():
    systems = [open_system(seed) for seed in range(12)]
    cutoff = 2.0
    nl = tricell.NeighborList(cutoff)
    offsets, *columns = nl.compute_batch([s[2] for s in systems], [s[0] for s in systems],
                                         [s[3] for s in systems], "ijSd")
    for k, (given, cell, positions, pbc, _) in enumerate(systems):
        alone = nl.compute(positions, cell, pbc, "ijSd")
        mine = [c[offsets[k]:offsets[k + 1]] for c in columns]
        assert_same_pairs(drop_near(cutoff, 1e-9, *sort_pairs(*mine)),
                          drop_near(cutoff, 1e-9, *sort_pairs(*alone)), f"structure {k}")


def test_a_molecule_needs_no_cell():
    positions = np.random.default_rng(5).uniform(0, 4, (9, 3))
    i, j, S, d = tricell.NeighborList(2.5).compute(positions, np.zeros((3, 3)), False)
    expected = np.linalg.norm(positions[:, None] - positions[None], axis=2)
    expected[np.arange(9), np.arange(9)] = np.inf
    assert len(i) == np.count_nonzero(expected < 2.5)
    np.testing.assert_allclose(d, expected[i, j], rtol=1e-14)
    assert not S.any()


def test_zero_or_parallel_periodic_rows_are_refused_by_name():
    positions = np.zeros((2, 3))
    nl = tricell.NeighborList(1.0)
    with pytest.raises(ValueError, match=r"lattice vector c is zero but axis c is periodic"):
        nl.compute(positions, np.diag([3.0, 3.0, 0.0]), True)
    with pytest.raises(ValueError, match=r"the periodic lattice vectors a and b are parallel"):
        nl.compute(positions, [[3, 0, 0], [6, 0, 0], [0, 0, 0]], [True, True, False])
    with pytest.raises(ValueError, match=r"structure 1: lattice vector b is zero"):
        nl.compute_batch([positions, positions], [np.eye(3), np.diag([1.0, 0.0, 1.0])], True)


def test_the_torch_op_takes_zero_rows():
    torch = pytest.importorskip("torch")
    try:
        import tricell.torch as tt
    except ImportError as error:
        pytest.skip(f"tricell.torch is not available: {error}")
    for seed in range(12):
        given, cell, positions, pbc, cutoff = open_system(seed)
        x = torch.tensor(positions, requires_grad=True)
        h = torch.tensor(given, requires_grad=True)
        i, j, S, d = tt.NeighborList(cutoff).compute(x, h, list(pbc), "ijSd")
        mine = sort_pairs(i.numpy(), j.numpy(), S.numpy(), d.detach().numpy())
        expected = sort_pairs(*tricell.NeighborList(cutoff).compute(positions, cell, pbc, "ijSd"))
        assert_same_pairs(drop_near(cutoff, 1e-9, *mine), drop_near(cutoff, 1e-9, *expected),
                          f"seed {seed}")
        d.sum().backward()  # gradients flow through the given (zero-row) box
        assert h.grad is not None and torch.all(torch.isfinite(h.grad))
