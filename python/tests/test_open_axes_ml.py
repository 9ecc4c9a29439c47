"""Boxes with nothing along open axes (a molecule's all-zero cell, zero or degenerate rows of a
slab's or a wire's open axes) through the machine-learning fronts: the concatenated batch of
numpy and torch, torchsim_nl, tricell.vesin and tricell.vesin.torch, each against a brute force
over the periodic images in the system's own cell (S = 0 along open axes). Gradients: D does
not depend on the rows of open axes (their shifts are 0), so the gradient of any function of D
and d is exactly zero there, and along periodic rows and the positions it is that of the same
system in its own cell.

Skipped, with the reason, where PyTorch or the op library is missing (the torch cases only)."""
import itertools

import numpy as np
import pytest

import tricell
import tricell.vesin
from conftest import ALL_PBC, assert_same_pairs, drop_near, random_system, sort_pairs


def open_system(seed):
    """(given rows, own rows, positions, pbc, cutoff): never all periodic; each open row zero
    or, one time in four, a multiple of another row (not spanning space)."""
    pbc = ALL_PBC[seed % 7]
    cell, positions, pbc, cutoff, _ = random_system(seed, pbc=pbc, far=1)
    given = cell.copy()
    rng = np.random.default_rng(seed + 23)
    for k in range(3):
        if not pbc[k]:
            given[k] = 2.5 * cell[(k + 1) % 3] if rng.random() < 0.25 else 0.0
    return given, cell, positions, pbc, cutoff


def brute_force(cell, positions, pbc, cutoff):
    """Every (i, j, S, d, D) with d < cutoff, S over the periodic axes only, sorted."""
    inverse = np.linalg.inv(cell)
    widths = 1.0 / np.linalg.norm(inverse, axis=0)
    fractional = positions @ inverse
    span = np.ptp(fractional, axis=0) if len(positions) else np.zeros(3)
    reach = [int(np.ceil(cutoff / widths[a] + span[a])) + 1 if pbc[a] else 0 for a in range(3)]
    shifts = np.array(list(itertools.product(*[range(-r, r + 1) for r in reach])))
    D = positions[None, :, None, :] - positions[:, None, None, :] + (shifts @ cell)[None, None]
    d = np.linalg.norm(D, axis=3)
    itself = np.all(shifts == 0, axis=1)
    d[np.arange(len(positions)), np.arange(len(positions)), :] = np.where(
        itself, np.inf, d[np.arange(len(positions)), np.arange(len(positions)), :])
    i, j, s = np.nonzero(d < cutoff)
    return sort_pairs(i, j, shifts[s], d[i, j, s], D[i, j, s])


def check(mine, system, context):
    """mine = (i, j, S, d, D) of one system (local indices) against the brute force."""
    given, cell, positions, pbc, cutoff = system
    mine = tuple(np.asarray(c) for c in mine)
    assert not np.any(mine[2][:, ~np.array(pbc)]), f"{context}: a shift along an open axis"
    expected = brute_force(cell, positions, pbc, cutoff)
    assert_same_pairs(drop_near(cutoff, 1e-9, *sort_pairs(*mine)),
                      drop_near(cutoff, 1e-9, *expected), context)


def concatenated(systems):
    """(points, boxes, pbc, batch_ptr) of the given rows, the cutoff of the first system."""
    ptr = np.concatenate([[0], np.cumsum([len(s[2]) for s in systems])]).astype(np.int64)
    return (np.concatenate([s[2] for s in systems]), np.array([s[0] for s in systems]),
            np.array([s[3] for s in systems]), ptr)


def batches():
    """Six batches of up to seven open systems, each with its first system's cutoff."""
    for seed in range(6):
        systems = [open_system(40 * seed + k) for k in range(1 + seed)]
        cutoff = systems[0][4]
        yield seed, [s[:4] + (cutoff,) for s in systems]


@pytest.mark.parametrize("seed", range(60))
def test_numpy_and_vesin_single_calls(seed):
    system = open_system(seed)
    given, _, positions, pbc, cutoff = system
    mine = tricell.NeighborList(cutoff).compute(positions, given, pbc, "ijSdD")
    check(mine, system, f"seed {seed} NeighborList")
    vesin = tricell.vesin.NeighborList(cutoff, full_list=True).compute(
        positions, given, pbc, "ijSdD")
    check(vesin, system, f"seed {seed} tricell.vesin")


@pytest.mark.parametrize("seed,systems", batches())
def test_numpy_concatenated_batch(seed, systems):
    points, boxes, pbc, ptr = concatenated(systems)
    offsets, i, j, S, d, D = tricell.NeighborList(systems[0][4]).compute_batch(
        points, boxes, pbc, "ijSdD", batch_ptr=ptr)
    for s, system in enumerate(systems):
        rows = slice(offsets[s], offsets[s + 1])
        check((i[rows] - ptr[s], j[rows] - ptr[s], S[rows], d[rows], D[rows]), system,
              f"batch {seed} structure {s}")


def test_a_molecule_with_an_all_zero_cell_everywhere():
    positions = np.random.default_rng(3).uniform(-2, 2, (11, 3))
    system = (np.zeros((3, 3)), 10 * np.eye(3), positions, (False,) * 3, 2.2)
    check(tricell.NeighborList(2.2).compute(positions, np.zeros((3, 3)), False, "ijSdD"),
          system, "numpy")
    check(tricell.vesin.NeighborList(2.2, full_list=True).compute(
        positions, np.zeros((3, 3)), False, "ijSdD"), system, "tricell.vesin")
    i, j, d = tricell.vesin.ase_neighbor_list(
        "ijd", __import__("ase").Atoms(positions=positions), 2.2)
    assert len(i) == len(brute_force(10 * np.eye(3), positions, (False,) * 3, 2.2)[0])


@pytest.fixture
def torch_fronts():
    torch = pytest.importorskip("torch")
    try:
        import tricell.torch as tt
        import tricell.vesin.torch as vt
    except ImportError as error:
        pytest.skip(f"tricell.torch is not available: {error}")
    return torch, tt, vt


@pytest.mark.parametrize("seed", range(24))
def test_torch_single_calls_and_gradients(seed, torch_fronts):
    torch, tt, vt = torch_fronts
    system = open_system(seed)
    given, cell, positions, pbc, cutoff = system
    open_rows = ~np.array(pbc)
    nl = tt.NeighborList(cutoff)
    grads = []
    for rows in (given, cell):
        x = torch.tensor(positions, requires_grad=True)
        h = torch.tensor(rows, requires_grad=True)
        i, j, S, d, D = nl(x, h, list(pbc), "ijSdD")
        if rows is given:
            check((i, j, S, d.detach(), D.detach()), system, f"seed {seed} tricell.torch")
        energy = (torch.exp(-d) * (1 + D[:, 0] ** 2)).sum()
        grads.append(torch.autograd.grad(energy, (x, h), allow_unused=True))
    gx, gh = (g if g is not None else torch.zeros(1) for g in grads[0])
    if len(S) > 0:
        assert torch.all(gh[open_rows] == 0), f"seed {seed}: gradient along an open row"
        torch.testing.assert_close(gx, grads[1][0], rtol=1e-12, atol=1e-12)
        torch.testing.assert_close(gh[~open_rows], grads[1][1][~open_rows], rtol=1e-12,
                                   atol=1e-12)
    x, h = torch.tensor(positions), torch.tensor(given)
    vesin = vt.NeighborList(cutoff, full_list=True).compute(x, h, torch.tensor(pbc), "ijSdD")
    check(vesin, system, f"seed {seed} tricell.vesin.torch")


@pytest.mark.parametrize("seed,systems", batches())
def test_torch_batch_and_torchsim_nl(seed, systems, torch_fronts):
    torch, tt, _ = torch_fronts
    points, boxes, pbc, ptr = concatenated(systems)
    x = torch.tensor(points, requires_grad=True)
    h = torch.tensor(boxes, requires_grad=True)
    offsets, i, j, S, d, D = tt.NeighborList(systems[0][4]).compute_batch(
        x, h, torch.from_numpy(pbc), torch.from_numpy(ptr), "ijSdD")
    for s, system in enumerate(systems):
        rows = slice(int(offsets[s]), int(offsets[s + 1]))
        check((i[rows] - ptr[s], j[rows] - ptr[s], S[rows], d[rows].detach(),
               D[rows].detach()), system, f"batch {seed} structure {s}")
    if len(d) > 0:
        (gh,) = torch.autograd.grad((d ** 2).sum() + D.sum(), (h,))
        assert torch.all(gh[torch.from_numpy(~pbc)] == 0), f"batch {seed}: open-row gradient"

    system_idx = torch.repeat_interleave(torch.arange(len(systems)), torch.from_numpy(ptr).diff())
    mapping, system_mapping, shifts = tt.torchsim_nl(
        x.detach(), h.detach(), torch.from_numpy(pbc), systems[0][4], system_idx)
    for s, system in enumerate(systems):
        mine = system_mapping == s
        a, b = mapping[0, mine], mapping[1, mine]
        vectors = x.detach()[b] - x.detach()[a] + shifts[mine] @ h.detach()[s]
        check((a - ptr[s], b - ptr[s], shifts[mine].long(), vectors.norm(dim=1), vectors),
              system, f"torchsim_nl batch {seed} system {s}")
