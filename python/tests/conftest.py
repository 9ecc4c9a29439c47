"""Shared helpers of the Python tests: seeded random systems and pair-set comparison.

A random system is a cell (random triclinic, strongly skewed, or tiny), a periodicity, N
positions (some far outside the box, by tens of lattice vectors) and a cutoff (sometimes
several times the box). Every case comes from a fixed seed, which the assertion messages
name, so a failure can be replayed.
"""
import importlib
import itertools
import os
import resource

import numpy as np
import pytest

# A peer that misbehaves on some input (pymatgen's grid once took 22 GB for atoms far outside a
# skewed cell) must fail its test, not exhaust the shared machine. (Not under AddressSanitizer,
# which reserves terabytes of address space for its shadow memory.)
if "asan" not in os.environ.get("LD_PRELOAD", ""):
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, resource.getrlimit(resource.RLIMIT_AS)[1]))

# The runs against an installed copy (pip, in a virtual environment) name where it must be.
_expected_package_dir = os.environ.get("TRICELL_EXPECT_PACKAGE_DIR")
if _expected_package_dir:
    import tricell

    if not os.path.realpath(tricell.__file__).startswith(os.path.realpath(_expected_package_dir)):
        raise ImportError(f"tricell comes from {tricell.__file__}, not from the installed copy "
                          f"in {_expected_package_dir}")

ALL_PBC = list(itertools.product([False, True], repeat=3))
SOURCE_DIR = os.environ.get(
    "TRICELL_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(__file__))))


def random_cell(rng, kind):
    if kind == "triclinic":
        from ase.geometry import cellpar_to_cell

        lengths = rng.uniform(3.0, 8.0, 3)
        angles = rng.uniform(65.0, 115.0, 3)
        return cellpar_to_cell(np.concatenate([lengths, angles]))
    if kind == "skewed":  # tilts of up to three edge lengths
        edge = rng.uniform(3.0, 6.0)
        tilt = rng.uniform(-3.0, 3.0, 3) * edge
        return np.array([[edge, 0, 0], [tilt[0], edge, 0], [tilt[1], tilt[2], edge]])
    if kind == "tiny":  # a cell much smaller than the cutoff
        return np.diag(rng.uniform(0.8, 1.6, 3)) + rng.uniform(-0.3, 0.3, (3, 3))
    raise ValueError(kind)


def random_system(seed, pbc=None, kind=None, atoms=None, far=40):
    """(cell rows, positions, pbc, cutoff, numbers) for one seed; about 30% of the atoms are
    moved by up to `far` lattice vectors along each axis."""
    rng = np.random.default_rng(seed)
    kind = kind or ["triclinic", "skewed", "tiny"][seed % 3]
    cell = random_cell(rng, kind)
    if pbc is None:
        pbc = ALL_PBC[seed % 8]
    n = atoms if atoms is not None else int(rng.integers(1, 25))
    fractional = rng.uniform(0.0, 1.0, (n, 3))
    # Some atoms far outside the box, by whole and fractional lattice vectors.
    moved = rng.random(n) < 0.3
    fractional[moved] += rng.integers(-far, far + 1, (int(moved.sum()), 3)) + rng.uniform(
        -1, 1, (int(moved.sum()), 3))
    positions = fractional @ cell
    widths = 1.0 / np.linalg.norm(np.linalg.inv(cell), axis=0)
    cutoff = float(rng.uniform(0.3, 2.5) * widths.min())
    if kind == "tiny":
        cutoff = float(rng.uniform(2.0, 4.0))
    numbers = rng.choice([1, 8, 14], n)
    return cell, positions, tuple(bool(p) for p in pbc), cutoff, numbers


def sort_pairs(i, j, S, *rest):
    """The columns reordered by i, then j, then S."""
    i, j, S = np.asarray(i), np.asarray(j), np.asarray(S)
    order = np.lexsort((S[:, 2], S[:, 1], S[:, 0], j, i))
    return (i[order], j[order], S[order]) + tuple(np.asarray(r)[order] for r in rest)


def drop_near(limit, tol, i, j, S, d, *rest):
    """Drops the pairs with |d - limit| < tol (where two codes may round differently)."""
    keep = np.abs(np.asarray(d) - limit) >= tol
    return tuple(np.asarray(c)[keep] for c in (i, j, S, d) + rest)


def assert_same_pairs(mine, theirs, context):
    """Both (i, j, S, d, D) sorted by i, j, S: i, j, S exactly equal, d and D close."""
    assert len(mine[0]) == len(theirs[0]), f"{context}: {len(mine[0])} pairs vs {len(theirs[0])}"
    for k, name in enumerate("ijS"):
        np.testing.assert_array_equal(mine[k], theirs[k], err_msg=f"{context}: {name}")
    for k, name in [(3, "d"), (4, "D")][: len(mine) - 3]:
        np.testing.assert_allclose(mine[k], theirs[k], rtol=1e-10, atol=1e-9,
                                   err_msg=f"{context}: {name}")


@pytest.fixture
def source_dir():
    return SOURCE_DIR


def import_torch_front(module="tricell.torch"):
    """The torch front `module`; the calling test file skips itself, with the reason, when
    PyTorch is missing or the op library was not built (no libtorch, or the sanitizer build).
    Any other failure to import is an error."""
    try:
        return importlib.import_module(module)
    except ImportError as error:
        if error.name in ("tricell._tricell_torch", "torch"):
            pytest.skip(str(error), allow_module_level=True)
        raise


def brute_force_pairs(positions, cell, pbc, cutoff):
    """The full list's (i, j, S) of one system by brute force, as a set: the positions wrapped
    along the periodic axes, every image the widths allow, S mapped back to the given
    positions."""
    periodic = np.array(pbc)
    moved = np.where(periodic, np.floor(positions @ np.linalg.inv(cell)), 0).astype(int)
    wrapped = positions - moved @ cell
    widths = 1.0 / np.linalg.norm(np.linalg.inv(cell), axis=0)
    reach = np.where(periodic, np.ceil(cutoff / widths).astype(int) + 1, 0)
    images = np.array([(a, b, c) for a in range(-reach[0], reach[0] + 1)
                       for b in range(-reach[1], reach[1] + 1)
                       for c in range(-reach[2], reach[2] + 1)])
    found = set()
    for i in range(len(positions)):
        d = wrapped[None, :, :] - wrapped[i] + (images @ cell)[:, None, :]
        for image, j in zip(*np.nonzero(np.linalg.norm(d, axis=2) < cutoff)):
            if i != j or images[image].any():
                S = images[image] - moved[j] + moved[i]
                found.add((i, int(j), tuple(int(v) for v in S)))
    return found
