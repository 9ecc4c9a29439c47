"""tricell.Rdf against ASE's get_rdf (ase.ga.utilities) where ASE's assumptions hold (rmax
below half the cell height, minimum image), against a numpy brute force over every image past
half the cell where ASE refuses, averaged over the frames of examples/data/argon.xyz; and
tricell.nearest_neighbors against a brute force. Fixed seeds, named in the messages."""
import itertools
import math
import os

import numpy as np
import pytest

import tricell
from conftest import SOURCE_DIR

ase = pytest.importorskip("ase")
from ase import Atoms  # noqa: E402
from ase.ga.utilities import get_rdf  # noqa: E402


def random_atoms(seed, n=30, repeat=(2, 2, 2)):
    rng = np.random.default_rng(seed)
    from ase.geometry import cellpar_to_cell

    cell = cellpar_to_cell(np.concatenate([rng.uniform(5.0, 8.0, 3), rng.uniform(70, 110, 3)]))
    numbers = rng.choice([8, 14, 26], n)
    atoms = Atoms(numbers=numbers, cell=cell, pbc=True,
                  scaled_positions=rng.uniform(0, 1, (n, 3)))
    return atoms.repeat(repeat)


def heights(atoms):
    cell = np.array(atoms.cell)
    volume = abs(np.linalg.det(cell))
    return [volume / np.linalg.norm(np.cross(cell[(k + 1) % 3], cell[(k + 2) % 3]))
            for k in range(3)]


@pytest.mark.parametrize("seed", range(5))
def test_total_and_partial_match_ase_below_half_the_cell(seed):
    atoms = random_atoms(seed)
    rmax = 0.45 * min(heights(atoms))
    bins = 30
    rdf = tricell.Rdf(rmax, bins)
    rdf.add_frame(atoms.positions, np.array(atoms.cell), True, atoms.numbers)
    r, g, n = rdf.total()
    ase_g, ase_r = get_rdf(atoms, rmax, bins)
    np.testing.assert_allclose(r, ase_r, rtol=1e-12, err_msg=f"seed {seed}")
    np.testing.assert_allclose(g, ase_g, rtol=1e-10, atol=1e-12, err_msg=f"seed {seed}")
    counts = np.bincount(atoms.numbers)
    for a, b in itertools.product([8, 14, 26], repeat=2):
        _, g_ab, _ = rdf.partial(a, b)
        ase_ab = get_rdf(atoms, rmax, bins, elements=(a, b), no_dists=True)
        # ASE normalises with N_A * N / V, tricell with N_A * N_B / V.
        np.testing.assert_allclose(g_ab * counts[b] / len(atoms), ase_ab, rtol=1e-10,
                                   atol=1e-12, err_msg=f"seed {seed}, pair {a}-{b}")


def brute_force_rdf(atoms, rmax, bins):
    """Ordered pairs over every image with d < rmax, histogrammed, normalised like tricell."""
    cell = np.array(atoms.cell)
    x = atoms.positions
    reach = [int(math.ceil(rmax / h)) + 1 for h in heights(atoms)]
    shifts = np.array(list(itertools.product(*[range(-m, m + 1) for m in reach])))
    edges = rmax * np.arange(bins + 1) / bins
    counts = np.zeros(bins)
    for i in range(len(atoms)):
        d = np.linalg.norm(x[None, :, :] - x[i] + (shifts @ cell)[:, None, :], axis=2).ravel()
        d = d[(d < rmax) & (d > 0)]
        counts += np.histogram(d, bins=edges)[0]
    n = len(atoms)
    shells = 4 / 3 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    return counts * abs(np.linalg.det(cell)) / (n * n * shells), np.cumsum(counts) / n


@pytest.mark.parametrize("seed", range(4))
def test_past_half_the_cell_where_ase_refuses(seed):
    atoms = random_atoms(100 + seed, n=12, repeat=(1, 1, 1))
    rmax = 1.7 * min(heights(atoms))  # beyond the whole cell
    with pytest.raises(AssertionError, match="not large enough"):
        get_rdf(atoms, rmax, 20)
    rdf = tricell.Rdf(rmax, 20)
    rdf.add_frame(atoms.positions, np.array(atoms.cell))
    _, g, n = rdf.total()
    want_g, want_n = brute_force_rdf(atoms, rmax, 20)
    np.testing.assert_allclose(g, want_g, rtol=1e-10, err_msg=f"seed {seed}")
    np.testing.assert_allclose(n, want_n, rtol=1e-10, err_msg=f"seed {seed}")


def test_argon_trajectory_average_matches_ase_frame_by_frame():
    from ase.io import read

    frames = read(os.path.join(SOURCE_DIR, "examples", "data", "argon.xyz"), ":")
    assert len(frames) == 10
    rdf = tricell.Rdf(10.0, 50, threads=2)
    expected = np.zeros(50)
    for atoms in frames:
        rdf.add_frame(atoms.positions, np.array(atoms.cell), atoms.pbc.tolist(), atoms.numbers)
        expected += get_rdf(atoms, 10.0, 50, no_dists=True)
    assert rdf.frames == 10
    assert rdf.species == [18]
    _, g, n = rdf.total()
    np.testing.assert_allclose(g, expected / 10, rtol=1e-10, atol=1e-12)
    assert 8 < n[24] < 16  # about twelve neighbours in the first shell (r < 5 A) of liquid argon


def test_rdf_errors_are_value_errors_with_the_library_message():
    with pytest.raises(ValueError, match=r"RdfOptions::rmax must be finite and > 0 \(got -1\)"):
        tricell.Rdf(-1.0, 10)
    rdf = tricell.Rdf(2.0, 10)
    with pytest.raises(ValueError, match="axis c of the frame is not periodic"):
        rdf.add_frame([[0, 0, 0]], np.eye(3) * 4, [True, True, False])
    with pytest.raises(ValueError, match="no frame was added"):
        rdf.total()
    rdf.add_frame([[0, 0, 0], [1, 1, 1]], np.eye(3) * 4, True, [1, 2])
    with pytest.raises(ValueError, match=r"species 3 never occurred \(species seen: 1, 2\)"):
        rdf.partial(1, 3)


@pytest.mark.parametrize("seed", range(6))
def test_nearest_neighbors_match_brute_force(seed):
    rng = np.random.default_rng(seed)
    cell = np.diag(rng.uniform(3, 5, 3)) + rng.uniform(-1, 1, (3, 3))
    x = rng.uniform(0, 1, (15, 3)) @ cell
    k = int(rng.integers(1, 40))
    j, S, d = tricell.nearest_neighbors(x, cell, True, k)
    assert j.shape == (15, k) and S.shape == (15, k, 3) and d.shape == (15, k)
    shifts = np.array(list(itertools.product(range(-6, 7), repeat=3)))
    for i in range(len(x)):
        all_d = np.linalg.norm(x[None, :, :] - x[i] + (shifts @ cell)[:, None, :], axis=2)
        all_d = np.sort(all_d.ravel())[1:]  # without the atom itself
        np.testing.assert_allclose(d[i], all_d[:k], rtol=1e-12, err_msg=f"seed {seed}")
        recomputed = np.linalg.norm(x[j[i]] - x[i] + S[i] @ cell, axis=1)
        np.testing.assert_allclose(recomputed, d[i], rtol=1e-12, err_msg=f"seed {seed}")
