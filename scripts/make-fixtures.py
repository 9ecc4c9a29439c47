#!/usr/bin/python3
"""Generate the pymatgen reference data in fixtures/reference/ from fixtures/structures/*.cif.

Usage (needs the Debian python3-pymatgen package, i.e. /usr/bin/python3, not a pyenv python):

    /usr/bin/python3 scripts/make-fixtures.py            # (re)write fixtures/reference/
    /usr/bin/python3 scripts/make-fixtures.py --check    # regenerate into a temporary directory
                                                         # and compare (numbers to 1e-12 relative,
                                                         # the rest exactly); exit 1 and list the
                                                         # drifted files on a difference

Only the standard library, numpy and pymatgen are used. The output is deterministic: the same
bytes on every run with the same pymatgen/numpy (reals are written with "%.17g", so they read
back exactly; lists are sorted).

Files written for every fixtures/structures/NAME.cif
------------------------------------------------------
NAME.structure.tsv -- pymatgen's expanded structure, CifParser(cif).get_structures(primitive=False)[0]:

    # tricell fixture: pymatgen expanded structure of fixtures/structures/NAME.cif (do not edit; ...)
    lattice_rows
    ax  ay  az
    bx  by  bz
    cx  cy  cz
    sites  N
    Symbol  fa  fb  fc  x  y  z  occupancy        (N lines, one per site, in pymatgen's order)

  Fields are separated by one TAB. The lattice rows are the vectors a, b, c in Angstrom (the box
  matrix H has them as columns). fa fb fc and x y z are the fractional and Cartesian coordinates
  exactly as pymatgen holds them (site.frac_coords, site.coords; nothing is wrapped again). Symbol
  and occupancy are those of the site's majority species (the first one on a tie).

NAME.neighbors.rcR.tsv (R written with one decimal, e.g. rc3.0) -- the full neighbour list of
structure.get_neighbor_list(R), i.e. pymatgen's (center_indices, points_indices, images, distances):

    # i j Sa Sb Sc d
    i  j  Sa  Sb  Sc  d                             (one line per ordered pair, TAB separated)

  sorted by (i, j, Sa, Sb, Sc). i and j are 0-based indices into the sites of NAME.structure.tsv;
  the image S = (Sa, Sb, Sc) follows tricell's convention D = x_j + H S - x_i, i.e.
  D = x_j + Sa*a + Sb*b + Sc*c - x_i with the Cartesian x and the lattice rows written in
  NAME.structure.tsv; d = |D|. The script recomputes d that way from the text it wrote and
  asserts agreement with pymatgen's distance to 1e-9 A, and asserts that the reverse pair
  (j, i, -S) of every pair is present.

MANIFEST.tsv -- one line per generated file: file, kind, sites, pairs, cutoff, pymatgen version.

Every structure gets two cutoffs (table CUTOFFS below): a moderate one, and one larger than the
smallest perpendicular width of the cell, so that several periodic images of the cell are
involved (for faujasite_si, 576 atoms and a 24 A cell, a 10 A cutoff is used instead, to keep
the file below 200k pairs).

What to know when comparing with tricell
----------------------------------------
* Cutoff: pymatgen keeps pairs with d <= r + 1e-8 (numerical_tol); tricell keeps d < r strictly.
  A consumer therefore skips pairs with |d - r| < 1e-6 on both sides. For the cutoffs chosen
  here the script asserts that no pair lies within MIN_GAP = 1e-4 A of the cutoff, so in these
  files nothing actually falls into that window.
* exclude_self=True (the default used here) removes only pairs with i == j and d <= 1e-8, that
  is the atom itself, (i, i, 0). An atom paired with its own periodic image (i == j, S != 0) is
  kept, and so are two distinct atoms that coincide (i != j, d == 0). check_pymatgen_semantics()
  verifies these statements (and the image convention) on every run.
* pymatgen's CifParser (2022.11.7) behaves as follows; tricell's CIF reader need not copy it,
  but tests comparing atom lists must allow for it:
  - Lattice: Lattice.from_parameters puts c along +z and a in the xz plane (a = (a sin(beta), 0,
    a cos(beta))); it is NOT "a along x, b in the xy plane". Compare fractional coordinates or
    distances, or use the lattice rows written here.
  - Order: sites are grouped by species (asymmetric-unit rows sorted by composition), each
    asymmetric-unit row expanded by the symmetry operators in file order, then the whole list
    is stably sorted by electronegativity (Structure.get_sorted_structure), so e.g. all Na come
    before all Cl whatever the file order.
  - Expansion: each image is wrapped with x - floor(x), and an image is dropped when it lies
    within 1e-4 (fractional, per axis, periodic) of one already kept for the same species --
    also across different asymmetric-unit rows of the same species. (gemmi's
    SmallStructure::get_all_unit_cell_sites merges only images of the same row, within 0.4 A.)
  - Fractional coordinates within a relative 1e-4 of 1/3 or 2/3 are replaced by 1/3 or 2/3
    (with a warning). The CIFs here write these values as 0.3333333333333333 /
    0.6666666666666666, the nearest doubles, so gemmi and pymatgen read the same numbers.
  - Occupancy: a row with occupancy < 1 gives a site whose species is a fractional
    composition (e.g. {Fe: 0.942}); rows at the same position are merged into one site with a
    mixed composition. Occupancy never changes positions or the neighbour list.
"""

import argparse
import os
import shutil
import sys
import tempfile
import warnings

try:
    import numpy as np
    import pymatgen.core
    from pymatgen.core import Lattice, Structure
    from pymatgen.io.cif import CifFile, CifParser
except ImportError as exc:  # pragma: no cover - depends on the machine
    sys.stderr.write(
        f"make-fixtures.py: {exc}; run with /usr/bin/python3 "
        "(apt-get install python3-pymatgen)\n"
    )
    sys.exit(77)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRUCTURES = os.path.join(ROOT, "fixtures", "structures")
REFERENCE = os.path.join(ROOT, "fixtures", "reference")

PYMATGEN_VERSION = pymatgen.core.__version__

# Two cutoffs (Angstrom) per structure: (moderate, large). Every structure must be listed, so
# adding a CIF forces a decision. Chosen so that no pair distance is within MIN_GAP of a cutoff.
CUTOFFS = {
    "albite_low": (3.0, 8.0),
    "alpha_quartz": (3.0, 7.0),
    "baddeleyite": (3.0, 7.0),
    "calcite": (3.0, 7.0),
    "cscl": (4.0, 9.0),
    "cu_fcc_primitive": (3.0, 8.0),
    "diopside": (3.0, 7.0),
    "faujasite_si": (3.0, 10.0),
    "forsterite": (3.0, 7.0),
    "graphite": (3.0, 8.0),
    "hydroxyapatite": (3.0, 8.0),
    "kaolinite": (3.0, 7.0),
    "kyanite": (3.0, 7.0),
    "mg_hcp": (3.5, 8.0),
    "nacl": (3.0, 7.5),
    "rutile": (3.0, 7.0),
    "si_diamond": (3.0, 7.0),
    "si_diamond_primitive": (3.0, 8.0),
    "srtio3": (3.0, 8.0),
    "wustite": (3.0, 7.5),
    "zno_wurtzite": (3.0, 8.0),
}

MIN_GAP = 1e-4  # no pair distance may lie this close to a cutoff (A)
MAX_PAIRS = 200_000  # per neighbour file
RECOMPUTE_TOL = 1e-9  # |d(recomputed from the written text) - d(pymatgen)| (A)

STRUCTURE_HEADER = (
    "# tricell fixture: pymatgen expanded structure of fixtures/structures/{name}.cif "
    "(do not edit; regenerate with scripts/make-fixtures.py)\n"
)
NEIGHBORS_HEADER = "# i j Sa Sb Sc d\n"
MANIFEST_HEADER = "# file\tkind\tsites\tpairs\tcutoff\tpymatgen\n"


def fmt(x):
    """A real with 17 significant digits (reads back to the same double)."""
    return "%.17g" % float(x)


def fail(msg):
    raise SystemExit(f"make-fixtures.py: {msg}")


def load_structure(cif_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "fractional coordinates rounded to ideal values", ...
        structure = CifParser(cif_path).get_structures(primitive=False)[0]
    return structure


def declared_site_count(cif_path):
    """Sum of _atom_site_symmetry_multiplicity, if the CIF gives it (else None)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cif = CifFile.from_file(cif_path)
    block = list(cif.data.values())[0]
    mult = block.data.get("_atom_site_symmetry_multiplicity")
    if mult is None or any(m in ("?", ".") for m in mult):
        return None
    return sum(int(m) for m in mult)


def majority_species(site):
    items = list(site.species.items())
    k = max(range(len(items)), key=lambda n: (items[n][1], -n))
    return items[k][0].symbol, items[k][1]


def structure_text(name, structure):
    out = [STRUCTURE_HEADER.format(name=name), "lattice_rows\n"]
    for row in structure.lattice.matrix:
        out.append("\t".join(fmt(v) for v in row) + "\n")
    out.append(f"sites\t{len(structure)}\n")
    for site in structure:
        symbol, occupancy = majority_species(site)
        fields = [symbol]
        fields += [fmt(v) for v in site.frac_coords]
        fields += [fmt(v) for v in site.coords]
        fields.append(fmt(occupancy))
        out.append("\t".join(fields) + "\n")
    return "".join(out)


def parse_structure_text(text):
    """Read back lattice rows and Cartesian coordinates from structure_text's output."""
    lines = [ln for ln in text.splitlines() if not ln.startswith("#")]
    assert lines[0] == "lattice_rows"
    lattice = np.array([[float(v) for v in ln.split("\t")] for ln in lines[1:4]])
    key, n = lines[4].split("\t")
    assert key == "sites"
    cart = np.array([[float(v) for v in ln.split("\t")[4:7]] for ln in lines[5 : 5 + int(n)]])
    assert len(cart) == int(n)
    return lattice, cart


def neighbor_rows(structure, cutoff):
    """pymatgen's full neighbour list as sorted integer arrays plus distances."""
    center, points, images, distances = structure.get_neighbor_list(cutoff)
    images_int = np.rint(images).astype(np.int64)
    if not np.array_equal(images_int, images):
        fail("pymatgen returned non-integer images")
    order = np.lexsort((images_int[:, 2], images_int[:, 1], images_int[:, 0], points, center))
    return center[order], points[order], images_int[order], distances[order]


def neighbors_text(i, j, s, d):
    out = [NEIGHBORS_HEADER]
    for a, b, (sa, sb, sc), dist in zip(i.tolist(), j.tolist(), s.tolist(), d.tolist()):
        out.append(f"{a}\t{b}\t{sa}\t{sb}\t{sc}\t{fmt(dist)}\n")
    return "".join(out)


def check_pairs(label, cutoff, lattice, cart, i, j, s, d):
    """Sanity checks on one neighbour list, using the coordinates as written to text."""
    if len(d) > MAX_PAIRS:
        fail(f"{label}: {len(d)} pairs, more than {MAX_PAIRS}; choose a smaller cutoff")
    if len(d) == 0:
        fail(f"{label}: no pairs; choose a larger cutoff")
    # D = x_j + H S - x_i with H's columns = the lattice rows written
    disp = cart[j] + s.astype(float) @ lattice - cart[i]
    dist = np.sqrt(np.einsum("ij,ij->i", disp, disp))
    err = np.max(np.abs(dist - d))
    if err > RECOMPUTE_TOL:
        fail(f"{label}: recomputed distances differ from pymatgen's by {err:g} A")
    gap = np.min(np.abs(d - cutoff))
    if gap < MIN_GAP:
        fail(f"{label}: a pair distance is within {gap:g} A of the cutoff; choose another cutoff")
    if np.any((i == j) & np.all(s == 0, axis=1)):
        fail(f"{label}: the self pair (i, i, 0) is present")
    keys = set(zip(i.tolist(), j.tolist(), map(tuple, s.tolist())))
    if len(keys) != len(d):
        fail(f"{label}: duplicate pairs")
    for a, b, (sa, sb, sc) in keys:
        if (b, a, (-sa, -sb, -sc)) not in keys:
            fail(f"{label}: pair ({a}, {b}, {sa} {sb} {sc}) has no reverse")


def check_pymatgen_semantics():
    """Assert the pymatgen behaviour the docstring describes, on a tiny hand-made structure."""
    lattice = Lattice([[3.0, 0.0, 0.0], [0.5, 3.0, 0.0], [0.0, 0.4, 3.0]])
    # atoms 0 and 1 coincide; atom 2 lies outside the cell (fractional > 1 and < 0)
    structure = Structure(
        lattice, ["Cu", "Cu", "Ni"], [[0, 0, 0], [0, 0, 0], [1.5, -0.5, 2.5]],
        coords_are_cartesian=False,
    )
    i, j, s, d = neighbor_rows(structure, 3.05)
    keys = {(a, b, tuple(t)): dist for a, b, t, dist in zip(i.tolist(), j.tolist(), s.tolist(), d)}
    if (0, 0, (0, 0, 0)) in keys or (1, 1, (0, 0, 0)) in keys:
        fail("pymatgen's exclude_self kept (i, i, 0)")
    if keys.get((0, 1, (0, 0, 0))) != 0.0 or keys.get((1, 0, (0, 0, 0))) != 0.0:
        fail("pymatgen's exclude_self dropped coincident distinct atoms")
    if (0, 0, (1, 0, 0)) not in keys:
        fail("pymatgen dropped an atom's own periodic image")
    cart = structure.cart_coords
    disp = cart[j] + s @ lattice.matrix - cart[i]
    if np.max(np.abs(np.linalg.norm(disp, axis=1) - d)) > RECOMPUTE_TOL:
        fail("pymatgen's images do not follow D = x_j + H S - x_i for unwrapped positions")
    # pymatgen includes a pair at exactly the cutoff (d <= r + 1e-8); tricell would not
    i, j, s, d = neighbor_rows(Structure(Lattice.cubic(3.0), ["Cu"], [[0, 0, 0]]), 3.0)
    if len(d) != 6:
        fail(f"expected pymatgen to keep the 6 pairs at d == r, got {len(d)}")


def generate(outdir):
    """Write every reference file into outdir; return {file name: content}."""
    names = sorted(f[:-4] for f in os.listdir(STRUCTURES) if f.endswith(".cif"))
    if not names:
        fail(f"no CIF files in {STRUCTURES}")
    missing = [n for n in names if n not in CUTOFFS]
    if missing:
        fail(f"no cutoffs chosen for {', '.join(missing)}: add them to CUTOFFS")
    check_pymatgen_semantics()
    files = {}
    manifest = [MANIFEST_HEADER]
    for name in names:
        cif_path = os.path.join(STRUCTURES, name + ".cif")
        structure = load_structure(cif_path)
        declared = declared_site_count(cif_path)
        if declared is not None and declared != len(structure):
            fail(f"{name}: CIF multiplicities add up to {declared}, pymatgen expands {len(structure)}")
        text = structure_text(name, structure)
        lattice, cart = parse_structure_text(text)
        fname = f"{name}.structure.tsv"
        files[fname] = text
        manifest.append(f"{fname}\tstructure\t{len(structure)}\t-\t-\t{PYMATGEN_VERSION}\n")
        for cutoff in CUTOFFS[name]:
            fname = f"{name}.neighbors.rc{cutoff:.1f}.tsv"
            i, j, s, d = neighbor_rows(structure, cutoff)
            check_pairs(fname, cutoff, lattice, cart, i, j, s, d)
            files[fname] = neighbors_text(i, j, s, d)
            manifest.append(
                f"{fname}\tneighbors\t{len(structure)}\t{len(d)}\t{cutoff:.1f}\t{PYMATGEN_VERSION}\n"
            )
    files["MANIFEST.tsv"] = "".join(manifest)
    os.makedirs(outdir, exist_ok=True)
    for fname, content in files.items():
        with open(os.path.join(outdir, fname), "w", encoding="ascii", newline="\n") as fh:
            fh.write(content)
    return files


def reference_files():
    if not os.path.isdir(REFERENCE):
        return set()
    return {f for f in os.listdir(REFERENCE) if f.endswith(".tsv")}


# pymatgen's lattice and Cartesian coordinates go through numpy's BLAS, whose kernels differ by
# processor in the last bits (a 1e-16 entry of the lattice matrix, the last digit of a
# coordinate), so --check compares numbers to a relative 1e-12 and everything else exactly.
CHECK_RTOL = 1e-12


def same_up_to_rounding(reference, generated):
    """True when two fixture texts have the same lines and words, numbers equal to CHECK_RTOL."""
    if reference == generated:
        return True
    ref_lines, gen_lines = reference.splitlines(), generated.splitlines()
    if len(ref_lines) != len(gen_lines):
        return False
    for ref_line, gen_line in zip(ref_lines, gen_lines):
        ref_words, gen_words = ref_line.split("\t"), gen_line.split("\t")
        if len(ref_words) != len(gen_words):
            return False
        for a, b in zip(ref_words, gen_words):
            if a == b:
                continue
            try:
                x, y = float(a), float(b)
            except ValueError:
                return False
            if abs(x - y) > CHECK_RTOL * max(1.0, abs(x), abs(y)):
                return False
    return True


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--check",
        action="store_true",
        help="regenerate into a temporary directory and compare with fixtures/reference/",
    )
    args = parser.parse_args()

    if args.check:
        tmp = tempfile.mkdtemp(prefix="tricell-fixtures-")
        try:
            files = generate(tmp)
            drifted = []
            for fname in sorted(files):
                ref = os.path.join(REFERENCE, fname)
                if not os.path.exists(ref):
                    drifted.append(f"{fname} (missing from fixtures/reference)")
                    continue
                with open(ref, encoding="ascii") as fh:
                    if not same_up_to_rounding(fh.read(), files[fname]):
                        drifted.append(f"{fname} (differs)")
            for fname in sorted(reference_files() - set(files)):
                drifted.append(f"{fname} (stale: no longer generated)")
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        if drifted:
            print("fixtures/reference/ is out of date (regenerate with scripts/make-fixtures.py):")
            for line in drifted:
                print(f"  {line}")
            return 1
        print(f"fixtures/reference/ is up to date ({len(files)} files, pymatgen {PYMATGEN_VERSION})")
        return 0

    files = generate(REFERENCE)
    for fname in sorted(reference_files() - set(files)):
        os.remove(os.path.join(REFERENCE, fname))
        print(f"removed stale {fname}")
    print(f"wrote {len(files)} files to fixtures/reference/ (pymatgen {PYMATGEN_VERSION})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
