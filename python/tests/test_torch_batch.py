"""tricell.torch's batches: NeighborList.compute_batch (the concatenated layout) and
torchsim_nl (TorchSim's contract), against one call per structure and the native module; D, d
and their gradients through the positions and every structure's cell (per-structure forces and
stress from one backward pass against each structure alone), float32 and float64, eager and
TorchScript; the messages of bad inputs.

Skipped, with the reason, when the op library was not built or PyTorch is missing."""
from typing import List

import numpy as np
import pytest

from conftest import import_torch_front

tt = import_torch_front()
import torch

import tricell
from conftest import brute_force_pairs, random_system
from test_torch import LennardJones, energy_forces_stress, lj_system

LETTERS = "ijSDd"


def random_batch(seed, dtype=torch.float64):
    """(points, boxes, pbc, batch_ptr, cutoff, systems): 0 to 8 random systems, the first
    one's cutoff for all (empty systems too), as tensors in the concatenated layout."""
    rng = np.random.default_rng(seed)
    count = int(rng.integers(0, 9))
    systems = [random_system(500 * seed + k, atoms=int(rng.integers(0, 12))) for k in range(count)]
    cutoff = systems[0][3] if systems else 1.0
    ptr = np.concatenate([[0], np.cumsum([len(s[1]) for s in systems])]).astype(np.int64)
    points = np.concatenate([s[1] for s in systems]) if systems else np.zeros((0, 3))
    boxes = np.array([s[0] for s in systems]).reshape(-1, 3, 3)
    pbc = np.array([s[2] for s in systems], dtype=bool).reshape(-1, 3)
    return (torch.tensor(points, dtype=dtype), torch.tensor(boxes, dtype=dtype),
            torch.from_numpy(pbc), torch.from_numpy(ptr), cutoff, systems)


@pytest.mark.parametrize("seed", range(30))
@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
def test_batch_equals_one_call_per_structure(seed, dtype):
    x, h, pbc, ptr, cutoff, systems = random_batch(seed, dtype)
    full = bool(seed % 2)
    nl = tt.NeighborList(cutoff, full=full, threads=seed % 3)
    for module in (nl, torch.jit.script(nl)):
        offsets, *columns = module.compute_batch(x, h, pbc, ptr, LETTERS)
        assert offsets.dtype == torch.int64 and offsets.shape == (len(systems) + 1,)
        assert [c.dtype for c in columns] == [torch.int64] * 3 + [dtype] * 2
        for s in range(len(systems)):
            rows = slice(int(offsets[s]), int(offsets[s + 1]))
            alone = nl(x[ptr[s]:ptr[s + 1]], h[s], pbc[s].tolist(), LETTERS)
            for letter, mine, theirs in zip(LETTERS, columns, alone):
                got = mine[rows] - (ptr[s] if letter in "ij" else 0)
                if letter in "ijS" or dtype == torch.float64:
                    assert torch.equal(got, theirs), f"seed {seed} structure {s} {letter}"
                else:  # float32: the same pairs, D and d to rounding of another summation order
                    torch.testing.assert_close(got, theirs, rtol=1e-5, atol=1e-5)


def test_outputs_of_many_megabytes_equal_the_native_lists():
    # Over 4 MiB per column: the ops allocate such outputs themselves (output_tensor.hpp).
    rng = np.random.default_rng(40)
    points = rng.uniform(0, 24, (7000, 3))
    box = 24 * np.eye(3)
    cutoff = 3.5
    expected = tricell.NeighborList(cutoff).compute(points, box, True, "ijSDd")
    assert len(expected[0]) > 600_000
    x, h = torch.from_numpy(points), torch.from_numpy(box)
    nl = tt.NeighborList(cutoff)
    single = nl(x, h, [True, True, True], "ijSDd")
    offsets, *batch = nl.compute_batch(x, h[None], torch.ones(1, 3, dtype=torch.bool),
                                       torch.tensor([0, len(points)]), "ijSDd")
    assert offsets.tolist() == [0, len(expected[0])]
    for columns in (single, batch):
        for letter, mine, theirs in zip("ijSDd", columns, expected):
            if letter in "ijS":
                assert np.array_equal(mine.numpy(), theirs), letter
            else:
                np.testing.assert_allclose(mine.numpy(), theirs, rtol=0, atol=1e-12)


def test_shared_box_and_periodicity_broadcast():
    x, h, pbc, ptr, cutoff, systems = random_batch(3)
    nl = tt.NeighborList(cutoff)
    count = len(systems)
    assert count > 1
    same = nl.compute_batch(x, h[0], pbc[0], ptr, "ijSd")
    expanded = nl.compute_batch(x, h[0].expand(count, 3, 3), pbc[0].expand(count, 3), ptr, "ijSd")
    assert all(torch.equal(a, b) for a, b in zip(same, expanded))


def test_no_pair_joins_structures_that_overlap():
    cell, positions, pbc, cutoff, _ = random_system(8, pbc=(True, False, True), atoms=10)
    x = torch.tensor(np.concatenate([positions] * 3))
    ptr = torch.tensor([0, 10, 10, 20, 30])
    h = torch.tensor(np.array([cell] * 4))
    offsets, i, j = tt.NeighborList(cutoff).compute_batch(
        x, h, torch.tensor([pbc] * 4), ptr, "ij")
    alone = len(tricell.NeighborList(cutoff).compute(positions, cell, pbc, "i"))
    assert (offsets[1:] - offsets[:-1]).tolist() == [alone, 0, alone, alone]
    for s in range(4):
        rows = slice(int(offsets[s]), int(offsets[s + 1]))
        assert bool(((i[rows] >= ptr[s]) & (i[rows] < ptr[s + 1])).all())
        assert bool(((j[rows] >= ptr[s]) & (j[rows] < ptr[s + 1])).all())


class BatchEnergy(torch.nn.Module):
    """The Lennard-Jones energy of test_torch.LennardJones, summed per structure of a batch."""

    def __init__(self, rc: float, full: bool):
        super().__init__()
        self.neighbors = tt.NeighborList(rc, full=full)
        self.shift = 4 * ((1 / rc) ** 12 - (1 / rc) ** 6)
        self.weight = 0.5 if full else 1.0

    def forward(self, x: torch.Tensor, h: torch.Tensor, pbc: torch.Tensor,
                ptr: torch.Tensor) -> torch.Tensor:
        offsets, d = self.neighbors.compute_batch(x, h, pbc, ptr, "d")
        s6 = (1 / d) ** 6
        pair = self.weight * (4 * (s6 * s6 - s6) - self.shift)
        system = torch.repeat_interleave(torch.arange(h.shape[0]), offsets[1:] - offsets[:-1])
        return torch.zeros(h.shape[0], dtype=x.dtype).index_add(0, system, pair)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("full", [True, False])
def test_per_structure_forces_and_stress_from_one_backward_pass(seed, full):
    """Several Lennard-Jones systems sharing one cutoff in one batch: the forces and each
    structure's stress from one backward pass equal each structure's own (test_torch)."""
    pbcs = ([True, True, True], [True, False, True], [False, False, False])
    systems = [lj_system(10 * seed + k, pbcs[k % 3]) for k in range(3)]
    rc = min(s[2] for s in systems)
    ptr = torch.tensor(np.cumsum([0] + [len(s[0]) for s in systems]))
    x = torch.tensor(np.concatenate([s[0] for s in systems]), requires_grad=True)
    h = torch.tensor(np.array([s[1] for s in systems]), requires_grad=True)
    pbc = torch.tensor(pbcs)
    for model in (BatchEnergy(rc, full), torch.jit.script(BatchEnergy(rc, full))):
        energies = model(x, h, pbc, ptr)
        gx, gh = torch.autograd.grad(energies.sum(), (x, h))
        for s, (positions, cell, _) in enumerate(systems):
            energy, forces, stress = energy_forces_stress(LennardJones(rc, full), positions, cell,
                                                          pbcs[s])
            atoms = slice(int(ptr[s]), int(ptr[s + 1]))
            xs, hs = x.detach()[atoms], h.detach()[s]
            mine = (xs.T @ gx[atoms] + hs.T @ gh[s]) / abs(float(torch.linalg.det(hs)))
            context = f"seed {seed} structure {s}"
            assert float(energies[s]) == pytest.approx(energy, rel=1e-12, abs=1e-12), context
            np.testing.assert_allclose(-gx[atoms].numpy(), forces, rtol=1e-10,
                                       atol=1e-10 * np.abs(forces).max(), err_msg=context)
            np.testing.assert_allclose(mine.numpy(), stress, rtol=1e-10,
                                       atol=1e-10 * np.abs(stress).max(), err_msg=context)


def test_gradcheck_through_positions_and_every_box():
    x, h, pbc, ptr, cutoff, systems = random_batch(11)
    nl = tt.NeighborList(cutoff)
    x.requires_grad_()
    h.requires_grad_()
    offsets, i, j, S = nl.compute_batch(x, h, pbc, ptr, "ijSd")[:4]

    def vectors(x, h):
        # The pair set of the unperturbed inputs (gradcheck's steps never cross the cutoff
        # for these points, checked by the pair count).
        out = nl.compute_batch(x, h, pbc, ptr, "ijSDd")
        assert torch.equal(out[1], i) and torch.equal(out[3], S)
        return out[4], out[5]

    assert len(i) > 0
    assert torch.autograd.gradcheck(vectors, (x, h))
    assert torch.autograd.gradgradcheck(vectors, (x, h))


def test_pair_vectors_refuses_pairs_that_do_not_fit():
    x, h = torch.zeros(3, 3, dtype=torch.float64), torch.eye(3, dtype=torch.float64)[None]
    i, j, S = torch.tensor([0]), torch.tensor([5]), torch.zeros(1, 3, dtype=torch.int64)
    with pytest.raises(RuntimeError, match=r"pair_vectors: pair 0 indexes an atom out of range"):
        torch.ops.tricell.pair_vectors(x, h, i, j, S, torch.tensor([0, 1]))
    with pytest.raises(RuntimeError, match=r"pair_vectors: offsets must have one entry per cell "
                                           r"and one more \(got shape \[3\] for 1 cells\)"):
        torch.ops.tricell.pair_vectors(x, h, i, i, S, torch.tensor([0, 1, 1]))
    with pytest.raises(RuntimeError, match=r"pair_vectors: offsets must start at 0 and end at the "
                                           r"number of pairs \(got 0 and 0 for 1 pairs\)"):
        torch.ops.tricell.pair_vectors(x, h, i, i, S, torch.tensor([0, 0]))
    with pytest.raises(RuntimeError, match=r"pair_vectors: S must be an int64 tensor"):
        torch.ops.tricell.pair_vectors(x, h, i, i, S.int(), torch.tensor([0, 1]))


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
def test_torchsim_nl_gives_every_systems_pairs_in_torchsims_layout(seed, dtype):
    rng = np.random.default_rng(seed)
    count = int(rng.integers(1, 5))
    systems = [random_system(70 * seed + k, atoms=int(rng.integers(1, 9)), far=2)
               for k in range(count)]
    cutoff = systems[0][3]
    positions = torch.tensor(np.concatenate([s[1] for s in systems]), dtype=dtype)
    cell = torch.tensor(np.array([s[0] for s in systems]), dtype=dtype)
    pbc = torch.tensor([s[2] for s in systems])
    system_idx = torch.repeat_interleave(torch.arange(count), torch.tensor(
        [len(s[1]) for s in systems]))
    for function in (tt.torchsim_nl, torch.jit.script(tt.torchsim_nl)):
        mapping, system_mapping, shifts = function(positions, cell, pbc, cutoff, system_idx)
        assert mapping.dtype == torch.int64 and mapping.shape[0] == 2
        assert system_mapping.dtype == torch.int64 and shifts.dtype == dtype
        assert torch.equal(system_mapping, system_idx[mapping[0]])
        assert torch.equal(system_mapping, system_idx[mapping[1]])
        first = torch.cumsum(torch.bincount(system_idx, minlength=count), 0) - \
            torch.bincount(system_idx, minlength=count)
        for s, (h, x, p, _, _) in enumerate(systems):
            mine = system_mapping == s
            local = mapping[:, mine] - first[s]
            found = {(int(a), int(b), tuple(int(v) for v in S)) for a, b, S in
                     zip(local[0], local[1], shifts[mine])}
            x64 = positions.double().numpy()[system_idx.numpy() == s]
            assert found == brute_force_pairs(x64, cell[s].double().numpy(), p, cutoff) or \
                dtype == torch.float32, f"seed {seed} system {s}"
        # TorchSim's distances: positions[j] - positions[i] + shifts @ cell[system].
        vectors = positions[mapping[1]] - positions[mapping[0]] + torch.einsum(
            "pa,pab->pb", shifts, cell[system_mapping])
        assert bool((vectors.norm(dim=1) < cutoff * (1 + 1e-5)).all())


def test_torchsim_nl_with_one_cell_self_interaction_and_empty_systems():
    cell, positions, pbc, cutoff, _ = random_system(5, atoms=6, pbc=(True, True, True))
    x = torch.tensor(np.concatenate([positions, positions]))
    system_idx = torch.tensor([0] * 6 + [2] * 6)  # system 1 is empty
    h = torch.tensor(cell)
    mapping, system_mapping, shifts = tt.torchsim_nl(x, h, torch.tensor(pbc), cutoff, system_idx)
    half = mapping.shape[1] // 2
    assert torch.equal(mapping[:, half:] - 6, mapping[:, :half])
    assert set(system_mapping.tolist()) == {0, 2}
    with_self = tt.torchsim_nl(x, h, torch.tensor(pbc), cutoff, system_idx, True)
    assert torch.equal(with_self[0][:, :2 * half], mapping)
    assert torch.equal(with_self[0][:, 2 * half:], torch.arange(12).expand(2, 12))
    assert torch.equal(with_self[1][2 * half:], system_idx)
    assert bool((with_self[2][2 * half:] == 0).all())
    empty = tt.torchsim_nl(torch.zeros(0, 3), torch.eye(3), torch.tensor([True] * 3), 1.0,
                           torch.zeros(0, dtype=torch.int64))
    assert [t.shape for t in empty] == [(2, 0), (0,), (0, 3)]


def call_batch(**changes):
    rng = np.random.default_rng(1)
    arguments = dict(points=torch.tensor(rng.random((40, 3)) * 3),
                     boxes=torch.eye(3, dtype=torch.float64).repeat(20, 1, 1) * 3,
                     periodic=torch.ones(20, 3, dtype=torch.bool),
                     batch_ptr=torch.arange(0, 41, 2))
    arguments.update(changes)
    return tt.NeighborList(2.0).compute_batch(**arguments)


def singular_box():
    boxes = torch.eye(3, dtype=torch.float64).repeat(20, 1, 1) * 3
    boxes[17, 1] = boxes[17, 0] * 2
    return boxes


def nan_points():
    points = torch.tensor(np.random.default_rng(1).random((40, 3)) * 3)
    points[7, 2] = float("nan")
    return points


@pytest.mark.parametrize("changes,message", [
    (dict(batch_ptr=torch.tensor([1, 40])), r"batch_pairs: batch_ptr must start at 0 \(got "
                                            r"batch_ptr\[0\] = 1\)"),
    (dict(batch_ptr=torch.tensor([0, 8, 3, 40])), r"batch_ptr must not decrease \(got "
                                                  r"batch_ptr\[1\] = 8 > batch_ptr\[2\] = 3"),
    (dict(batch_ptr=torch.tensor([0, 38])), r"batch_ptr must end at the number of points, 40 "
                                            r"\(got batch_ptr\[1\] = 38\)"),
    (dict(batch_ptr=torch.tensor([0.0, 40.0])), r"batch_ptr must hold integers \(got Float\)"),
    (dict(boxes=torch.eye(3, dtype=torch.float64).repeat(19, 1, 1)),
     r"cells must be a B x 3 x 3 tensor, one cell per structure of batch_ptr, the lattice "
     r"vectors as rows \(B = 20; got shape \[19, 3, 3\]\)"),
    (dict(periodic=torch.ones(19, 3, dtype=torch.bool)),
     r"pbc must be a B x 3 bool tensor, one row per structure of batch_ptr \(B = 20; got Bool "
     r"of shape \[19, 3\]\)"),
    (dict(boxes=singular_box()), r"batch_pairs: structure 17, cells\[17\]: "),
    (dict(points=nan_points()), r"batch_pairs: structure 3, positions\[6:8\]: position 1 is not "
                                r"finite"),
    (dict(points=torch.zeros(40, 2, dtype=torch.float64)),
     r"batch_pairs: positions must be an N x 3 tensor \(got shape \[40, 2\]\)"),
    (dict(boxes=torch.eye(3).repeat(20, 1, 1)),
     r"cells must have the dtype of positions \(got Float for cells and Double for positions\)"),
])
def test_bad_batches_raise_messages_naming_the_argument_and_structure(changes, message):
    with pytest.raises(RuntimeError, match=message):
        call_batch(**changes)


@pytest.mark.parametrize("call,message", [
    (lambda: tt.torchsim_nl(torch.zeros(4, 3), torch.eye(3), torch.tensor([True] * 3), 1.0,
                            torch.tensor([0, 1, 0, 1])),
     r"system_idx must not decrease, each system's atoms contiguous \(got system_idx\[2\] = 0 "
     r"after system_idx\[1\] = 1\)"),
    (lambda: tt.torchsim_nl(torch.zeros(4, 3), torch.eye(3).repeat(2, 1, 1),
                            torch.tensor([True] * 3), 1.0, torch.tensor([0, 0, 1, 2])),
     r"system_idx must lie in \[0, 2\), one system per cell \(got values from 0 to 2\)"),
    (lambda: tt.torchsim_nl(torch.zeros(4, 3), torch.eye(3), torch.tensor([True] * 3), 1.0,
                            torch.tensor([0, 0, 0])),
     r"system_idx must have one entry per atom, shape \[4\] \(got shape \[3\]\)"),
    (lambda: tt.torchsim_nl(torch.zeros(4, 3), torch.eye(3), torch.ones(3), 1.0,
                            torch.zeros(4, dtype=torch.int64)),
     r"pbc must be bools \(got torch.float32\)"),
])
def test_torchsim_nl_messages_name_the_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()
