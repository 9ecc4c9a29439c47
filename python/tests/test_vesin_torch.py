"""tricell.vesin with torch tensors, and tricell.vesin.torch (vesin-torch's NeighborList): the
pairs against tricell.torch, vesin-torch's output types, periodic as a bool or a tensor, the
gradients (gradcheck), TorchScript, and the errors.

Skipped, with the reason, when the op library was not built or PyTorch is missing."""
from typing import List

import numpy as np
import pytest

from conftest import import_torch_front

vesin_torch = import_torch_front("tricell.vesin.torch")
import torch

import tricell.vesin as vesin
from conftest import random_system, sort_pairs


def test_torch_tensors_in_give_torch_tensors_out():
    cell, positions, pbc, cutoff, _ = random_system(7, pbc=(True, False, True))
    nl = vesin.NeighborList(cutoff, full_list=True)
    i, j, S, d = nl.compute(torch.tensor(positions), torch.tensor(cell), torch.tensor(pbc),
                            "ijSd")
    assert all(isinstance(a, torch.Tensor) for a in (i, j, S, d))
    assert S.dtype == torch.int32 and d.dtype == torch.float64
    theirs = nl.compute(positions, cell, pbc, "ijSd")
    for mine, expected in zip((i, j, S, d), theirs):
        assert np.array_equal(mine.numpy().astype(expected.dtype), expected)
    with pytest.raises(RuntimeError, match=r"does not support autograd"):
        nl.compute(torch.tensor(positions, requires_grad=True), torch.tensor(cell), pbc, "ij")


@pytest.mark.parametrize("seed", range(24))
@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
def test_torch_module_equals_tricell_torch(seed, dtype):
    import tricell.torch as tt

    cell, positions, pbc, cutoff, _ = random_system(seed)
    full, sorted_ = bool(seed % 2), bool(seed % 3 == 0)
    x, h = torch.tensor(positions, dtype=dtype), torch.tensor(cell, dtype=dtype)
    nl = vesin_torch.NeighborList(cutoff, full_list=full, sorted=sorted_)
    periodic = torch.tensor(pbc) if seed % 4 else bool(pbc[0])
    flags = list(pbc) if seed % 4 else [bool(pbc[0])] * 3
    i, j, S, D, d, P = nl.compute(x, h, periodic, "ijSDdP")
    assert [a.dtype for a in (i, j, S, D, d, P)] == [torch.int64, torch.int64, torch.int32, dtype,
                                                     dtype, torch.int64]
    expected = tt.NeighborList(cutoff, full=full)(x, h, flags, "ijSDd")
    mine = sort_pairs(i.numpy(), j.numpy(), S.numpy(), D.numpy(), d.numpy())
    theirs = sort_pairs(*(a.numpy() for a in expected))
    for k, name in enumerate("ijSDd"):
        assert np.array_equal(mine[k], theirs[k].astype(mine[k].dtype)), f"seed {seed}: {name}"
    if sorted_:
        assert bool((i[1:] >= i[:-1]).all())


class Holder(torch.nn.Module):
    def __init__(self, cutoff: float):
        super().__init__()
        self.nl = vesin_torch.NeighborList(cutoff, full_list=True)

    def forward(self, x: torch.Tensor, h: torch.Tensor) -> List[torch.Tensor]:
        return self.nl.compute(x, h, True, "ijd")


def test_torch_module_scripts_and_differentiates():
    cell, positions, pbc, cutoff, _ = random_system(9, pbc=(True, True, True), atoms=8)
    x = torch.tensor(positions, requires_grad=True)
    h = torch.tensor(cell, requires_grad=True)
    eager = Holder(cutoff)
    scripted = torch.jit.script(eager)
    for mine, theirs in zip(eager(x, h), scripted(x, h)):
        assert torch.equal(mine, theirs)
    nl = vesin_torch.NeighborList(cutoff, full_list=False)
    i = nl.compute(x, h, True, "i")[0]
    assert len(i) > 0

    def distances(x, h):
        i, j, S, d = nl.compute(x, h, True, "ijSd")
        order = np.lexsort((S[:, 2].numpy(), S[:, 1].numpy(), S[:, 0].numpy(), j.numpy(),
                            i.numpy()))
        return d[torch.from_numpy(order)]

    assert torch.autograd.gradcheck(distances, (x, h))


def test_torch_module_errors_name_the_value():
    nl = vesin_torch.NeighborList(1.0, full_list=True)
    x, h = torch.zeros(2, 3, dtype=torch.float64), torch.eye(3, dtype=torch.float64)
    with pytest.raises(ValueError, match=r"unexpected character in `quantities`: Q"):
        nl.compute(x, h, True, "ijQ")
    with pytest.raises(ValueError, match=r"same device, got cpu and meta"):
        nl.compute(x, h.to("meta"), True, "ij")
    with pytest.raises(RuntimeError, match=r"same dtype, got torch.float32 and torch.float64"):
        nl.compute(x.float(), h, True, "ij")
    with pytest.raises(ValueError, match=r"periodic must be one bool or three \(got 2\)"):
        nl.compute(x, h, torch.tensor([True, False]), "ij")
    with pytest.raises(RuntimeError, match=r"neighbor_pairs: cutoff must be finite and > 0 "
                                           r"\(got -1\)"):
        vesin_torch.NeighborList(-1.0, full_list=True).compute(x, h, True, "ij")
    with pytest.raises(ValueError, match=r"n_threads must be zero or a positive integer"):
        vesin_torch.NeighborList(1.0, full_list=True, n_threads=-1)
