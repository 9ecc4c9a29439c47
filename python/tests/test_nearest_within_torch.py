"""The k nearest within the cutoff from torch: tricell.torch.NeighborList(cutoff,
max_neighbors=k, tie_tolerance=t, symmetric=s), one structure and the concatenated batch, eager
and scripted, gives exactly the pairs of the native list (whose definition
test_nearest_within_native.py checks), on random systems and perfect crystals of several
lattices (shells of equal distances, where only the (j, S) order decides); D and d keep their
gradients; the messages of options that do not go together name the argument.

Skipped, with the reason, where PyTorch or the op library is missing."""
import ase.build
import numpy as np
import pytest

from conftest import import_torch_front

tt = import_torch_front()
import torch

import tricell
from test_nearest_within_native import expected, system


def lattice(seed):
    """(positions, cell, pbc, cutoff): a perfect crystal, several shells within the cutoff."""
    name, structure, a = [("Cu", "fcc", 3.6), ("Fe", "bcc", 2.87), ("Po", "sc", 3.35),
                          ("Si", "diamond", 5.43), ("Mg", "hcp", 3.21)][seed % 5]
    atoms = ase.build.bulk(name, structure, a).repeat((1 + seed % 3, 2, 1))
    return atoms.positions, atoms.cell[:], [True, True, seed % 4 != 3], 1.6 * a


def cases():
    for seed in range(20):
        positions, box, pbc, cutoff = lattice(seed) if seed % 2 else system(seed)
        k = [1, 2, 3, 5, 8, 13][seed % 6]
        yield seed, (positions, box, pbc, cutoff), k, [0.0, 1e-9, 0.3][seed % 3], seed % 4 == 1


@pytest.mark.parametrize("seed,structure,k,tolerance,symmetric", cases())
def test_single_batch_and_scripted_give_the_native_lists(seed, structure, k, tolerance,
                                                         symmetric):
    positions, box, pbc, cutoff = structure
    want = expected(positions, box, pbc, cutoff, k, tolerance, symmetric)
    assert np.array_equal(
        want[0], tricell.NeighborList(cutoff, max_neighbors=k, tie_tolerance=tolerance,
                                      symmetric=symmetric).compute(positions, box, pbc, "i"))
    nl = tt.NeighborList(cutoff, max_neighbors=k, tie_tolerance=tolerance, symmetric=symmetric)
    x = torch.tensor(positions, requires_grad=True)
    h = torch.tensor(np.asarray(box), requires_grad=True)
    for module in (nl, torch.jit.script(nl)):
        single = module(x, h, list(pbc), "ijSd")
        offsets, *batch = module.compute_batch(x, h[None], torch.tensor([pbc]),
                                               torch.tensor([0, len(positions)]), "ijSd")
        assert offsets.tolist() == [0, len(want[0])]
        for columns, way in ((single, "single"), (batch, "batch")):
            for name, mine, theirs in zip("ijS", columns, want):
                assert np.array_equal(mine.numpy(), theirs), f"seed {seed} {way} {name}"
            np.testing.assert_allclose(columns[3].detach().numpy(), want[3], rtol=1e-13,
                                       atol=1e-13, err_msg=f"seed {seed} {way} d")
    d = single[3]
    if len(d) > 0:
        gx, gh = torch.autograd.grad(d.sum(), (x, h))
        assert torch.all(torch.isfinite(gx)) and torch.all(torch.isfinite(gh))


def test_a_lattice_shell_is_cut_by_j_and_S():
    positions, box, pbc, cutoff = lattice(0)  # fcc: 12 nearest at one distance
    i, j, S, d = tt.NeighborList(cutoff, max_neighbors=5)(
        torch.tensor(positions), torch.tensor(box), pbc, "ijSd")
    full = tricell.NeighborList(cutoff).compute(positions, box, pbc, "ijSd")
    first = full[3][full[0] == 0].min()
    assert np.count_nonzero(np.isclose(full[3][full[0] == 0], first, rtol=1e-12)) == 12
    assert torch.allclose(d[:5], torch.full((5,), first, dtype=d.dtype), rtol=1e-12)


def test_messages_name_the_argument():
    x, h = torch.zeros(2, 3, dtype=torch.float64), torch.eye(3, dtype=torch.float64)
    with pytest.raises(RuntimeError, match=r"neighbor_pairs: max_neighbors keeps the nearest "
                                           r"pairs of each centre of a full list: full must be "
                                           r"True"):
        tt.NeighborList(1.0, full=False, max_neighbors=2)(x, h, [True] * 3, "ij")
    with pytest.raises(RuntimeError, match=r"batch_pairs: max_neighbors must be >= 0"):
        tt.NeighborList(1.0, max_neighbors=-2).compute_batch(
            x, h[None], torch.ones(1, 3, dtype=torch.bool), torch.tensor([0, 2]), "ij")
    with pytest.raises(RuntimeError, match=r"neighbor_pairs: tie_tolerance applies to the "
                                           r"nearest pairs kept: set max_neighbors too"):
        tt.NeighborList(1.0, tie_tolerance=0.5)(x, h, [True] * 3, "ij")
    with pytest.raises(ValueError, match=r"full must be True \(got full=False\)"):
        tricell.NeighborList(1.0, full=False, max_neighbors=2)
    with pytest.raises(ValueError, match=r"sorted=True \(by j, S\) cannot be asked with it"):
        tricell.NeighborList(1.0, sorted=True, max_neighbors=2)
