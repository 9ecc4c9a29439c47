"""tricell.torch: the pairs against the native module, gradients (gradcheck, gradgradcheck,
finite differences), Lennard-Jones forces and stress against ASE's calculator, eager against
TorchScript, dtypes and the messages of bad inputs.

Skipped, with the reason, when the op library was not built (no libtorch, or the sanitizer
build) or PyTorch is missing; any other failure to import is an error.
"""
import io
from typing import List

import numpy as np
import pytest

from conftest import import_torch_front

tt = import_torch_front()
import torch
from ase import Atoms
from ase.calculators.lj import LennardJones as AseLennardJones
from ase.stress import voigt_6_to_full_3x3_stress

import tricell
from conftest import ALL_PBC, assert_same_pairs, random_cell, random_system, sort_pairs

MIXED_PBC = [True, False, True]


def as_tensors(positions, cell, dtype=torch.float64, grad=False):
    x = torch.tensor(np.asarray(positions), dtype=dtype, requires_grad=grad)
    h = torch.tensor(np.asarray(cell), dtype=dtype, requires_grad=grad)
    return x, h


def away_from_pairs(positions, cell, pbc, cutoff, gap=1e-3):
    """The first cutoff from `cutoff` up (in steps of gap) that no pair distance is within gap
    of, so that perturbations of ~1e-5 leave the pair set unchanged."""
    d = tricell.NeighborList(cutoff + 1.0).compute(positions, cell, pbc, "d")
    while np.any(np.abs(d - cutoff) < gap):
        cutoff += gap
    return cutoff


def sorted_vectors(nl, x, h, pbc):
    """D and d of the list reordered by i, j, S, so that a function of them does not depend on
    the search's order (which may change when a perturbed atom moves to another cell)."""
    i, j, S, D, d = nl(x, h, pbc, "ijSDd")
    order = np.lexsort((S[:, 2].numpy(), S[:, 1].numpy(), S[:, 0].numpy(), j.numpy(),
                        i.numpy()))
    order = torch.from_numpy(order)
    return D.index_select(0, order), d.index_select(0, order)


def small_system(seed, pbc):
    """A few atoms near a skewed or triclinic cell and a cutoff between two pair distances
    (away from both) that keeps 2 to 40 pairs of the full list (for gradcheck)."""
    rng = np.random.default_rng(1000 + seed)
    cell = random_cell(rng, ["triclinic", "skewed"][seed % 2])
    positions = rng.uniform(-0.2, 1.2, (int(rng.integers(2, 6)), 3)) @ cell
    d = np.sort(tricell.NeighborList(2 * np.abs(cell).sum(axis=1).max()).compute(
        positions, cell, pbc, "d"))
    k = int(rng.integers(2, min(len(d), 40) + 1))
    cutoff = away_from_pairs(positions, cell, pbc, 0.5 * (d[k - 1] + d[min(k, len(d) - 1)]))
    return positions, cell, cutoff


GRAD_CASES = [(seed, full, pbc) for seed in range(8) for full in (True, False)
              for pbc in ([True, True, True], MIXED_PBC, list(ALL_PBC[seed % 8]))]


@pytest.mark.parametrize("seed,full,pbc", GRAD_CASES)
def test_gradcheck_and_gradgradcheck_of_vectors_and_distances(seed, full, pbc):
    positions, cell, cutoff = small_system(seed, pbc)
    nl = tt.NeighborList(cutoff, full=full)
    x, h = as_tensors(positions, cell, grad=True)
    assert len(nl(x, h, pbc, "i")[0]) >= 2, f"seed {seed}"

    def vectors(x, h):
        return sorted_vectors(nl, x, h, pbc)

    assert torch.autograd.gradcheck(vectors, (x, h)), f"seed {seed}"
    assert torch.autograd.gradgradcheck(vectors, (x, h)), f"seed {seed}"


class LennardJones(torch.nn.Module):
    """E = sum over pairs d < rc of 4 eps ((sigma/d)^12 - (sigma/d)^6) - (the same at rc), each
    pair once (a full list counts both orientations, so it takes half): ASE's smooth=False
    energy."""

    def __init__(self, rc: float, full: bool, sigma: float = 1.0, epsilon: float = 1.0):
        super().__init__()
        self.neighbors = tt.NeighborList(rc, full=full)
        self.sigma = sigma
        self.epsilon = epsilon
        self.shift = 4 * epsilon * ((sigma / rc) ** 12 - (sigma / rc) ** 6)
        self.weight = 0.5 if full else 1.0

    def forward(self, positions: torch.Tensor, cell: torch.Tensor,
                periodic: List[bool]) -> torch.Tensor:
        d = self.neighbors(positions, cell, periodic, "d")[0]
        s6 = (self.sigma / d) ** 6
        return self.weight * (4 * self.epsilon * (s6 * s6 - s6) - self.shift).sum()


def energy_forces_stress(model, positions, cell, pbc):
    """E, -dE/dx and the stress (1/V) dE/d(strain): with x -> x (1 + e)^T and cell ->
    cell (1 + e)^T, dE/de = (dE/dx)^T x + (dE/dcell)^T cell (ASE's sign: positive when the
    energy rises under expansion)."""
    x, h = as_tensors(positions, cell, grad=True)
    energy = model(x, h, pbc)
    gx, gh = torch.autograd.grad(energy, (x, h))
    volume = abs(float(torch.linalg.det(h.detach())))
    stress = (gx.T @ x.detach() + gh.T @ h.detach()) / volume
    return float(energy), -gx.numpy(), stress.numpy()


def lj_system(seed, pbc):
    """Atoms at least 0.9 sigma apart in a random triclinic or skewed cell (by random sequential
    insertion), rc between 1.6 and 3 sigma away from every pair distance."""
    rng = np.random.default_rng(2000 + seed)
    cell = random_cell(rng, ["triclinic", "skewed"][seed % 2]) * rng.uniform(0.8, 1.2)
    target = int(rng.integers(4, 20))
    close = tricell.NeighborList(0.9)
    positions = np.empty((0, 3))
    for _ in range(200):
        candidate = np.vstack([positions, rng.uniform(0, 1, 3) @ cell])
        i = close.compute(candidate, cell, pbc, "i")
        if not np.any(i == len(candidate) - 1):
            positions = candidate
        if len(positions) == target:
            break
    rc = away_from_pairs(positions, cell, pbc, float(rng.uniform(1.6, 3.0)))
    return positions, cell, rc


LJ_CASES = [(seed, full, pbc) for seed in range(16) for full in (True, False)
            for pbc in ([True, True, True], MIXED_PBC)]


@pytest.mark.parametrize("seed,full,pbc", LJ_CASES)
def test_lennard_jones_forces_and_stress_match_ase(seed, full, pbc):
    positions, cell, rc = lj_system(seed, pbc)
    energy, forces, stress = energy_forces_stress(LennardJones(rc, full), positions, cell, pbc)

    atoms = Atoms("Ar%d" % len(positions), positions=positions, cell=cell, pbc=pbc)
    atoms.calc = AseLennardJones(sigma=1.0, epsilon=1.0, rc=rc, smooth=False)
    context = f"seed {seed}, {len(positions)} atoms, rc {rc}"
    assert energy == pytest.approx(atoms.get_potential_energy(), rel=1e-10, abs=1e-12), context
    reference = atoms.get_forces()
    np.testing.assert_allclose(forces, reference, rtol=1e-10,
                               atol=1e-10 * np.abs(reference).max(), err_msg=context)
    reference = voigt_6_to_full_3x3_stress(atoms.get_stress())
    np.testing.assert_allclose(stress, reference, rtol=1e-10,
                               atol=1e-10 * np.abs(reference).max(), err_msg=context)
    assert np.abs(forces).max() > 0 and np.abs(stress).max() > 0, context


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("full", [True, False])
def test_forces_and_stress_match_finite_differences(seed, full):
    pbc = [True, True, True] if seed % 2 else MIXED_PBC
    positions, cell, rc = lj_system(seed, pbc)
    model = LennardJones(rc, full)
    _, forces, stress = energy_forces_stress(model, positions, cell, pbc)

    def energy(positions, cell):
        return float(model(*as_tensors(positions, cell), pbc))

    step = 1e-5
    numerical = np.zeros_like(positions)
    for n in range(len(positions)):
        for a in range(3):
            shifted = np.zeros_like(positions)
            shifted[n, a] = step
            numerical[n, a] = -(energy(positions + shifted, cell) -
                                energy(positions - shifted, cell)) / (2 * step)
    np.testing.assert_allclose(forces, numerical, rtol=1e-6, atol=1e-6 * np.abs(forces).max(),
                               err_msg=f"seed {seed}")

    volume = abs(np.linalg.det(cell))
    strained = np.zeros((3, 3))
    for a in range(3):
        for b in range(3):
            e = np.zeros((3, 3))
            e[a, b] = step
            plus, minus = (np.eye(3) + e).T, (np.eye(3) - e).T
            strained[a, b] = (energy(positions @ plus, cell @ plus) -
                              energy(positions @ minus, cell @ minus)) / (2 * step * volume)
    np.testing.assert_allclose(stress, strained, rtol=1e-6, atol=1e-6 * np.abs(stress).max(),
                               err_msg=f"seed {seed}")


def run_three_times(model, positions, cell, pbc, dtype, weights=None):
    """(value, dvalue/dpositions, dvalue/dcell) of three calls: TorchScript profiles the first
    call and runs its optimised graph from the second on. A module returning several tensors
    gets the value sum(weights[k] * output[k]) for its backward pass."""
    results = []
    for _ in range(3):
        x, h = as_tensors(positions, cell, dtype=dtype, grad=True)
        outputs = model(x, h, pbc)
        if weights is None:
            value = outputs
        else:
            value = sum((w * o).sum() for w, o in zip(weights, outputs))
            outputs = torch.cat([o.reshape(-1) for o in outputs])
        results.append((outputs.detach(),) + torch.autograd.grad(value, (x, h)))
    return results


def scripted_and_reloaded(module):
    scripted = torch.jit.script(module)
    buffer = io.BytesIO()
    torch.jit.save(scripted, buffer)
    buffer.seek(0)
    return [scripted, torch.jit.load(buffer)]


class VectorsHolder(torch.nn.Module):
    """A module holding a NeighborList, returning D and d sorted by i, j, S."""

    def __init__(self, cutoff: float, full: bool):
        super().__init__()
        self.neighbors = tt.NeighborList(cutoff, full=full)

    def forward(self, positions: torch.Tensor, cell: torch.Tensor,
                periodic: List[bool]) -> List[torch.Tensor]:
        i, j, S, D, d = self.neighbors(positions, cell, periodic, "ijSDd")
        n = positions.shape[0]
        span = 2 * S.abs().max() + 1 if S.numel() > 0 else torch.tensor(1)
        key = ((i * n + j) * span + S[:, 0]) * span * span + S[:, 1] * span + S[:, 2]
        order = torch.argsort(key)
        return [D.index_select(0, order), d.index_select(0, order)]


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("full", [True, False])
@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
def test_torchscript_gives_the_eager_vectors_and_gradients_bit_for_bit(seed, full, dtype):
    pbc = [True, True, True] if seed % 2 else MIXED_PBC
    positions, cell, rc = lj_system(seed, pbc)
    eager = VectorsHolder(rc, full)
    pairs = len(eager(*as_tensors(positions, cell), pbc)[1])
    rng = np.random.default_rng(seed)
    weights = [torch.tensor(rng.normal(size=(pairs, 3)), dtype=dtype),
               torch.tensor(rng.normal(size=pairs), dtype=dtype)]
    expected = run_three_times(eager, positions, cell, pbc, dtype, weights)
    for model in scripted_and_reloaded(eager):
        for mine, theirs in zip(expected, run_three_times(model, positions, cell, pbc, dtype,
                                                          weights)):
            for a, b in zip(mine, theirs):
                assert a.dtype == dtype and torch.equal(a, b), f"seed {seed}"


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("full", [True, False])
@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
def test_torchscript_gives_the_eager_energy_and_gradients(seed, full, dtype):
    """The energy bit for bit; the gradients to rounding, since TorchScript's optimised graph
    differentiates the energy's own arithmetic (powers, quotients) by its own formulas."""
    pbc = [True, True, True] if seed % 2 else MIXED_PBC
    positions, cell, rc = lj_system(seed, pbc)
    eager = LennardJones(rc, full)
    expected = run_three_times(eager, positions, cell, pbc, dtype)
    tolerance = 1e-12 if dtype == torch.float64 else 1e-5
    for model in scripted_and_reloaded(eager):
        for mine, theirs in zip(expected, run_three_times(model, positions, cell, pbc, dtype)):
            assert torch.equal(mine[0], theirs[0]), f"seed {seed}"
            for a, b in zip(mine[1:], theirs[1:]):
                assert a.dtype == dtype
                torch.testing.assert_close(b, a, rtol=tolerance,
                                           atol=tolerance * float(a.abs().max()),
                                           msg=f"seed {seed}")


def test_a_scripted_list_returns_what_the_eager_one_returns():
    cell, positions, pbc, cutoff, _ = random_system(3)
    nl = tt.NeighborList(cutoff)
    scripted = torch.jit.script(nl)
    x, h = as_tensors(positions, cell)
    for mine, theirs in zip(nl(x, h, list(pbc)), scripted.compute(x, h, list(pbc), "ijSDd")):
        assert torch.equal(mine, theirs)
    assert [q.dtype for q in scripted(x, h, list(pbc), "dSi")] == [
        torch.float64, torch.int64, torch.int64]


@pytest.mark.parametrize("seed", range(96))
@pytest.mark.parametrize("full", [True, False])
@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
def test_pairs_match_the_native_module(seed, full, dtype):
    cell, positions, pbc, cutoff, _ = random_system(seed)
    x, h = as_tensors(positions, cell, dtype=dtype)
    i, j, S, D, d = tt.NeighborList(cutoff, full=full)(x, h, list(pbc), "ijSDd")
    assert [q.dtype for q in (i, j, S, D, d)] == [torch.int64] * 3 + [dtype] * 2
    assert S.shape == (len(i), 3) and D.shape == (len(i), 3) and d.shape == (len(i),)
    # The native module converts the same float32 values to float64 as the op does.
    native = tricell.NeighborList(cutoff, full=full).compute(
        x.numpy().astype(np.float64), h.numpy().astype(np.float64), pbc, "ijSdD")
    context = f"seed {seed}, {dtype}"
    mine = sort_pairs(i.numpy(), j.numpy(), S.numpy(), d.numpy(), D.numpy())
    theirs = sort_pairs(*native)
    if dtype == torch.float64:
        assert_same_pairs(mine, theirs, context)
    else:
        assert_same_pairs(mine[:3], theirs[:3], context)
        scale = 1 + np.abs(positions).max()
        np.testing.assert_allclose(mine[4], theirs[4], atol=1e-5 * scale, err_msg=context)


def test_empty_and_single_atom_systems():
    nl = tt.NeighborList(1.5)
    i, j, S, D, d = nl(torch.zeros(0, 3), torch.eye(3), [True, True, True])
    assert i.shape == (0,) and S.shape == (0, 3) and D.shape == (0, 3) and d.shape == (0,)
    i, j, S, D, d = nl(torch.zeros(1, 3), torch.eye(3), [True, True, True])
    assert len(i) == 18 and torch.all(i == 0) and torch.all(j == 0)
    np.testing.assert_allclose(np.sort(d.numpy()), np.sort(np.linalg.norm(S.numpy(), axis=1)),
                               rtol=1e-6)
    assert len(nl(torch.zeros(1, 3), torch.eye(3), [False, False, False], "i")[0]) == 0


def test_the_op_records_no_gradient_and_gradients_reach_each_input_alone():
    rng = np.random.default_rng(7)
    x, h = as_tensors(rng.uniform(0, 2, (6, 3)), np.eye(3) * 2 + rng.uniform(0, 0.3, (3, 3)),
                      grad=True)
    i, j, S = torch.ops.tricell.neighbor_pairs(x, h, [True, True, True], 1.5, True)
    assert len(i) > 0 and not (i.requires_grad or j.requires_grad or S.requires_grad)
    nl = tt.NeighborList(1.5)
    for wanted in (x, h):
        other = h.detach() if wanted is x else x.detach()
        inputs = (wanted, other) if wanted is x else (other, wanted)
        (grad,) = torch.autograd.grad(nl(*inputs, [True, True, True], "d")[0].sum(), wanted)
        assert torch.all(torch.isfinite(grad)) and grad.abs().max() > 0


PBC = [True, True, True]


@pytest.mark.parametrize("call,message", [
    (lambda nl: nl(torch.zeros(4, 2), torch.eye(3), PBC),
     r"positions must be an N x 3 tensor \(got shape \[4, 2\]\)"),
    (lambda nl: nl(torch.zeros(3), torch.eye(3), PBC),
     r"positions must be an N x 3 tensor \(got shape \[3\]\)"),
    (lambda nl: nl(torch.zeros(4, 3), torch.eye(3)[:2], PBC),
     r"cell must be a 3 x 3 tensor with the lattice vectors as rows \(got shape \[2, 3\]\)"),
    (lambda nl: nl(torch.zeros(4, 3, dtype=torch.int64), torch.eye(3), PBC),
     r"positions must be float32 or float64 \(got Long\)"),
    (lambda nl: nl(torch.zeros(4, 3, dtype=torch.float16), torch.eye(3), PBC),
     r"positions must be float32 or float64 \(got Half\)"),
    (lambda nl: nl(torch.zeros(4, 3), torch.eye(3, dtype=torch.int32), PBC),
     r"cell must be float32 or float64 \(got Int\)"),
    (lambda nl: nl(torch.zeros(4, 3), torch.eye(3, dtype=torch.float64), PBC),
     r"cell must have the dtype of positions \(got Double for cell and Float for positions\)"),
    (lambda nl: nl(torch.zeros(4, 3, device="meta"), torch.eye(3), PBC),
     r"positions must be on the CPU \(got device meta\)"),
    (lambda nl: nl(torch.zeros(4, 3), torch.eye(3), [True, False]),
     r"periodic must be three bools \(got 2\)"),
    (lambda nl: nl(torch.tensor([[0.0, 0, 0], [float("nan"), 0, 0]]), torch.eye(3), PBC),
     r"neighbor_pairs: position 1 is not finite"),
    (lambda nl: nl(torch.zeros(4, 3), torch.zeros(3, 3), PBC),
     r"neighbor_pairs: lattice vector a is zero but axis a is periodic"),
])
def test_bad_inputs_raise_messages_naming_the_argument(call, message):
    with pytest.raises(RuntimeError, match=message):
        call(tt.NeighborList(1.0))
    with pytest.raises(RuntimeError, match=message):
        call(torch.jit.script(tt.NeighborList(1.0)))


@pytest.mark.parametrize("cutoff,shown", [
    (float("nan"), "nan"), (float("inf"), "inf"), (-1.5, "-1.5"), (0.0, "0")])
def test_bad_cutoffs_raise_messages_naming_the_cutoff(cutoff, shown):
    message = rf"neighbor_pairs: cutoff must be finite and > 0 \(got {shown}\)"
    for nl in (tt.NeighborList(cutoff), torch.jit.script(tt.NeighborList(cutoff))):
        with pytest.raises(RuntimeError, match=message):
            nl(torch.zeros(2, 3), torch.eye(3), PBC)


def test_unknown_quantities_raise_messages_naming_the_letter():
    message = r"quantities: unknown letter 'x' in 'ijx' \(letters of 'ijSDd'\)"
    with pytest.raises(ValueError, match=message):
        tt.NeighborList(1.0)(torch.zeros(2, 3), torch.eye(3), PBC, "ijx")
    with pytest.raises(torch.jit.Error, match=message):
        torch.jit.script(tt.NeighborList(1.0))(torch.zeros(2, 3), torch.eye(3), PBC, "ijx")


# Every dtype but float32 and float64 (quantized ones aside), with the name torch's messages use.
SCALAR_TYPES = {torch.uint8: "Byte", torch.int8: "Char", torch.int16: "Short", torch.int32: "Int",
                torch.int64: "Long", torch.bool: "Bool", torch.float16: "Half",
                torch.bfloat16: "BFloat16", torch.complex32: "ComplexHalf",
                torch.complex64: "ComplexFloat", torch.complex128: "ComplexDouble"}


@pytest.mark.filterwarnings("ignore:ComplexHalf support is experimental")
@pytest.mark.parametrize("dtype", SCALAR_TYPES, ids=str)
def test_integer_complex_and_bool_tensors_name_the_argument_and_dtype(dtype):
    x, h = torch.zeros(4, 3), torch.eye(3)
    for points, cell, name in ((x.to(dtype), h, "positions"), (x, h.to(dtype), "cell")):
        got = SCALAR_TYPES[dtype]
        message = rf"neighbor_pairs: {name} must be float32 or float64 \(got {got}\)"
        for nl in (tt.NeighborList(1.0), torch.jit.script(tt.NeighborList(1.0))):
            with pytest.raises(RuntimeError, match=message):
                nl(points, cell, PBC)


def test_strided_and_transposed_tensors_give_the_pairs_of_contiguous_ones():
    cell, positions, pbc, cutoff, _ = random_system(3, atoms=30, pbc=(True, True, True))
    x, h = as_tensors(positions, cell)
    nl = tt.NeighborList(cutoff)
    expected = nl(x, h, list(pbc), "ijSd")
    wide = torch.zeros(len(positions), 9, dtype=torch.float64)
    wide[:, ::3] = x
    for points, box in ((wide[:, ::3], h), (x.t().contiguous().t(), h.t().contiguous().t()),
                        (torch.stack([x, x], 1).reshape(-1, 3)[::2],
                         torch.stack([h, h], 1).reshape(-1, 3)[::2])):
        assert not points.is_contiguous() or not box.is_contiguous()
        for mine, theirs in zip(nl(points, box, list(pbc), "ijSd"), expected):
            assert torch.equal(mine, theirs)
