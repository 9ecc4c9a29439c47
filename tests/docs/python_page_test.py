"""The Python examples of docs/python.md run as the page shows them, against the built package.

Every ```python block of the page (also one indented in a list) is one test, named after the
heading it sits under and its place there. A block's HARNESS entry gives it the names the page
takes as given (`points`, `atoms`, `structure`, ...), runs it, then checks what it computed
against ASE, pymatgen, MDAnalysis or the definition of a pair; a block without an entry, or an entry without
a block, fails. The PyTorch block is skipped, with the reason, where PyTorch (or the op library,
built only with libtorch) is missing.
"""
import os
import re

import numpy as np
import pytest

SOURCE_DIR = os.environ.get(
    "TRICELL_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(__file__))))
PAGE = os.path.join(SOURCE_DIR, "docs", "python.md")


def page_blocks():
    """(heading, place under it, code) of every python block of the page, dedented."""
    with open(PAGE, encoding="utf-8") as f:
        text = f.read()
    blocks, heading, place = [], None, 0
    for match in re.finditer(r"^(#+) ([^\n]*)$|^( *)```python\n(.*?)^\3```$", text, re.M | re.S):
        if match.group(1):
            heading, place = match.group(2), 0
            continue
        indent = len(match.group(3))
        code = "".join(line[indent:] + "\n" for line in match.group(4).splitlines())
        place += 1
        blocks.append((heading, place, code))
    return blocks


def silicon():
    from ase.build import bulk

    return bulk("Si", "diamond", a=5.43, cubic=True)


def skewed_points(count, seed):
    """Random points in a skewed cell (rows are lattice vectors), some far outside it."""
    rng = np.random.default_rng(seed)
    box = np.array([[9.0, 0.0, 0.0], [2.5, 8.5, 0.0], [-1.5, 2.0, 9.5]])
    points = rng.random((count, 3)) @ box
    points[::7] += 30 * box[0] - 12 * box[2]
    return points, box


def pairs_by_definition(points, box, cutoff):
    """The ordered pairs (i, j, S) of a full list, by brute force over the images."""
    images = np.array([(a, b, c) for a in range(-3, 4) for b in range(-3, 4)
                       for c in range(-3, 4)])
    wrapped = points - np.floor(points @ np.linalg.inv(box)) @ box
    shift = np.rint((wrapped - points) @ np.linalg.inv(box)).astype(int)
    found = set()
    for i in range(len(points)):
        for j in range(len(points)):
            d = wrapped[j] - wrapped[i] + images @ box
            for image in images[np.linalg.norm(d, axis=1) < cutoff]:
                if i != j or image.any():
                    # Back to the caller's positions: S = image + shift_j - shift_i.
                    found.add((i, j, tuple(image + shift[j] - shift[i])))
    return found


def native_api_inputs():
    points, box = skewed_points(40, 1)
    rng = np.random.default_rng(2)
    return dict(points=points, box=box, radii=rng.uniform(0.8, 1.6, len(points)),
                numbers=rng.choice([1, 8, 14], len(points)), solute=[0, 5, 11],
                points_list=[skewed_points(n, n)[0] for n in (4, 9)],
                box_list=[skewed_points(1, 0)[1], np.diag([6.0, 7.0, 8.0])])


def check_native_api(ns):
    points, box = ns["points"], ns["box"]
    nl = ns["nl"]
    i, j, S, d = nl.compute(points, box, quantities="ijSd")
    assert set(zip(i.tolist(), j.tolist(), map(tuple, S.tolist()))) == \
        pairs_by_definition(points, box, 5.0)
    D = points[j] - points[i] + S @ box
    np.testing.assert_allclose(np.linalg.norm(D, axis=1), d, atol=1e-12)
    in_query = [p for p in pairs_by_definition(points, box, 5.0) if p[0] in ns["solute"]]
    assert len(ns["S"]) == len(in_query), "query: the full list's pairs with i in the subset"
    offsets = ns["offsets"]  # and d, of the batch (i and j are the Verlet list's by then)
    for s, (x, cell) in enumerate(zip(ns["points_list"], ns["box_list"])):
        np.testing.assert_array_equal(ns["d"][offsets[s]:offsets[s + 1]],
                                      nl.compute(x, cell, quantities="d"))
    assert np.all(np.linalg.norm(ns["D"], axis=1) < 5.0), "the Verlet list within the cutoff"
    assert ns["s"].positions.shape == (9, 3), "quartz: 9 atoms"


def batch_inputs():
    from ase.build import bulk

    structures = [bulk("Si", "diamond", a=5.43, cubic=True), bulk("Cu", "fcc", a=3.6),
                  bulk("NaCl", "rocksalt", a=5.64) * (2, 1, 1)]
    for k, atoms in enumerate(structures):
        atoms.rattle(0.05, seed=k)
    ptr = np.cumsum([0] + [len(a) for a in structures])
    return dict(positions=np.concatenate([a.positions for a in structures]),
                cells=np.array([a.cell[:] for a in structures]),
                pbc=np.array([a.pbc for a in structures]), ptr=ptr, structures=structures)


def check_batch(ns):
    from ase.neighborlist import neighbor_list

    offsets, ptr = ns["offsets"], ns["ptr"]
    for s, atoms in enumerate(ns["structures"]):
        rows = slice(offsets[s], offsets[s + 1])
        theirs = neighbor_list("ijS", atoms, 5.0)
        ours = (ns["i"][rows] - ptr[s], ns["j"][rows] - ptr[s], ns["S"][rows])
        key = lambda i, j, S: sorted(zip(i.tolist(), j.tolist(), map(tuple, S.tolist())))  # noqa: E731
        assert key(*ours) == key(*theirs), "structure %d: ASE's pairs" % s
    np.testing.assert_allclose(np.linalg.norm(ns["D"], axis=1), ns["d"], atol=1e-12)


def requests_inputs():
    torch_inputs()  # skips, with the reason, where PyTorch or the op library is missing
    import torch
    import tricell.torch

    ns = batch_inputs()
    points, box = skewed_points(30, 3)
    return dict(tricell=tricell, torch=torch, points=points, box=box, **{
        k: ns[k] for k in ("positions", "cells", "pbc", "ptr")})


def check_requests(ns):
    import tricell

    points, box = ns["points"], ns["box"]
    alone = tricell.NeighborList(3.0, full=False).compute(points, box, True, "ijSd")
    key = lambda i, j, S: sorted(zip(np.asarray(i).tolist(), np.asarray(j).tolist(),  # noqa: E731
                                     map(tuple, np.asarray(S).tolist())))
    mine = tricell.neighbor_lists(points, box, True, ns["requests"], "ijSd")[1]
    assert key(*mine[:3]) == key(*alone[:3])
    torch_lists = ns["lists"]
    assert [len(t[0]) for t in torch_lists] == [
        len(tricell.NeighborList(r, full=f).compute(points, box, True, "i"))
        for r, f in ns["requests"]]
    offsets = ns["offsets"]
    assert np.all(ns["d"][:offsets[1]] < 3.0) and np.all(ns["d"] < 6.0)
    assert ns["batch"][0][0][-1] == len(ns["batch"][0][1])


def check_nearest(ns):
    import tricell

    points, box = ns["points"], ns["box"]
    i, j, S, d = tricell.NeighborList(6.0).compute(points, box, True, "ijSd")
    for a in range(len(points)):
        mine = ns["d"][ns["o"][a]:ns["o"][a + 1]]
        assert np.array_equal(mine, np.sort(d[i == a])[:20])
    assert ns["offsets"][-1] == len(ns["S"]) and len(ns["D"]) > 0  # S: the batch call's


def verify_inputs():
    import ase.neighborlist  # noqa: F401 - the block calls ase.neighborlist.neighbor_list

    atoms = silicon()
    atoms.rattle(0.05, seed=3)
    import tricell  # the page's blocks continue one session: the first imported it

    return dict(ase=__import__("ase"), atoms=atoms, tricell=tricell)


def check_verify(ns):
    assert ns["report"], ns["report"].message


def check_ase_function(ns):
    from ase.neighborlist import neighbor_list

    theirs = neighbor_list("ijS", ns["atoms"], 5.0)
    ours = (ns["i"], ns["j"], ns["S"])
    assert sorted(zip(*(a.tolist() if a.ndim == 1 else list(map(tuple, a.tolist()))
                        for a in ours))) == \
        sorted(zip(*(a.tolist() if a.ndim == 1 else list(map(tuple, a.tolist()))
                     for a in theirs)))


def ase_class_inputs():
    atoms = silicon()
    return dict(atoms=atoms, cutoffs=[1.3] * len(atoms))


def check_ase_class(ns):
    from ase.neighborlist import NeighborList

    theirs = NeighborList(ns["cutoffs"], skin=0.3, self_interaction=False, bothways=True)
    theirs.update(ns["atoms"])
    their_indices, their_offsets = theirs.get_neighbors(0)
    assert sorted(zip(ns["indices"].tolist(), map(tuple, ns["offsets"].tolist()))) == \
        sorted(zip(their_indices.tolist(), map(tuple, their_offsets.tolist())))


def pymatgen_inputs():
    from pymatgen.io.ase import AseAtomsAdaptor

    return dict(structure=AseAtomsAdaptor.get_structure(silicon()))


def check_pymatgen(ns):
    theirs = ns["structure"].get_neighbor_list(5.0)
    ours = (ns["centers"], ns["points"], ns["images"], ns["distances"])
    assert len(ours[0]) == len(theirs[0])
    key = lambda arrays: sorted(zip(arrays[0].tolist(), arrays[1].tolist(),  # noqa: E731
                                    map(tuple, np.rint(arrays[2]).astype(int).tolist())))
    assert key(ours) == key(theirs)


def check_mdanalysis(ns):
    import MDAnalysis.lib.distances
    from MDAnalysis.analysis.rdf import InterRDF

    assert MDAnalysis.lib.distances.capped_distance.__module__ == "MDAnalysis.lib.distances", \
        "uninstall() gives MDAnalysis its own function back"
    positions, box = ns["positions"].astype(np.float64), np.asarray(ns["box"][:3], np.float64)
    d = positions[None, :, :] - positions[:10, None, :]
    d = np.linalg.norm(d - box * np.round(d / box), axis=2)  # a cube: the nearest image
    expected = set(zip(*np.nonzero(d <= 6.0 - 1e-9)))
    near = set(zip(*np.nonzero(np.abs(d - 6.0) <= 1e-9)))  # either way within rounding
    found = set(map(tuple, ns["pairs"].tolist()))
    assert expected <= found <= expected | near, "FastNS(...).search: the pairs with d <= 6"
    np.testing.assert_allclose(ns["distances"], d[tuple(ns["pairs"].T)], atol=1e-12)
    theirs = InterRDF(ns["u"].atoms, ns["u"].atoms, nbins=75, range=(0.0, 15.0)).run().results
    # MDAnalysis's float32 distances may put a pair within rounding of a bin edge next door.
    d = ns["capped_distance"](positions, positions, 15.0, box=ns["box"])[1]
    edges = theirs.edges
    k = np.clip(np.searchsorted(edges, d), 1, len(edges) - 1)
    near_edges = np.count_nonzero(np.minimum(d - edges[k - 1], edges[k] - d) < 1e-4)
    assert np.abs(ns["rdf"].results.count - theirs.count).sum() <= 2 * near_edges
    assert theirs.count.sum() > 10000


def torch_inputs():
    try:
        import tricell.torch  # noqa: F401
    except ImportError as error:
        if error.name in ("tricell._tricell_torch", "torch"):
            pytest.skip("the PyTorch example needs PyTorch and the op library: %s" % error)
        raise
    import torch

    atoms = silicon()
    atoms.rattle(0.05, seed=4)
    return dict(positions=torch.tensor(atoms.positions), cell=torch.tensor(atoms.cell[:]))


def check_torch(ns):
    forces = ns["forces"]
    assert forces.shape == ns["positions"].shape
    # A pair potential: the forces on all atoms sum to zero.
    assert float(forces.sum(dim=0).abs().max()) < 1e-9
    assert ns["cell_gradient"].shape == (3, 3)


def torch_batch_inputs():
    torch_inputs()  # skips, with the reason, where PyTorch or the op library is missing
    import torch
    import tricell.torch

    ns = batch_inputs()
    return dict(torch=torch, tricell=tricell,
                positions=torch.tensor(ns["positions"], requires_grad=True),
                cells=torch.tensor(ns["cells"], requires_grad=True),
                pbc=torch.tensor(ns["pbc"]), batch_ptr=torch.tensor(ns["ptr"]),
                structures=ns["structures"])


def check_torch_batch(ns):
    import torch
    from ase.neighborlist import neighbor_list

    for s, atoms in enumerate(ns["structures"]):
        their = neighbor_list("ijS", atoms, 5.0)
        mine = ns["system_mapping"] == s
        first = int(ns["batch_ptr"][s])
        key = lambda i, j, S: sorted(zip(i.tolist(), j.tolist(), map(tuple, S.tolist())))  # noqa: E731
        assert key(ns["mapping"][0, mine] - first, ns["mapping"][1, mine] - first,
                   ns["shifts_idx"][mine].long()) == key(*their), "structure %d" % s
    # The stress of each structure alone, through the single-structure list.
    nl = ns["tricell"].torch.NeighborList(5.0)
    for s, atoms in enumerate(ns["structures"]):
        x = torch.tensor(atoms.positions, requires_grad=True)
        h = torch.tensor(atoms.cell[:], requires_grad=True)
        (D,) = nl(x, h, [True] * 3, "D")
        gx, gh = torch.autograd.grad((D.norm(dim=1) ** -6).sum(), (x, h))
        alone = (x.detach().T @ gx + h.detach().T @ gh) / abs(float(torch.linalg.det(h)))
        torch.testing.assert_close(ns["stress"][s], alone, rtol=1e-10, atol=1e-12)


def vesin_inputs():
    torch_inputs()  # skips, with the reason, where PyTorch or the op library is missing
    import torch

    atoms = silicon()
    atoms.rattle(0.05, seed=5)
    return dict(torch=torch, atoms=atoms, positions=atoms.positions, cell=atoms.cell[:])


def check_vesin(ns):
    import torch
    from ase.neighborlist import neighbor_list

    atoms = ns["atoms"]
    theirs = neighbor_list("ijSD", atoms, 5.0)
    key = lambda i, j, S: sorted(zip(np.asarray(i).tolist(), np.asarray(j).tolist(),  # noqa: E731
                                     map(tuple, np.asarray(S).tolist())))
    ours = (ns["i"].numpy(), ns["j"].numpy())
    assert sorted(zip(*ours)) == sorted(zip(theirs[0].tolist(), theirs[1].tolist()))
    assert ns["D"].requires_grad is False and ns["D"].dtype == torch.float64
    assert key(*ns["nl"].compute(atoms.positions, atoms.cell[:], True, "ijS")) == key(*theirs[:3])


# (heading, place under it) -> (the names the block takes as given, the checks afterwards).
HARNESS = {
    ("The native API", 1): (native_api_inputs, check_native_api),
    ("The native API", 2): (verify_inputs, check_verify),
    ("Batches for machine learning", 1): (batch_inputs, check_batch),
    ("Several cutoffs per call", 1): (requests_inputs, check_requests),
    ("The k nearest within the cutoff", 1): (requests_inputs, check_nearest),
    ("Drop-in for ASE", 1): (lambda: dict(atoms=silicon()), check_ase_function),
    ("Drop-in for ASE", 2): (ase_class_inputs, check_ase_class),
    ("Drop-in for pymatgen", 1): (pymatgen_inputs, check_pymatgen),
    ("Drop-in for MDAnalysis", 1): (dict, check_mdanalysis),
    ("Drop-in for vesin", 1): (vesin_inputs, check_vesin),
    ("PyTorch", 1): (torch_inputs, check_torch),
    ("PyTorch", 2): (torch_batch_inputs, check_torch_batch),
}

BLOCKS = page_blocks()


def test_every_block_has_a_harness_and_every_harness_a_block():
    found = {(heading, place) for heading, place, _ in BLOCKS}
    assert found - set(HARNESS) == set(), "python blocks of docs/python.md without a harness"
    assert set(HARNESS) - found == set(), "harnesses of blocks docs/python.md no longer has"


@pytest.mark.parametrize("heading, place, code", BLOCKS,
                         ids=["%s %d" % (heading, place) for heading, place, _ in BLOCKS])
def test_block(heading, place, code, monkeypatch, tmp_path):
    if (heading, place) not in HARNESS:
        pytest.fail("no harness for python block %d under '%s'" % (place, heading))
    inputs, check = HARNESS[heading, place]
    # In a file of its own: TorchScript reads the source of the classes it compiles.
    path = tmp_path / ("python_md_%s_%d.py" % (re.sub(r"\W+", "_", heading), place))
    path.write_text(code)
    monkeypatch.chdir(os.path.join(SOURCE_DIR, "examples", "data"))  # tricell.read("quartz.cif")
    namespace = inputs()
    exec(compile(code, str(path), "exec"), namespace)
    check(namespace)
