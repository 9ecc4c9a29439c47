"""Several cutoffs from one search in tricell.torch: neighbor_lists (one structure, the op
neighbor_shells) and neighbor_lists_batch (the concatenated layout, batch_pairs with shells).
Every requested list (cutoff, full or half) must equal a separate NeighborList(cutoff, full)
call, pairs exactly and D and d bit for bit after sorting by (i, j, S), in eager mode and in
TorchScript; gradients through the positions and the boxes sum those of separate calls.

Skipped, with the reason, when the op library was not built or PyTorch is missing."""
import numpy as np
import pytest

from conftest import import_torch_front

tt = import_torch_front()
import torch

from conftest import random_system
from test_requests import random_requests

LETTERS = "ijSDd"
SCRIPTED = {"one": torch.jit.script(tt.neighbor_lists),
            "batch": torch.jit.script(tt.neighbor_lists_batch)}


def sorted_columns(columns):
    i, j, S = (c.numpy() for c in columns[:3])
    order = torch.from_numpy(np.lexsort((S[:, 2], S[:, 1], S[:, 0], j, i)))
    return [c.index_select(0, order) for c in columns]


def assert_same(mine, theirs, context):
    for letter, a, b in zip(LETTERS, sorted_columns(mine), sorted_columns(theirs)):
        assert a.dtype == b.dtype and torch.equal(a, b), f"{context}: {letter}"


@pytest.mark.parametrize("seed", range(40))
@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
def test_each_request_equals_a_separate_call(seed, dtype):
    cell, positions, pbc, cutoff, _ = random_system(seed)
    requests = random_requests(np.random.default_rng(seed), cutoff)
    x, h = torch.tensor(positions, dtype=dtype), torch.tensor(cell, dtype=dtype)
    for function in (tt.neighbor_lists, SCRIPTED["one"]):
        lists = function(x, h, list(pbc), requests, LETTERS)
        for k, ((r, full), got) in enumerate(zip(requests, lists)):
            alone = tt.NeighborList(r, full=full)(x, h, list(pbc), LETTERS)
            assert_same(got, alone, f"seed {seed} request {k}")


@pytest.mark.parametrize("seed", range(20))
def test_batch_requests_equal_one_call_per_structure(seed):
    rng = np.random.default_rng(seed)
    systems = [random_system(30 * seed + k) for k in range(int(rng.integers(1, 5)))]
    requests = random_requests(rng, systems[0][3])
    ptr = torch.tensor(np.concatenate([[0], np.cumsum([len(s[1]) for s in systems])]))
    x = torch.tensor(np.concatenate([s[1] for s in systems]))
    h = torch.tensor(np.array([s[0] for s in systems]))
    pbc = torch.tensor([s[2] for s in systems])
    for function in (tt.neighbor_lists_batch, SCRIPTED["batch"]):
        lists = function(x, h, pbc, ptr, requests, LETTERS, 1)
        for k, ((r, full), (offsets, *columns)) in enumerate(zip(requests, lists)):
            for s, (cell, positions, periodic, _, _) in enumerate(systems):
                rows = slice(int(offsets[s]), int(offsets[s + 1]))
                mine = [c[rows] for c in columns]
                mine[0], mine[1] = mine[0] - ptr[s], mine[1] - ptr[s]
                alone = tt.NeighborList(r, full=full)(x[ptr[s]:ptr[s + 1]], h[s],
                                                      list(periodic), LETTERS)
                assert_same(mine, alone, f"seed {seed} request {k} structure {s}")


def test_gradients_sum_those_of_separate_calls():
    cell, positions, pbc, cutoff, _ = random_system(5, pbc=(True, True, True), atoms=12)
    requests = [(cutoff, True), (0.6 * cutoff, False)]
    x = torch.tensor(positions, requires_grad=True)
    h = torch.tensor(cell, requires_grad=True)
    lists = tt.neighbor_lists(x, h, list(pbc), requests, "d")
    energy = sum(((d[0] - 0.5) ** 2).sum() for d in lists)
    mine = torch.autograd.grad(energy, (x, h))
    energy = sum(((tt.NeighborList(r, full=f)(x, h, list(pbc), "d")[0] - 0.5) ** 2).sum()
                 for r, f in requests)
    theirs = torch.autograd.grad(energy, (x, h))
    for a, b in zip(mine, theirs):
        torch.testing.assert_close(a, b, rtol=1e-12, atol=1e-12)


def test_bad_requests_raise_messages():
    x, h = torch.zeros(2, 3, dtype=torch.float64), torch.eye(3, dtype=torch.float64)
    with pytest.raises(ValueError, match=r"requests must hold at least one request"):
        tt.neighbor_lists(x, h, [True] * 3, [], "ij")
    with pytest.raises(RuntimeError, match=r"neighbor_shells: cutoffs\[0\] must be finite and > 0 "
                                           r"\(got -1\)"):
        tt.neighbor_lists(x, h, [True] * 3, [(-1.0, True)], "ij")
    with pytest.raises(ValueError, match=r"unknown letter 'o'"):
        tt.neighbor_lists(x, h, [True] * 3, [(1.0, True)], "io")
    with pytest.raises(RuntimeError, match=r"batch_pairs: cutoff must be finite and > 0 \(got nan\)"):
        tt.neighbor_lists_batch(x, h, torch.ones(3, dtype=torch.bool), torch.tensor([0, 2]),
                                [(float("nan"), True)], "ij")
