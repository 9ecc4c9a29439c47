"""tricell.verify: tricell's own lists and ASE's pass on seeded random systems (full and half,
every backend, radii and species tables); each kind of defect planted in a correct list fails
with words that name it; bad arguments raise TypeError or ValueError naming the argument."""
import numpy as np
import pytest

import tricell

ase = pytest.importorskip("ase")
from ase.neighborlist import neighbor_list as ase_neighbor_list  # noqa: E402


def random_system(seed, n=None):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 60)) if n is None else n
    cell = np.diag(rng.uniform(4, 8, 3)) + rng.uniform(-1.5, 1.5, (3, 3))
    points = rng.uniform(0, 1, (n, 3)) @ cell
    pbc = [bool(b) for b in rng.integers(0, 2, 3)] if seed % 3 == 0 else [True, True, True]
    cutoff = float(rng.uniform(1.5, 4.5))
    return points, cell, pbc, cutoff


@pytest.mark.parametrize("seed", range(24))
def test_own_lists_pass_on_every_backend(seed):
    points, cell, pbc, cutoff = random_system(seed)
    backend = tricell.backends()[seed % len(tricell.backends())]
    half = seed % 2 == 1
    nl = tricell.NeighborList(cutoff, full=not half, backend=backend)
    i, j, S, d, D = nl.compute(points, cell, pbc, "ijSdD")
    report = tricell.verify(points, cell, i, j, S, d, D, cutoff=cutoff, half=half, periodic=pbc)
    assert report.ok, report.message
    assert report and report.entries == len(i)
    assert report.reference == "brute force"
    assert report.message.startswith("ok: ")


@pytest.mark.parametrize("seed", range(8))
def test_variable_cutoffs(seed):
    points, cell, pbc, cutoff = random_system(seed)
    n = len(points)
    rng = np.random.default_rng(seed)
    if seed % 2 == 0:
        radii = rng.uniform(0.3, 1.5, n)
        i, j, S = tricell.NeighborList(None).compute(points, cell, pbc, "ijS", radii=radii)
        report = tricell.verify(points, cell, i, j, S, radii=radii, periodic=pbc)
    else:
        species = rng.integers(0, 3, n)
        table = {(0, 0): 2.0, (0, 1): 3.0, (2, 2): 2.5}
        i, j, S = tricell.NeighborList(table).compute(points, cell, pbc, "ijS", species=species)
        report = tricell.verify(points, cell, i, j, S, cutoff=table, species=species,
                                periodic=pbc)
    assert report.ok, report.message


@pytest.mark.parametrize("seed", range(16))
def test_ase_lists_pass(seed):
    points, cell, pbc, cutoff = random_system(seed)
    atoms = ase.Atoms("H" * len(points), positions=points, cell=cell, pbc=pbc)
    i, j, S, d, D = ase_neighbor_list("ijSdD", atoms, cutoff)
    report = tricell.verify(points, cell, i, j, S, d, D, cutoff=cutoff, periodic=pbc)
    assert report.ok, report.message
    assert report.entries == len(i)


def ase_list():
    points, cell, pbc, cutoff = random_system(5, n=40)
    atoms = ase.Atoms("H" * len(points), positions=points, cell=cell, pbc=pbc)
    return (points, cell, pbc, cutoff) + ase_neighbor_list("ijSdD", atoms, cutoff)


def test_corrupted_ase_lists_are_reported():
    points, cell, pbc, cutoff, i, j, S, d, D = ase_list()
    assert len(i) > 20

    def check(i=i, j=j, S=S, d=d, D=D, half=False):
        report = tricell.verify(points, cell, i, j, S, d, D, cutoff=cutoff, half=half,
                                periodic=pbc)
        assert not report
        return report

    r = check(i=np.delete(i, 7), j=np.delete(j, 7), S=np.delete(S, 7, 0), d=np.delete(d, 7),
              D=np.delete(D, 7, 0))
    assert r.missing == 1
    assert r.message == "pair (%d, %d, [%d %d %d]) at distance %.6g < cutoff %.6g is missing" % (
        i[7], j[7], *S[7], d[7], cutoff)

    dup = lambda a: np.concatenate([a, a[3:4]])  # noqa: E731
    r = check(i=dup(i), j=dup(j), S=dup(S), d=dup(d), D=dup(D))
    assert r.duplicates == 1 and "is listed twice (entries 3 and %d)" % len(i) in r.message

    flipped = S.copy()
    k = int(np.flatnonzero(np.any(S != 0, axis=1))[0])
    flipped[k] = -flipped[k]
    r = check(S=flipped)
    assert r.wrong_values == 1 and "entry %d " % k in r.message

    add = lambda a, v: np.concatenate([a, np.asarray(v, dtype=a.dtype)])  # noqa: E731
    r = check(i=add(i, [0]), j=add(j, [0]), S=add(S, [[0, 0, 0]]), d=add(d, [0.0]),
              D=add(D, [[0.0, 0.0, 0.0]]))
    assert "entry %d (0, 0, [0 0 0]): an atom paired with itself" % len(i) in r.message

    wrong = d.copy()
    wrong[2] += 0.1
    r = check(d=wrong)
    assert r.message.startswith("entry 2 (") and " but the positions give " in r.message

    out = j.copy()
    out[4] = len(points)
    r = check(j=out)
    assert "index %d is out of range for %d positions" % (len(points), len(points)) in r.message
    assert r.rule_breaks == 1


def test_open_axes_and_half_lists():
    points, cell, _, cutoff = random_system(7, n=30)
    pbc = [True, True, False]
    i, j, S, d = tricell.NeighborList(cutoff, full=False).compute(points, cell, pbc, "ijSd")
    assert tricell.verify(points, cell, i, j, S, d, cutoff=cutoff, half=True, periodic=pbc)
    # the other orientation of every pair: still a half list
    assert tricell.verify(points, cell, j, i, -S, d, cutoff=cutoff, half=True, periodic=pbc)
    # both orientations of a pair
    r = tricell.verify(points, cell, np.append(i, j[0]), np.append(j, i[0]),
                       np.vstack([S, -S[:1]]), cutoff=cutoff, half=True, periodic=pbc)
    assert "in both orientations; a half list holds each pair once" in r.message
    # a half list where a full one is expected
    r = tricell.verify(points, cell, i, j, S, cutoff=cutoff, periodic=pbc)
    assert r.missing == len(i) and not r
    bad = S.copy()
    bad[1, 2] = 2
    r = tricell.verify(points, cell, i, j, bad, cutoff=cutoff, half=True, periodic=pbc)
    assert "a shift along the open axis c (Sc = 2)" in r.message


def test_bad_arguments_name_the_argument():
    points, cell, pbc, cutoff, i, j, S, d, D = ase_list()
    with pytest.raises(ValueError, match=r"j must have shape \(%d,\), one entry per entry of i" %
                       len(i)):
        tricell.verify(points, cell, i, j[:-1], S, cutoff=cutoff, periodic=pbc)
    with pytest.raises(ValueError, match=r"S must have shape \(%d, 3\)" % len(i)):
        tricell.verify(points, cell, i, j, S[:, :2], cutoff=cutoff, periodic=pbc)
    with pytest.raises(ValueError, match=r"d must have shape"):
        tricell.verify(points, cell, i, j, S, d[:3], cutoff=cutoff, periodic=pbc)
    with pytest.raises(TypeError, match="i must be integers, not float"):
        tricell.verify(points, cell, i.astype(float), j, S, cutoff=cutoff, periodic=pbc)
    with pytest.raises(TypeError, match="S must be integers, not complex"):
        tricell.verify(points, cell, i, j, S.astype(complex), cutoff=cutoff, periodic=pbc)
    with pytest.raises(ValueError, match="beyond a 64-bit signed integer"):
        tricell.verify(points, cell, i.astype(np.uint64) + np.uint64(2**63), j, S, cutoff=cutoff,
                       periodic=pbc)
    nan = points.copy()
    nan[3, 1] = np.nan
    with pytest.raises(ValueError, match="position 3 is not finite"):
        tricell.verify(nan, cell, i, j, S, cutoff=cutoff, periodic=pbc)
    with pytest.raises(ValueError, match="cutoff must be > 0"):
        tricell.verify(points, cell, i, j, S, cutoff=-1.0, periodic=pbc)
    with pytest.raises(ValueError, match="verify needs cutoff="):
        tricell.verify(points, cell, i, j, S, periodic=pbc)
    with pytest.raises(ValueError, match="S= is needed"):
        tricell.verify(points, cell, i, j, cutoff=cutoff, periodic=True)
    # a NaN distance is a wrong value of the list, not a bad argument
    nan_d = d.copy()
    nan_d[0] = np.nan
    r = tricell.verify(points, cell, i, j, S, nan_d, cutoff=cutoff, periodic=pbc)
    assert not r and r.wrong_values == 1 and "distance nan" in r.message
