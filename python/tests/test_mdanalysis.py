"""tricell.mdanalysis against Debian's MDAnalysis (its brute-force method and FastNS) and against
a float64 brute force over lattice images, on random systems with fixed seeds in every box shape
(none, orthogonal, triclinic), positions in float32 and float64.

MDAnalysis rounds positions to float32 and its box to float32 before it computes, so pairs within
a small window of a cutoff may differ from tricell's float64 ones: the comparisons with MDAnalysis
skip pairs within TOLERANCE of max_cutoff or min_cutoff, and compare distances to TOLERANCE. The
comparisons with the float64 brute force skip only pairs within 1e-9 of a cutoff.
"""
import subprocess
import sys

import numpy as np
import pytest

MDAnalysis = pytest.importorskip("MDAnalysis")
from MDAnalysis.analysis.rdf import InterRDF  # noqa: E402
from MDAnalysis.coordinates.memory import MemoryReader  # noqa: E402
from MDAnalysis.lib import distances as mda_distances  # noqa: E402
from MDAnalysis.lib import nsgrid as mda_nsgrid  # noqa: E402
from MDAnalysis.lib.mdamath import triclinic_vectors  # noqa: E402

import tricell.mdanalysis as tm  # noqa: E402

TOLERANCE = 1e-4  # Angstrom: float32 rounding of positions up to 100 Angstrom, with margin
BOX_KINDS = ["none", "orthogonal", "triclinic"]


def random_box(rng, kind):
    if kind == "none":
        return None
    lengths = rng.uniform(12.0, 20.0, 3)
    if kind == "orthogonal":
        return np.concatenate([lengths, [90.0, 90.0, 90.0]])
    while True:
        box = np.concatenate([lengths, rng.uniform(60.0, 120.0, 3)])
        if triclinic_vectors(box, dtype=np.float64).any():
            return box


def widths(matrix):
    """Perpendicular widths of the cell with the lattice vectors as rows."""
    return 1.0 / np.linalg.norm(np.linalg.inv(matrix), axis=0)


def random_points(rng, n, box, far):
    """n positions in the box (or a 15 Angstrom cube), a third of them moved by up to `far`
    box lengths."""
    matrix = np.diag([15.0] * 3) if box is None else triclinic_vectors(box, dtype=np.float64)
    fractional = rng.uniform(0.0, 1.0, (n, 3))
    moved = rng.random(n) < 1 / 3
    fractional[moved] += rng.integers(-far, far + 1, (int(moved.sum()), 3))
    return fractional @ matrix


def brute_force(reference, configuration, box, max_cutoff, self_pairs=False):
    """{(i, j): d} of the minimum-image distances d <= max_cutoff, in float64, over every image
    that can come within max_cutoff."""
    reference = np.asarray(reference, dtype=np.float64)
    configuration = np.asarray(configuration, dtype=np.float64)
    D = configuration[None, :, :] - reference[:, None, :]
    if box is None:
        d = np.linalg.norm(D, axis=2)
    else:
        matrix = triclinic_vectors(np.asarray(box, dtype=np.float64), dtype=np.float64)
        inverse = np.linalg.inv(matrix)
        fractional = D @ inverse
        D = (fractional - np.round(fractional)) @ matrix  # fractional parts in [-1/2, 1/2]
        reach = np.floor(max_cutoff / widths(matrix) + 0.5).astype(int) + 1
        d = np.full(D.shape[:2], np.inf)
        for a in range(-reach[0], reach[0] + 1):
            for b in range(-reach[1], reach[1] + 1):
                for c in range(-reach[2], reach[2] + 1):
                    image = np.array([a, b, c], dtype=np.float64) @ matrix
                    d = np.minimum(d, np.linalg.norm(D + image, axis=2))
    if self_pairs:
        d[np.tril_indices(len(reference))] = np.inf
    i, j = np.nonzero(d <= max_cutoff)
    return {(a, b): d[a, b] for a, b in zip(i.tolist(), j.tolist())}


def as_dict(pairs, distances):
    assert pairs.dtype == np.intp and pairs.ndim == 2 and pairs.shape[1] == 2, pairs.shape
    assert distances.dtype == np.float64 and distances.shape == (len(pairs),), distances.shape
    keys = [tuple(p) for p in pairs.tolist()]
    assert len(set(keys)) == len(keys), "a pair is listed twice"
    return dict(zip(keys, distances.tolist()))


def assert_same_pairs(mine, theirs, cutoffs, tolerance, context):
    """The same pairs, except those within `tolerance` of a cutoff; the same distances."""
    def near(d):
        return any(abs(d - c) <= tolerance for c in cutoffs if c is not None)

    for key in set(mine) ^ set(theirs):
        d = mine.get(key, theirs.get(key))
        assert near(d), (f"{context}: pair {key} at {d!r} is "
                         f"{'extra' if key in mine else 'missing'} (cutoffs {cutoffs})")
    for key in set(mine) & set(theirs):
        assert abs(mine[key] - theirs[key]) <= tolerance, (
            f"{context}: pair {key}: distance {mine[key]!r}, expected {theirs[key]!r}")


def random_case(seed, kind, dtype):
    rng = np.random.default_rng(seed)
    box = random_box(rng, kind)
    n, m = int(rng.integers(1, 120)), int(rng.integers(1, 160))
    reference = random_points(rng, n, box, far=3).astype(dtype)
    configuration = random_points(rng, m, box, far=3).astype(dtype)
    if seed % 4 == 1:  # one set twice, as InterRDF of a group with itself passes it
        configuration = reference.copy()
    limit = 7.5 if box is None else 0.45 * widths(triclinic_vectors(box, dtype=np.float64)).min()
    max_cutoff = float(rng.uniform(0.5, limit))
    min_cutoff = None if seed % 3 == 0 else float(rng.uniform(-0.5, max_cutoff))
    box = None if box is None else box.astype(dtype)
    return reference, configuration, box, max_cutoff, min_cutoff


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("kind", BOX_KINDS)
@pytest.mark.parametrize("function", ["capped_distance", "self_capped_distance"])
def test_matches_mdanalysis_and_brute_force(function, kind, dtype):
    within_one_set = function == "self_capped_distance"
    for seed in range(16):
        reference, configuration, box, max_cutoff, min_cutoff = random_case(seed, kind, dtype)
        context = f"{function}, seed {seed}, box {kind}, {np.dtype(dtype).name}"
        sets = (reference,) if within_one_set else (reference, configuration)
        arguments = (*sets, max_cutoff, min_cutoff, box)
        pairs, distances = getattr(tm, function)(*arguments)
        mine = as_dict(pairs, distances)
        if within_one_set:
            assert all(i < j for i, j in mine), f"{context}: a pair with i >= j"
        theirs = as_dict(*getattr(mda_distances, function)(*arguments, method="bruteforce"))
        assert_same_pairs(mine, theirs, [max_cutoff, min_cutoff], TOLERANCE, context)
        exact = {key: d for key, d in brute_force(reference, sets[-1], box, max_cutoff,
                                                  self_pairs=within_one_set).items()
                 if min_cutoff is None or d > min_cutoff}
        assert_same_pairs(mine, exact, [max_cutoff, min_cutoff], 1e-9, context + " (float64)")
        np.testing.assert_array_equal(pairs, getattr(tm, function)(*arguments,
                                                                   return_distances=False))


@pytest.mark.parametrize("kind", ["orthogonal", "triclinic"])
def test_cutoffs_beyond_half_the_box_give_the_nearest_image(kind):
    """MDAnalysis's FastNS refuses these cutoffs; the distance is still the minimum image's,
    each pair once."""
    for seed in range(12):
        rng = np.random.default_rng(1000 + seed)
        box = random_box(rng, kind)
        width = widths(triclinic_vectors(box, dtype=np.float64)).min()
        max_cutoff = float(rng.uniform(0.55, 2.5)) * width
        reference = random_points(rng, int(rng.integers(1, 40)), box, far=2)
        configuration = random_points(rng, int(rng.integers(1, 50)), box, far=2)
        context = f"seed {1000 + seed}, box {kind}, cutoff {max_cutoff:.3f} (width {width:.3f})"
        with pytest.raises(ValueError, match="too large for box"):
            mda_nsgrid.FastNS(max_cutoff, configuration.astype(np.float32),
                              box.astype(np.float32))
        mine = as_dict(*tm.capped_distance(reference, configuration, max_cutoff, box=box))
        exact = brute_force(reference, configuration, box, max_cutoff)
        assert_same_pairs(mine, exact, [max_cutoff], 1e-9, context)
        mine = as_dict(*tm.self_capped_distance(configuration, max_cutoff, box=box))
        exact = brute_force(configuration, configuration, box, max_cutoff, self_pairs=True)
        assert_same_pairs(mine, exact, [max_cutoff], 1e-9, context + " (self)")
        mine = as_dict(*tm.capped_distance(configuration, configuration, max_cutoff, box=box))
        exact = brute_force(configuration, configuration, box, max_cutoff)
        assert_same_pairs(mine, exact, [max_cutoff], 1e-9, context + " (one set twice)")
        results = tm.FastNS(max_cutoff, configuration, box).search(reference)
        mine = as_dict(results.get_pairs(), results.get_pair_distances())
        assert_same_pairs(mine, brute_force(reference, configuration, box, max_cutoff),
                          [max_cutoff], 1e-9, context + " (FastNS)")


def listed(result):
    """{(i, j): d} of a result with distances (the order of the pairs is the search's)."""
    return as_dict(*result) if isinstance(result, tuple) else as_dict(
        result.get_pairs(), result.get_pair_distances())


def test_exact_at_the_cutoff_in_float64():
    """d <= max_cutoff and d > min_cutoff decided on the float64 distance, to the last bit."""
    points = np.array([[0.0, 0.0, 0.0], [3.0, 4.0, 0.0], [0.0, 0.0, 13.0]])  # d = 5, 13
    box = [20.0, 20.0, 20.0, 90.0, 90.0, 90.0]  # (0, 0, 13) is 7 from the origin through z
    below = np.nextafter(5.0, 0.0)
    assert listed(tm.self_capped_distance(points, 5.0, box=box)) == {(0, 1): 5.0}
    assert listed(tm.self_capped_distance(points, below, box=box)) == {}
    assert listed(tm.self_capped_distance(points, 7.0, min_cutoff=5.0, box=box)) == {(0, 2): 7.0}
    assert listed(tm.self_capped_distance(points, 7.0, min_cutoff=below, box=box)) == {
        (0, 1): 5.0, (0, 2): 7.0}
    assert listed(tm.capped_distance(points[:1], points, 7.0, box=box)) == {
        (0, 0): 0.0, (0, 1): 5.0, (0, 2): 7.0}
    assert listed(tm.capped_distance(points, points[:1], below, box=box)) == {(0, 0): 0.0}
    assert listed(tm.capped_distance(points[:1], points, 7.0)) == {(0, 0): 0.0, (0, 1): 5.0}
    assert listed(tm.capped_distance(points, points, 0.0)) == {(0, 0): 0, (1, 1): 0, (2, 2): 0}
    assert listed(tm.capped_distance(points, points, 5.0, min_cutoff=0.0, box=box)) == {
        (0, 1): 5.0, (1, 0): 5.0}
    assert listed(tm.FastNS(5.0, points, np.array(box)).self_search()) == {(0, 1): 5.0}
    # The farthest a nearest image can be: half the cell's diagonal; without a box, the two
    # ends of the points' bounding box's diagonal.
    corner = np.array([[0.0, 0.0, 0.0], [5.0, 5.0, 5.0]])
    assert listed(tm.self_capped_distance(corner, 1e6, box=[10, 10, 10, 90, 90, 90])) == {
        (0, 1): np.sqrt(75.0)}
    assert listed(tm.self_capped_distance(corner, 1e6)) == {(0, 1): np.sqrt(75.0)}
    assert listed(tm.FastNS(below, points, np.array(box)).search(points[1:2])) == {(0, 1): 0.0}


@pytest.mark.parametrize("kind", ["orthogonal", "triclinic"])
def test_fastns_matches_mdanalysis_fastns(kind):
    for seed in range(8):
        rng = np.random.default_rng(2000 + seed)
        box = random_box(rng, kind).astype(np.float32)
        coords = random_points(rng, int(rng.integers(2, 300)), box, far=1).astype(np.float32)
        queries = random_points(rng, int(rng.integers(1, 100)), box, far=1).astype(np.float32)
        cutoff = float(rng.uniform(1.0, 0.45 * widths(triclinic_vectors(box, np.float64)).min()))
        context = f"seed {2000 + seed}, box {kind}"
        mine, theirs = tm.FastNS(cutoff, coords, box), mda_nsgrid.FastNS(cutoff, coords, box)
        assert mine.cutoff == cutoff
        for search in ("search", "self_search"):
            args = (queries,) if search == "search" else ()
            a, b = getattr(mine, search)(*args), getattr(theirs, search)(*args)
            pairs = b.get_pairs()
            if search == "self_search":  # MDAnalysis's grid gives either orientation
                pairs = np.sort(pairs, axis=1)
            assert_same_pairs(as_dict(a.get_pairs(), a.get_pair_distances()),
                              as_dict(pairs, b.get_pair_distances()), [cutoff], TOLERANCE,
                              f"{context}, {search}")


def test_fastns_without_pbc_ignores_the_box():
    rng = np.random.default_rng(7)
    coords = rng.uniform(0, 10, (50, 3))
    for box in (None, np.array([10, 10, 10, 90, 90, 90], dtype=np.float32)):
        results = tm.FastNS(3.0, coords, box, pbc=False).self_search()
        mine = as_dict(results.get_pairs(), results.get_pair_distances())
        assert_same_pairs(mine, brute_force(coords, coords, None, 3.0, self_pairs=True), [3.0],
                          1e-9, f"pbc=False, box {box}")


def test_shapes_atomgroups_and_empty_results():
    u = MDAnalysis.Universe.empty(4, trajectory=True)
    u.atoms.positions = np.array([[0, 0, 0], [1, 0, 0], [0, 2, 0], [9, 9, 9]], dtype=np.float32)
    u.dimensions = np.array([10, 10, 10, 90, 90, 90], dtype=np.float32)
    found = listed(tm.capped_distance(u.atoms[:1], u.atoms, 2.5, box=u.dimensions))
    assert found == pytest.approx({(0, 0): 0, (0, 1): 1, (0, 2): 2, (0, 3): np.sqrt(3)})
    found = listed(tm.capped_distance([0.0, 0.0, 0.0], u.atoms.positions, 1.5))  # shape (3,)
    assert found == {(0, 0): 0, (0, 1): 1}
    for pairs, d in (tm.capped_distance(np.zeros((0, 3)), u.atoms.positions, 2.0),
                     tm.capped_distance(u.atoms.positions, np.zeros((0, 3)), 2.0),
                     tm.self_capped_distance(np.zeros((1, 3)), 2.0),
                     tm.self_capped_distance(u.atoms.positions, 0.5, box=u.dimensions)):
        assert pairs.shape == (0, 2) and pairs.dtype == np.intp
        assert d.shape == (0,) and d.dtype == np.float64
    empty = tm.capped_distance(np.zeros((0, 3)), u.atoms, 2.0, return_distances=False)
    assert isinstance(empty, np.ndarray) and empty.shape == (0, 2)


def test_method_is_accepted_and_changes_nothing():
    rng = np.random.default_rng(3)
    points = rng.uniform(0, 12, (80, 3))
    box = [12, 12, 12, 90, 90, 90]
    expected = tm.capped_distance(points[:30], points, 3.0, box=box)
    for method in ("bruteforce", "nsgrid", "pkdtree", "NSGrid"):
        result = tm.capped_distance(points[:30], points, 3.0, box=box, method=method)
        np.testing.assert_array_equal(result[0], expected[0])
        np.testing.assert_array_equal(result[1], expected[1])


HOSTILE = [
    (lambda: tm.capped_distance(np.zeros((4, 2)), np.zeros((3, 3)), 1.0), ValueError,
     r"reference must be an array of shape \(n, 3\) or \(3,\) \(got shape \(4, 2\)\)"),
    (lambda: tm.capped_distance(np.zeros((4, 3)), np.zeros(4), 1.0), ValueError,
     r"configuration must be an array of shape .* \(got shape \(4,\)\)"),
    (lambda: tm.capped_distance([[0, 0, 0], [1, 2]], np.zeros((3, 3)), 1.0), ValueError,
     "reference"),
    (lambda: tm.capped_distance(np.zeros((2, 3), complex), np.zeros((3, 3)), 1.0), TypeError,
     "reference"),
    (lambda: tm.capped_distance([["a", "b", "c"]], np.zeros((3, 3)), 1.0), TypeError,
     "reference"),
    (lambda: tm.capped_distance(np.zeros((2, 3)), [[0, 0, np.nan]], 1.0), ValueError,
     r"configuration\[0\] is not finite"),
    (lambda: tm.self_capped_distance([[0, 0, 0], [np.inf, 0, 0]], 1.0), ValueError,
     r"reference\[1\] is not finite"),
    (lambda: tm.capped_distance(np.zeros((2, 3)), np.zeros((2, 3)), -1.0), ValueError,
     r"max_cutoff must be a finite number >= 0 \(got -1.0\)"),
    (lambda: tm.capped_distance(np.zeros((2, 3)), np.zeros((2, 3)), np.nan), ValueError,
     "max_cutoff"),
    (lambda: tm.capped_distance(np.zeros((2, 3)), np.zeros((2, 3)), [1.0, 2.0]), ValueError,
     "max_cutoff must be one number"),
    (lambda: tm.capped_distance(np.zeros((2, 3)), np.zeros((2, 3)), "3"), TypeError,
     "max_cutoff"),
    (lambda: tm.self_capped_distance(np.zeros((2, 3)), 1.0, min_cutoff=np.nan), ValueError,
     "min_cutoff"),
    (lambda: tm.self_capped_distance(np.zeros((2, 3)), 1.0, box=[10, 10, 10]), ValueError,
     r"box must be None or \[a, b, c, alpha, beta, gamma\], six numbers \(got shape \(3,\)\)"),
    (lambda: tm.self_capped_distance(np.zeros((2, 3)), 1.0, box=[10, 0, 10, 90, 90, 90]),
     ValueError, r"box lengths a, b, c must be > 0 \(got \[10.0, 0.0, 10.0\]\)"),
    (lambda: tm.self_capped_distance(np.zeros((2, 3)), 1.0, box=[10, 10, 10, 90, 180, 90]),
     ValueError, r"box angles alpha, beta, gamma must be in \(0, 180\) degrees"),
    (lambda: tm.self_capped_distance(np.zeros((2, 3)), 1.0, box=[10, 10, 10, 30, 30, 90]),
     ValueError, r"box angles alpha, beta, gamma = \[30.0, 30.0, 90.0\] do not form a cell"),
    (lambda: tm.self_capped_distance(np.zeros((2, 3)), 1.0, box=[10, 10, np.nan, 90, 90, 90]),
     ValueError, "box must hold finite numbers"),
    (lambda: tm.capped_distance(np.zeros((2, 3)), np.zeros((2, 3)), 1.0, method="grid"),
     ValueError, "method must be None or one of bruteforce, nsgrid, pkdtree"),
    (lambda: tm.FastNS(1.0, np.zeros(3), [10, 10, 10, 90, 90, 90]), ValueError,
     r"coords must be an array of shape \(n, 3\) \(got shape \(3,\)\)"),
    (lambda: tm.FastNS(1.0, np.zeros((2, 3)), None), ValueError, "box must be .* with pbc=True"),
    (lambda: tm.FastNS(-1.0, np.zeros((2, 3)), [10, 10, 10, 90, 90, 90]), ValueError,
     "cutoff must be a finite number >= 0"),
    (lambda: tm.FastNS(1.0, np.zeros((2, 3)), [10, 10, 10, 90, 90, 90]).search(np.zeros((2, 4))),
     ValueError, r"search_coords must be an array of shape \(n, 3\)"),
]


@pytest.mark.parametrize("call, error, message", HOSTILE)
def test_hostile_input_gets_errors_naming_the_argument(call, error, message):
    with pytest.raises(error, match=message):
        call()


ROUTED_IN = [  # (module, name): where MDAnalysis 2.4's analyses find the three names
    ("MDAnalysis.lib.distances", "capped_distance"),
    ("MDAnalysis.lib.distances", "self_capped_distance"),
    ("MDAnalysis.lib.distances", "FastNS"),
    ("MDAnalysis.lib.nsgrid", "FastNS"),
    ("MDAnalysis.lib.NeighborSearch", "capped_distance"),
    ("MDAnalysis.analysis.distances", "capped_distance"),
    ("MDAnalysis.analysis.hydrogenbonds.hbond_analysis", "capped_distance"),
]


def test_install_routes_mdanalysis_and_uninstall_restores_it():
    import importlib

    modules = {name: importlib.import_module(name) for name, _ in ROUTED_IN}
    originals = {(m, n): getattr(modules[m], n) for m, n in ROUTED_IN}
    try:
        for _ in range(2):  # a second install() changes nothing
            tm.install()
            for m, n in ROUTED_IN:
                assert getattr(modules[m], n) is getattr(tm, n), f"{m}.{n} is not routed"
        points = np.random.default_rng(5).uniform(0, 10, (200, 3)).astype(np.float32)
        u = MDAnalysis.Universe.empty(200, trajectory=True)
        u.atoms.positions = points
        u.dimensions = [10, 10, 10, 90, 90, 90]
        around = u.select_atoms("around 2.0 index 0")  # selections look the name up per call
        expected = tm.capped_distance(points[:1], points, 2.0, box=u.dimensions)[0][:, 1]
        assert sorted(around.indices) == sorted(set(expected.tolist()) - {0})
    finally:
        for _ in range(2):  # a second uninstall() changes nothing
            tm.uninstall()
            for (m, n), value in originals.items():
                assert getattr(modules[m], n) is value, f"{m}.{n} is not restored"


def test_modules_imported_after_install_are_restored_by_uninstall():
    # A fresh interpreter: the analysis modules are imported after install() and take tricell's
    # functions at import; uninstall() must find them there too.
    code = """
import tricell.mdanalysis as tm
tm.install()
import MDAnalysis.analysis.distances as d, MDAnalysis.analysis.hydrogenbonds.wbridge_analysis as w
import MDAnalysis.lib.nsgrid as ns
assert d.capped_distance is tm.capped_distance and w.capped_distance is tm.capped_distance
assert ns.FastNS is tm.FastNS
tm.uninstall()
import MDAnalysis.lib.distances as lib
assert d.capped_distance is lib.capped_distance is w.capped_distance, d.capped_distance
assert lib.capped_distance.__module__ == "MDAnalysis.lib.distances"
assert ns.FastNS.__module__ == "MDAnalysis.lib.nsgrid", ns.FastNS
print("ok")
"""
    done = subprocess.run([sys.executable, "-W", "ignore", "-c", code], capture_output=True,
                          text=True)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr


def lattice_gas_universe(seed, frames=4, atoms=300):
    """A generated trajectory on a 1/8 Angstrom grid in a 16 Angstrom cube: every engine's
    float32 and float64 arithmetic is exact on it, so distances agree to the last bit."""
    rng = np.random.default_rng(seed)
    coordinates = (rng.integers(-64, 192, (frames, atoms, 3)) / 8).astype(np.float32)
    u = MDAnalysis.Universe.empty(atoms, trajectory=True)
    dimensions = np.tile(np.array([16, 16, 16, 90, 90, 90], np.float32), (frames, 1))
    u.load_new(coordinates, format=MemoryReader, dimensions=dimensions)
    return u


def triclinic_universe(seed, frames=4, atoms=300):
    rng = np.random.default_rng(seed)
    box = np.array([18, 19, 20, 75, 100, 110], np.float32)
    coordinates = np.stack([random_points(rng, atoms, box, far=1) for _ in range(frames)])
    u = MDAnalysis.Universe.empty(atoms, trajectory=True)
    u.load_new(coordinates.astype(np.float32), format=MemoryReader,
               dimensions=np.tile(box, (frames, 1)))
    return u


def rdf_with_and_without_install(u, **arguments):
    g1, g2 = u.atoms[: len(u.atoms) // 2], u.atoms
    theirs = InterRDF(g1, g2, **arguments).run().results
    calls = []
    tm.install()
    try:
        routed = mda_distances.capped_distance
        mda_distances.capped_distance = lambda *a, **k: calls.append(1) or routed(*a, **k)
        mine = InterRDF(g1, g2, **arguments).run().results
    finally:
        mda_distances.capped_distance = routed
        tm.uninstall()
    assert len(calls) == len(u.trajectory), "InterRDF did not search through tricell"
    return mine, theirs


@pytest.mark.parametrize("range_", [(0.0, 7.5), (0.5, 12.0)])  # 12 > half the box: brute force
def test_interrdf_gives_the_same_rdf_with_install(range_):
    mine, theirs = rdf_with_and_without_install(lattice_gas_universe(11), nbins=60,
                                                range=range_)
    np.testing.assert_array_equal(mine.bins, theirs.bins)
    np.testing.assert_array_equal(mine.count, theirs.count)
    np.testing.assert_array_equal(mine.rdf, theirs.rdf)
    assert theirs.count.sum() > 1000


def test_interrdf_in_a_triclinic_box_differs_only_by_rounding_at_bin_edges():
    u = triclinic_universe(12)
    edges = np.linspace(0.0, 8.0, 81)
    mine, theirs = rdf_with_and_without_install(u, nbins=80, range=(0.0, 8.0))
    # Pairs within float32 rounding of a bin edge may fall into the neighbouring bin.
    near_edges = 0
    for _ in u.trajectory:
        d = tm.capped_distance(u.atoms[: len(u.atoms) // 2], u.atoms, 8.0,
                               box=u.dimensions)[1]
        near_edges += int((np.abs(d[:, None] - edges[None, :]) < TOLERANCE).any(axis=1).sum())
    assert np.abs(mine.count - theirs.count).sum() <= 2 * near_edges
    assert theirs.count.sum() > 1000
