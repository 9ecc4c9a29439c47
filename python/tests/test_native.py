"""The native API (tricell.NeighborList, VerletList, read) against ASE's primitive_neighbor_list
in the same process: values, dtypes, letters, array-like inputs, copy=False views, half lists,
threads and errors."""
import gc
import re
import threading

import numpy as np
import pytest
from ase import neighborlist as ase_nl

import tricell
from conftest import assert_same_pairs, drop_near, random_system, sort_pairs


def ase_reference(cell, positions, pbc, cutoff):
    found = ase_nl.primitive_neighbor_list("ijSdD", pbc, cell, positions, cutoff)
    return drop_near(cutoff, 1e-9, *sort_pairs(*found))


@pytest.mark.parametrize("seed", range(48))
def test_full_sorted_list_matches_ase(seed):
    cell, positions, pbc, cutoff, _ = random_system(seed)
    found = tricell.NeighborList(cutoff, sorted=True).compute(positions, cell, pbc, "ijSdD")
    mine = drop_near(cutoff, 1e-9, *found)
    assert_same_pairs(mine, ase_reference(cell, positions, pbc, cutoff), f"seed {seed}")


@pytest.mark.parametrize("seed", range(24))
def test_half_list_is_the_canonical_half_of_the_full_list(seed):
    cell, positions, pbc, cutoff, _ = random_system(seed)
    i, j, S, d = tricell.NeighborList(cutoff, full=False).compute(positions, cell, pbc)
    # Canonical orientation: i < j, or i == j with S lexicographically positive.
    first = np.argmax(S != 0, axis=1)
    positive = S[np.arange(len(S)), first] > 0
    assert np.all((i < j) | ((i == j) & positive)), f"seed {seed}"
    fi, fj, fS, fd = tricell.NeighborList(cutoff).compute(positions, cell, pbc)
    keep = (fi < fj) | ((fi == fj) & (fS[np.arange(len(fS)), np.argmax(fS != 0, axis=1)] > 0))
    assert_same_pairs(sort_pairs(i, j, S, d), sort_pairs(fi[keep], fj[keep], fS[keep], fd[keep]),
                      f"seed {seed}")


def test_letters_dtypes_and_shapes():
    cell, positions, pbc, cutoff, _ = random_system(4, atoms=10)
    nl = tricell.NeighborList(cutoff, sorted=True)
    i, j, S, d, D, P = nl.compute(positions, cell, pbc, "ijSdDP")
    assert (i.dtype, j.dtype, S.dtype, d.dtype, D.dtype, P.dtype) == (
        np.uint32, np.uint32, np.int32, np.float64, np.float64, np.uint32)
    n = len(i)
    assert (S.shape, D.shape, P.shape, d.shape) == ((n, 3), (n, 3), (n, 2), (n,))
    np.testing.assert_array_equal(P, np.stack([i, j], axis=1))
    np.testing.assert_allclose(D, positions[j] - positions[i] + S @ cell, atol=1e-12)
    np.testing.assert_allclose(d, np.linalg.norm(D, axis=1), atol=1e-12)
    only_d = nl.compute(positions, cell, pbc, "d")
    assert isinstance(only_d, np.ndarray)
    np.testing.assert_array_equal(only_d, d)
    Dj = nl.compute(positions, cell, pbc, "Dj")
    np.testing.assert_array_equal(Dj[0], D)
    np.testing.assert_array_equal(Dj[1], j)


@pytest.mark.parametrize("seed", range(4))
def test_every_quantities_string_gives_its_columns_in_order(seed):
    """Random strings of the letters (repeats, any order) through NeighborList (views and
    copies), compute_batch and VerletList: each gives the columns of the call with every letter,
    in its own order; an unknown letter is named with the quantities argument."""
    cell, positions, pbc, cutoff, _ = random_system(seed, atoms=12)
    letters = "ijSdDPo"
    nl = tricell.NeighborList(cutoff, grouped=True)
    full = dict(zip(letters, nl.compute(positions, cell, pbc, letters)))
    offsets, *batch = nl.compute_batch([positions, positions], [cell, cell], pbc, letters)
    batch = dict(zip(letters, batch))
    verlet = tricell.VerletList(cutoff, 0.3)
    by_verlet = dict(zip(letters, verlet.update(positions, cell, pbc, letters)))
    rng = np.random.default_rng(seed)
    for _ in range(40):
        quantities = "".join(rng.choice(list(letters), size=rng.integers(1, 9)))
        calls = [(full, nl.compute(positions, cell, pbc, quantities)),
                 (full, nl.compute(positions, cell, pbc, quantities, copy=False)),
                 (batch, nl.compute_batch([positions, positions], [cell, cell], pbc,
                                          quantities)[1:]),
                 (by_verlet, verlet.update(positions, cell, pbc, quantities))]
        for expected, got in calls:
            if len(quantities) == 1 and not isinstance(got, tuple):
                got = (got,)
            assert len(got) == len(quantities), quantities
            for letter, column in zip(quantities, got):
                assert column.dtype == expected[letter].dtype, (quantities, letter)
                np.testing.assert_array_equal(column, expected[letter], err_msg=quantities)
    message = r"unknown quantity 'x' in quantities='iSx' \(expected letters among i, j, S, d, D, P, o\)"
    with pytest.raises(ValueError, match=message):
        nl.compute(positions, cell, pbc, "iSx")
    with pytest.raises(ValueError, match=message):
        nl.compute_batch([positions], [cell], pbc, "iSx")
    with pytest.raises(ValueError, match=message):
        verlet.update(positions, cell, pbc, "iSx")
    with pytest.raises(ValueError, match=r"quantities must name at least one of i, j, S, d, D, P, o"):
        nl.compute(positions, cell, pbc, "")


def test_array_likes_are_converted():
    cell, positions, pbc, cutoff, _ = random_system(11, atoms=16)
    nl = tricell.NeighborList(cutoff, sorted=True)
    expected = nl.compute(positions, cell, pbc, "ijS")
    wide = np.zeros((len(positions), 6))
    wide[:, ::2] = positions  # a strided, non-contiguous view
    for points in (positions.tolist(), wide[:, ::2], np.asfortranarray(positions)):
        for box in (cell.tolist(), np.asfortranarray(cell)):
            got = nl.compute(points, box, list(pbc), "ijS")
            for g, e in zip(got, expected):
                np.testing.assert_array_equal(g, e)
    single = positions.astype(np.float32)
    got = nl.compute(single, cell, pbc, "ijSd")
    np.testing.assert_allclose(got[3], np.linalg.norm(
        single.astype(float)[got[1]] - single.astype(float)[got[0]] + got[2] @ cell, axis=1))


def test_periodic_as_one_bool():
    cell, positions, _, cutoff, _ = random_system(2, atoms=8)
    nl = tricell.NeighborList(cutoff, sorted=True)
    for flag in (True, False):
        a = nl.compute(positions, cell, flag, "ijS")
        b = nl.compute(positions, cell, (flag,) * 3, "ijS")
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y)


def test_copy_false_views_stay_valid_while_they_live():
    cell, positions, pbc, cutoff, _ = random_system(9, atoms=20, pbc=(True, True, True))
    nl = tricell.NeighborList(cutoff, sorted=True)
    copies = nl.compute(positions, cell, pbc, "ijSd")
    views = nl.compute(positions, cell, pbc, "ijSd", copy=False)
    assert all(v.base is not None for v in views)
    # Later calls with other systems never write into memory a live view refers to.
    for seed in range(5):
        c2, x2, p2, r2, _ = random_system(100 + seed, atoms=20)
        nl.compute(x2, c2, p2, "ijSdD", copy=False)
    del nl
    gc.collect()
    for v, c in zip(views, copies):
        np.testing.assert_array_equal(v, c)


def test_copy_false_reuses_the_buffers_once_views_are_dropped():
    cell, positions, pbc, cutoff, _ = random_system(9, atoms=20, pbc=(True, True, True))
    nl = tricell.NeighborList(cutoff)
    addresses = set()
    for _ in range(6):
        d = nl.compute(positions, cell, pbc, "d", copy=False)
        addresses.add(d.__array_interface__["data"][0])
    # The previous result is alive during each call, so two buffers alternate.
    assert len(addresses) <= 2


def test_threads_give_the_identical_list():
    cell, positions, pbc, cutoff, _ = random_system(3, atoms=400, kind="triclinic",
                                                   pbc=(True, True, True))
    one = tricell.NeighborList(cutoff, threads=1).compute(positions, cell, pbc, "ijSdD")
    for threads in (2, 0):
        other = tricell.NeighborList(cutoff, threads=threads).compute(positions, cell, pbc,
                                                                        "ijSdD")
        for a, b in zip(one, other):
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("seed", range(6))
def test_every_backend_gives_the_same_list(seed):
    cell, positions, pbc, cutoff, _ = random_system(seed, atoms=60)
    expected = tricell.NeighborList(cutoff, sorted=True).compute(positions, cell, pbc, "ijSdD")
    for backend in tricell._tricell.backends():
        nl = tricell.NeighborList(cutoff, sorted=True, backend=backend)
        got = nl.compute(positions, cell, pbc, "ijSdD")
        for g, e in zip(got, expected):
            np.testing.assert_array_equal(g, e, err_msg=f"seed {seed}, {backend}")


@pytest.mark.parametrize("seed", range(12))
def test_grouped_list_is_the_list_grouped_by_i_with_offsets(seed):
    # A half list grouped is the unordered one stably grouped by i; a full list grouped holds
    # the unordered one's pairs (which come from the half stencil, turned around) in runs of i.
    cell, positions, pbc, cutoff, _ = random_system(seed, atoms=80)
    full = seed % 2 == 0
    for backend in tricell._tricell.backends():
        plain = tricell.NeighborList(cutoff, full=full, backend=backend, threads=1 + seed % 3)
        grouped = tricell.NeighborList(cutoff, full=full, backend=backend, grouped=True)
        assert grouped.grouped and not plain.grouped
        found = plain.compute(positions, cell, pbc, "ijSdD")
        i, j, S, d, D, o = grouped.compute(positions, cell, pbc, "ijSdDo")
        if full:
            rows = [np.column_stack(c) for c in ((i, j, S, d, D), found)]
            rows = [r[np.lexsort(r.T[::-1])] for r in rows]
            np.testing.assert_array_equal(rows[0], rows[1], err_msg=f"seed {seed}, {backend}")
            assert np.all(np.diff(i.astype(np.int64)) >= 0)
        else:
            order = np.argsort(found[0], kind="stable")
            for g, e in zip((i, j, S, d, D), found):
                np.testing.assert_array_equal(g, e[order], err_msg=f"seed {seed}, {backend}")
        assert o.dtype == np.int64 and len(o) == len(positions) + 1
        np.testing.assert_array_equal(o, np.searchsorted(i, np.arange(len(positions) + 1)))
    _, _, _, _, o_sorted = tricell.NeighborList(cutoff, full=full, sorted=True).compute(
        positions, cell, pbc, "ijSdo")
    np.testing.assert_array_equal(o, o_sorted)


def test_offsets_need_a_grouped_or_sorted_list():
    cell, positions, pbc, cutoff, _ = random_system(1, atoms=10)
    with pytest.raises(ValueError, match="quantity 'o'.*grouped=True or sorted=True"):
        tricell.NeighborList(cutoff).compute(positions, cell, pbc, "ijo")
    with pytest.raises(ValueError, match="quantity 'o'"):
        tricell.NeighborList(cutoff).compute_batch([positions], [cell], pbc, "ijo")
    offsets, o = tricell.NeighborList(cutoff, grouped=True).compute_batch(
        [positions, positions], [cell, cell], pbc, "o")
    assert len(o) == 2 * len(positions) + 1 and o[-1] == offsets[-1]


def test_concurrent_calls_from_python_threads():
    cell, positions, pbc, cutoff, _ = random_system(6, atoms=300, kind="triclinic",
                                                   pbc=(True, True, True))
    nl = tricell.NeighborList(cutoff, sorted=True)
    expected = nl.compute(positions, cell, pbc, "ijSd")
    results = []

    def work():
        for _ in range(10):
            results.append(nl.compute(positions, cell, pbc, "ijSd", copy=False))

    workers = [threading.Thread(target=work) for _ in range(3)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert len(results) == 30
    for got in results:
        for g, e in zip(got, expected):
            np.testing.assert_array_equal(g, e)


@pytest.mark.parametrize("seed", range(12))
def test_verlet_list_follows_moving_atoms(seed):
    cell, positions, pbc, cutoff, _ = random_system(seed, atoms=30, kind="triclinic")
    rng = np.random.default_rng(seed)
    verlet = tricell.VerletList(cutoff, 0.3)
    x = positions.copy()
    for step in range(8):
        found = verlet.update(x, cell, pbc, "ijSdD")
        mine = drop_near(cutoff, 1e-9, *sort_pairs(*found))
        assert_same_pairs(mine, ase_reference(cell, x, pbc, cutoff), f"seed {seed} step {step}")
        x = x + rng.uniform(-0.05, 0.05, x.shape)
    assert 1 <= verlet.rebuild_count <= 8
    assert isinstance(verlet.rebuilt, bool)


def test_empty_inputs():
    nl = tricell.NeighborList(1.0)
    for points in ([], np.zeros((0, 3))):
        i, j, S, d, D, P = nl.compute(points, np.eye(3), True, "ijSdDP")
        assert (i.shape, S.shape, D.shape, P.shape) == ((0,), (0, 3), (0, 3), (0, 2))
    views = nl.compute(np.zeros((1, 3)), np.eye(3) * 5, True, "ijSd", copy=False)
    assert [v.shape for v in views] == [(0,), (0,), (0, 3), (0,)]


def test_errors_carry_the_library_message():
    nl = tricell.NeighborList(2.0)
    x = np.random.default_rng(0).random((10, 3))
    with pytest.raises(ValueError, match=r"cutoff must be > 0 \(got -1.5\)"):
        tricell.NeighborList(-1.5)
    with pytest.raises(ValueError, match=r"points must be an array of shape \(N, 3\) \(got shape \(10, 2\)\)"):
        nl.compute(x[:, :2], np.eye(3))
    with pytest.raises(ValueError, match=r"box must be a 3 x 3 array"):
        nl.compute(x, np.eye(2))
    with pytest.raises(ValueError, match=r"periodic must be a bool or three bools"):
        nl.compute(x, np.eye(3), (True, False))
    with pytest.raises(ValueError, match=r"unknown quantity 'x'"):
        nl.compute(x, np.eye(3), True, "ijx")
    bad = x.copy()
    bad[7, 2] = np.inf
    with pytest.raises(ValueError, match="position 7 is not finite"):
        nl.compute(bad, np.eye(3))
    with pytest.raises(ValueError):
        nl.compute(x, np.zeros((3, 3)))
    with pytest.raises(ValueError):
        nl.compute(x, [[1, 0, 0], [0, 1, 0], [0, 0, np.nan]])
    with pytest.raises(ValueError):
        tricell.VerletList(1.0, -0.5)


def test_backends_come_from_the_library_table():
    names = tricell._tricell.backends()
    assert names[0] == "auto"
    assert {"dense", "linked", "hash", "octree", "direct"} <= set(names)
    listed = ", ".join('"%s"' % name for name in names)
    assert "backend (" + listed + ") changes only the speed" in tricell.NeighborList.__doc__


def test_a_refused_pair_limit_names_the_keyword_max_pairs():
    cell, positions, pbc, cutoff, _ = random_system(5, atoms=40, pbc=(True, True, True))
    pairs = len(tricell.NeighborList(cutoff).compute(positions, cell, pbc, "i"))
    assert pairs > 10
    tail = ", more than max_pairs = 10; raise max_pairs to allow it"
    with pytest.raises(ValueError) as refused:
        tricell.NeighborList(cutoff, max_pairs=10).compute(positions, cell, pbc)
    assert str(refused.value).endswith(tail), str(refused.value)
    assert "NeighborOptions" not in str(refused.value)
    with pytest.raises(ValueError) as refused:
        tricell.NeighborList(cutoff, max_pairs=10).compute_batch([positions], [cell], pbc)
    assert str(refused.value).endswith(tail), str(refused.value)
    with pytest.raises(ValueError) as refused:
        tricell.VerletList(cutoff, 0.5, max_pairs=10).update(positions, cell, pbc)
    assert str(refused.value).endswith(tail), str(refused.value)
    # The default limit refuses an absurd cutoff from the estimate, before any search.
    with pytest.raises(ValueError, match=r"more than max_pairs = 500000000; raise max_pairs"):
        tricell.NeighborList(1000.0).compute(positions, cell, pbc)
    # Raising the limit (well above the estimate), or 0 (none), lets the same list through.
    for limit in (100 * pairs, 0):
        found = tricell.NeighborList(cutoff, max_pairs=limit).compute(positions, cell, pbc, "i")
        assert len(found) == pairs
    found = tricell.VerletList(cutoff, 0.5, max_pairs=0).update(positions, cell, pbc, "i")
    assert len(found) == pairs


def test_a_refused_memory_limit_names_the_keyword_max_bytes():
    # 30 atoms within 1.5 A of each other in a 10 A cube: every pair counts (870), well above
    # the density's estimate (about 100), so the list itself decides.
    cell, pbc, cutoff = 10 * np.eye(3), True, 3.0
    positions = np.random.default_rng(3).uniform(0, 1.5, (30, 3))
    pairs = len(tricell.NeighborList(cutoff).compute(positions, cell, pbc, "i"))
    assert pairs == 30 * 29
    fits = 28 * pairs
    # i, j, S, d: 28 bytes a pair; one byte short of the list is refused, with the pairs, their
    # bytes and the limit in the keyword's name.
    tail = ", more than max_bytes = %d (" % (fits - 1)
    raise_it = " GiB); raise max_bytes to allow it (0 = no limit)"
    for make in (lambda: tricell.NeighborList(cutoff, max_bytes=fits - 1),
                 lambda: tricell.NeighborList(cutoff, True, False, 1, "auto", 0, False, fits - 1)):
        with pytest.raises(ValueError) as refused:
            make().compute(positions, cell, pbc)
        text = str(refused.value)
        assert text.startswith("the neighbour list has too many pairs: 870 pairs are 24360 "
                               "bytes at their peak (28 bytes a pair of i, j, S, d)"), text
        assert tail in text and text.endswith(raise_it), text
        assert "NeighborOptions" not in text, text
    with pytest.raises(ValueError) as refused:
        tricell.NeighborList(cutoff, max_bytes=10).compute_batch([positions], [cell], pbc)
    assert str(refused.value).endswith(raise_it), str(refused.value)
    with pytest.raises(ValueError) as refused:
        tricell.VerletList(cutoff, 0.5, max_bytes=10).update(positions, cell, pbc)
    assert "more than max_bytes = 10 (" in str(refused.value), str(refused.value)
    # Exactly the list's bytes, or 0 (no limit), or None (the default), let it through.
    for limit in (fits, 0, None):
        found = tricell.NeighborList(cutoff, max_bytes=limit).compute(positions, cell, pbc, "i")
        assert len(found) == pairs
    found = tricell.VerletList(cutoff, 0.5, max_bytes=0).update(positions, cell, pbc, "i")
    assert len(found) == pairs
    i, j, S, d = tricell.NeighborList(cutoff).compute(positions, cell, pbc, "ijSd")
    assert tricell.verify(positions, cell, i, j, S, d, cutoff=cutoff, periodic=pbc, max_bytes=0)
    # Anything but a whole number >= 0 or None is refused, naming max_bytes and the value.
    for bad in (-1, 1.5, "16G", True, 2 ** 70):
        with pytest.raises(ValueError, match=r"^max_bytes must be a whole number of bytes >= 0 "
                                             r"\(0: no limit\) or None .*, got " + re.escape(repr(bad))):
            tricell.NeighborList(cutoff, max_bytes=bad)


@pytest.mark.parametrize("seed", range(16))
def test_radii_and_species_tables_match_ase_full_and_half(seed):
    cell, positions, pbc, cutoff, numbers = random_system(seed)
    rng = np.random.default_rng(4000 + seed)
    radii = rng.uniform(0.0, 0.6, len(positions)) * cutoff
    table = {(1, 1): 0.7 * cutoff, (8, 1): 0.9 * cutoff, (14, 8): cutoff, (14, 14): 0.5 * cutoff}
    ase_table = {(a, b): c for (a, b), c in table.items()}
    for how, native, peer in (("radii", dict(radii=radii), radii),
                              ("table", dict(species=numbers), ase_table)):
        nl = tricell.NeighborList(None if how == "radii" else table, sorted=True)
        mine = nl.compute(positions, cell, pbc, "ijSdD", **native)
        theirs = sort_pairs(*ase_nl.primitive_neighbor_list("ijSdD", pbc, cell, positions, peer,
                                                            numbers=numbers))
        assert_same_pairs(mine, theirs, f"seed {seed}, {how}")
        half = tricell.NeighborList(None if how == "radii" else table, full=False)
        i, j, S, d = half.compute(positions, cell, pbc, "ijSd", **native)
        # Each pair of the full list once: with its reverse, the half list is the full list.
        both_ways = sort_pairs(np.concatenate([i, j]), np.concatenate([j, i]),
                               np.concatenate([S, -S]), np.concatenate([d, d]))
        assert_same_pairs(both_ways, mine[:4], f"seed {seed}, {how}, half")


def test_variable_cutoff_errors():
    x = np.random.default_rng(0).random((6, 3))
    with pytest.raises(ValueError, match="radii= is needed"):
        tricell.NeighborList(None).compute(x, np.eye(3))
    with pytest.raises(ValueError, match="radii= is only for"):
        tricell.NeighborList(1.0).compute(x, np.eye(3), radii=np.ones(6))
    with pytest.raises(ValueError, match="species= is needed"):
        tricell.NeighborList({(1, 1): 1.0}).compute(x, np.eye(3))
    with pytest.raises(ValueError, match="one value per atom"):
        tricell.NeighborList(None).compute(x, np.eye(3), radii=np.ones(5))
    with pytest.raises(ValueError, match=r"radii\[2\] must be finite and >= 0"):
        tricell.NeighborList(None).compute(x, np.eye(3), radii=[1, 1, -1, 1, 1, 1])
    with pytest.raises(ValueError, match="species must be integers"):
        tricell.NeighborList({(1, 1): 1.0}).compute(x, np.eye(3), species=np.ones(6) * 0.5)
    with pytest.raises(ValueError, match="pairs of integer species"):
        tricell.NeighborList({("H", "H"): 1.0})
    with pytest.raises(ValueError, match="empty"):
        tricell.NeighborList({})
    with pytest.raises(ValueError, match="cutoff must be a number"):
        tricell.NeighborList("5")
    with pytest.raises(ValueError, match="backend"):
        tricell.NeighborList(1.0, backend="quantum")
    with pytest.raises(ValueError, match="species_cutoffs"):
        tricell.NeighborList({(1, 1): -1.0})


def test_read_matches_ase_for_poscar_and_extxyz(source_dir):
    from ase.io import read as ase_read

    for name in ("examples/data/POSCAR", "tests/io/data/graphene.extxyz"):
        path = f"{source_dir}/{name}"
        s = tricell.read(path)
        atoms = ase_read(path)
        np.testing.assert_allclose(s.cell, atoms.cell[:], atol=1e-12, err_msg=name)
        np.testing.assert_allclose(s.positions, atoms.positions, atol=1e-9, err_msg=name)
        assert s.species == atoms.get_chemical_symbols(), name
        assert s.pbc == tuple(bool(p) for p in atoms.pbc), name
        assert s.occupancies.shape == (len(atoms),)


def test_read_cif_and_open_xyz(source_dir):
    quartz = tricell.read(f"{source_dir}/examples/data/quartz.cif")
    assert len(quartz.positions) == 9 and quartz.species.count("Si") == 3
    assert quartz.pbc == (True, True, True)
    water = tricell.read(f"{source_dir}/examples/data/water.xyz")
    assert water.pbc == (False, False, False) and water.species == ["O", "H", "H"]
    i, j = tricell.NeighborList(1.2).compute(water.positions, water.cell, water.pbc, "ij")
    assert len(i) == 4


def test_read_errors_are_oserrors_with_file_and_line(source_dir, tmp_path):
    with pytest.raises(OSError, match="cannot open"):
        tricell.read(tmp_path / "missing.cif")
    with pytest.raises(OSError, match=r"truncated.cif"):
        tricell.read(f"{source_dir}/tests/io/data/truncated.cif")
    bad = tmp_path / "POSCAR"
    bad.write_text("title\n1.0\n1 0 0\n0 1 0\n")
    with pytest.raises(OSError, match=r"POSCAR:\d+: "):
        tricell.read(bad)
    with pytest.raises(OSError, match="structure.txt"):
        tricell.read(f"{source_dir}/tests/io/data/structure.txt")


@pytest.mark.parametrize("seed", range(16))
def test_query_lists_the_pairs_of_a_subset(seed):
    # query=: the full list restricted to i in the query; half: also each pair with both ends
    # in the query once (canonical orientation), and each other pair from its query end.
    cell, positions, pbc, cutoff, _ = random_system(seed)
    rng = np.random.default_rng(seed)
    n = len(positions)
    query = rng.permutation(n)[: rng.integers(0, n + 1)]
    inside = np.zeros(n, bool)
    inside[query] = True
    fi, fj, fS, fd = tricell.NeighborList(cutoff, sorted=True).compute(positions, cell, pbc)
    full = tricell.NeighborList(cutoff, sorted=True).compute(positions, cell, pbc, query=query)
    keep = inside[fi]
    assert_same_pairs(full, (fi[keep], fj[keep], fS[keep], fd[keep]), f"seed {seed}")
    half = tricell.NeighborList(cutoff, full=False).compute(positions, cell, pbc, query=query)
    positive = fS[np.arange(len(fS)), np.argmax(fS != 0, axis=1)] > 0
    canonical = (fi < fj) | ((fi == fj) & positive)
    keep = inside[fi] & (~inside[fj] | canonical)
    assert_same_pairs(sort_pairs(*half), (fi[keep], fj[keep], fS[keep], fd[keep]), f"seed {seed}")


def test_query_errors_name_the_entry():
    points = np.zeros((3, 3))
    nl = tricell.NeighborList(1.0)
    with pytest.raises(ValueError, match=r"query\[1\] is -2"):
        nl.compute(points, np.eye(3) * 4, query=[0, -2])
    with pytest.raises(ValueError, match=r"query\[0\] is 3, not the index of one of the 3"):
        nl.compute(points, np.eye(3) * 4, query=[3])
    with pytest.raises(ValueError, match="already holds"):
        nl.compute(points, np.eye(3) * 4, query=np.array([1, 1]))
    with pytest.raises(TypeError, match="query"):
        nl.compute(points, np.eye(3) * 4, query=["a"])
