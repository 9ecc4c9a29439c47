"""NeighborList(max_neighbors=, tie_tolerance=, symmetric=) of the compiled module against its
definition on the full list: each centre's pairs sorted by (d, j, S), the first k kept, with a
tolerance every pair within it of the k-th distance, with symmetric every kept pair's reverse;
random systems and perfect crystals (exact ties), single calls and the concatenated batch."""
import numpy as np
import pytest

import tricell


def system(seed):
    rng = np.random.default_rng(seed)
    if seed % 2 == 0:  # simple cubic or fcc, repeated: many equal distances
        basis = np.array([[0, 0, 0]] if seed % 4 == 0 else
                         [[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]], dtype=float)
        repeat = 2 + seed % 2
        a = 2.5
        grid = np.array([[x, y, z] for x in range(repeat) for y in range(repeat)
                         for z in range(repeat)], dtype=float)
        positions = a * (grid[:, None, :] + basis[None]).reshape(-1, 3)
        return positions, a * repeat * np.eye(3), [True] * 3, 1.6 * a
    n = int(rng.integers(1, 60))
    box = np.diag(rng.uniform(3, 7, 3)) + rng.uniform(-1, 1, (3, 3)) * (1 - np.eye(3))
    pbc = [bool(b) for b in rng.integers(0, 2, 3)]
    return rng.uniform(0, 1, (n, 3)) @ box, box, pbc, float(rng.uniform(1.5, 4))


def expected(positions, box, pbc, cutoff, k, tolerance, symmetric):
    i, j, S, d = tricell.NeighborList(cutoff).compute(positions, box, pbc, "ijSd")
    order = np.lexsort((S[:, 2], S[:, 1], S[:, 0], j, d, i))
    i, j, S, d = i[order], j[order], S[order], d[order]
    keep = np.zeros(len(i), dtype=bool)
    starts = np.searchsorted(i, np.arange(len(positions) + 1))
    for c in range(len(positions)):
        block = slice(starts[c], starts[c + 1])
        rank = np.arange(starts[c + 1] - starts[c])
        within = rank < k
        if len(rank) > k and tolerance > 0:
            within |= d[block] <= d[block][k - 1] + tolerance
        keep[block] = within
    if symmetric:
        kept = {(a, b, tuple(s)) for a, b, s in zip(i[keep], j[keep], S[keep])}
        keep |= np.array([(b, a, tuple(-s)) in kept for a, b, s in zip(i, j, S)], dtype=bool)
    return i[keep], j[keep], S[keep], d[keep]


@pytest.mark.parametrize("seed", range(24))
def test_single_calls_equal_the_definition(seed):
    positions, box, pbc, cutoff = system(seed)
    rng = np.random.default_rng(seed + 100)
    k = int(rng.integers(1, 14))
    tolerance = [0.0, 1e-9, 0.2][seed % 3]
    symmetric = seed % 4 >= 2
    nl = tricell.NeighborList(cutoff, max_neighbors=k, tie_tolerance=tolerance,
                              symmetric=symmetric)
    assert (nl.max_neighbors, nl.tie_tolerance, nl.symmetric) == (k, tolerance, symmetric)
    got = nl.compute(positions, box, pbc, "ijSdo")
    want = expected(positions, box, pbc, cutoff, k, tolerance, symmetric)
    for name, g, w in zip("ijSd", got, want):
        np.testing.assert_array_equal(g, w, err_msg=f"seed {seed}, column {name}")
    np.testing.assert_array_equal(got[4], np.searchsorted(got[0], np.arange(len(positions) + 1)))


def test_the_concatenated_batch_gives_each_system_its_single_call():
    systems = [system(seed) for seed in range(10)]
    cutoff = 3.0
    nl = tricell.NeighborList(cutoff, max_neighbors=4, tie_tolerance=0.05, symmetric=True)
    ptr = np.cumsum([0] + [len(s[0]) for s in systems])
    offsets, i, j, d = nl.compute_batch(
        np.concatenate([s[0] for s in systems]), np.stack([s[1] for s in systems]),
        np.array([s[2] for s in systems]), "ijd", batch_ptr=ptr)
    for k, (positions, box, pbc, _) in enumerate(systems):
        alone = nl.compute(positions, box, pbc, "ijd")
        mine = slice(offsets[k], offsets[k + 1])
        np.testing.assert_array_equal(i[mine], alone[0] + ptr[k])
        np.testing.assert_array_equal(j[mine], alone[1] + ptr[k])
        np.testing.assert_array_equal(d[mine], alone[2])


def test_what_it_cannot_define_is_refused_by_name():
    with pytest.raises(ValueError, match=r"max_neighbors keeps the nearest pairs of each centre "
                                         r"of a full list: full must be True \(got full=False\)"):
        tricell.NeighborList(3.0, full=False, max_neighbors=4)
    with pytest.raises(ValueError, match=r"tie_tolerance must be finite and >= 0 \(got -1\)"):
        tricell.NeighborList(3.0, max_neighbors=4, tie_tolerance=-1.0)
    with pytest.raises(ValueError, match="symmetric applies to the nearest pairs kept"):
        tricell.NeighborList(3.0, symmetric=True)
