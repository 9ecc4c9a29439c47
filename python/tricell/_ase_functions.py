"""The functions of tricell.ase (neighbor_list, primitive_neighbor_list, first_neighbors),
whose doc says what they promise; tricell._ase_classes builds on primitive_neighbor_list.

ASE's arguments are checked by the native module's rules (tricell._tricell._as_array) under
ASE's names, then one search runs per call: each thread keeps a tricell.NeighborList(grouped=True)
for its last cutoff, whose columns come back as views and are copied once into ASE's dtypes.
A cutoff per atom is the library's per-atom radii, a dict of element pairs its species table;
self_interaction adds each atom's pair with itself by one scatter into the grouped columns,
using the list's per-atom offsets (no sort).
"""
import threading

import numpy as np

from ._tricell import NeighborList as _Search
from ._tricell import _as_array

__all__ = ["neighbor_list", "primitive_neighbor_list", "first_neighbors"]

_EMPTY = {
    "i": (np.int64, (0,)),
    "j": (np.int64, (0,)),
    "d": (np.float64, (0,)),
    "D": (np.float64, (0, 3)),
    "S": (np.int64, (0, 3)),
}


def _result(quantities, columns):
    values = tuple(columns[q] for q in quantities)
    return values[0] if len(values) == 1 else values


def _empty(quantities):
    return _result(quantities, {q: np.zeros(shape, dtype) for q, (dtype, shape) in _EMPTY.items()})


_last_search = threading.local()


def _search(key, cutoff):
    """This thread's tricell.NeighborList(cutoff, grouped=True) for `key`, kept from its last
    call so that repeated calls with the same cutoff reuse the list's memory (one per thread:
    the last)."""
    last = getattr(_last_search, "value", None)
    if last is None or last[0] != key:
        last = (key, _Search(cutoff, grouped=True))
        _last_search.value = last
    return last[1]


def _species_table(cutoff):
    """ASE's dict of element pairs as {(Z_a, Z_b): cutoff} with Z_a <= Z_b: a later key for
    the same two elements replaces an earlier one, and pairs that can never count in ASE
    (cutoff <= 0, a name that is no element) are left out."""
    from ase.data import atomic_numbers

    table = {}
    for (a, b), value in cutoff.items():
        a = atomic_numbers.get(a, a)
        b = atomic_numbers.get(b, b)
        if isinstance(a, str) or isinstance(b, str):
            continue
        table[(min(a, b), max(a, b))] = float(value)
    return {pair: value for pair, value in table.items() if value > 0}


def primitive_neighbor_list(quantities, pbc, cell, positions, cutoff, numbers=None,
                            self_interaction=False, use_scaled_positions=False, max_nbins=1e6):
    """ase.neighborlist.primitive_neighbor_list, computed by tricell (see tricell.ase's doc).

    pbc: three bools; cell: 3 x 3, lattice vectors as rows (zero rows of open axes are
    completed by the library's rule, as ASE completes them); positions: N x 3 Cartesian, or
    fractional with use_scaled_positions; numbers: atomic numbers, needed with a dict cutoff."""
    for q in quantities:
        if q not in _EMPTY:
            raise ValueError("Unsupported quantity specified.")
    positions = _as_array(positions, "positions", "points")
    cell = _as_array(cell, "cell", "box")
    pbc = _as_array(pbc, "pbc", "periodic")
    if not isinstance(cutoff, dict):
        cutoff = _as_array(cutoff, "cutoff", "real")
        if cutoff.ndim != 0 and cutoff.shape != (len(positions),):
            raise ValueError(f"cutoff must be one number or one value per atom, shape "
                             f"({len(positions)},) (got shape {cutoff.shape})")
    elif numbers is not None:  # as in ASE, numbers are read only for a dict cutoff
        numbers = _as_array(numbers, "numbers", "species")
        if len(numbers) != len(positions):
            raise ValueError(f"numbers must have one value per atom, shape ({len(positions)},) "
                             f"(got shape {numbers.shape})")
    if len(positions) == 0:
        return _empty(quantities)
    if use_scaled_positions:
        positions = positions @ cell

    needed = "ij" + "".join(q for q in "SdD" if q in quantities)
    if self_interaction:
        needed += "o"
    if isinstance(cutoff, dict):
        if numbers is None:
            raise ValueError("a cutoff dict of element pairs needs the atomic numbers (numbers=)")
        table = _species_table(cutoff)
        if not table:
            return _empty(quantities)
        search = _search(("species", tuple(sorted(table.items()))), table)
        extra = {"species": numbers}
        # An atom and itself (d = 0) count when its element pair with itself has a cutoff.
        has_self = np.array([table.get((z, z), 0) > 0 for z in numbers.tolist()], dtype=bool)
    elif cutoff.ndim == 0:
        if not cutoff > 0:
            return _empty(quantities)  # ASE keeps d < cutoff: nothing for a cutoff <= 0
        search = _search(("cutoff", float(cutoff)), float(cutoff))
        extra = {}
        has_self = np.ones(len(positions), dtype=bool)
    else:
        search = _search(("radii",), None)
        extra = {"radii": cutoff}
        has_self = cutoff > 0
    # Views of the list's buffers (copy=False): each column is copied once, into ASE's dtype.
    found = search.compute(positions, cell, pbc, needed, copy=False, **extra)
    columns = dict(zip(needed, found))
    if self_interaction:
        return _result(quantities, _with_self_pairs(columns, columns.pop("o"), has_self))
    return _result(quantities, {q: column.astype(_EMPTY[q][0]) for q, column in columns.items()})


def _with_self_pairs(columns, offsets, has_self):
    """Adds (a, a, S = 0) with d = 0, D = 0 for every atom a with has_self[a], first among the
    pairs of a, keeping the grouping by i: one scatter of each column into ASE's dtype, no
    sort."""
    pairs = len(columns["i"])
    selves_to = np.cumsum(has_self)  # self pairs of the atoms 0..a
    atoms = np.flatnonzero(has_self)
    self_at = offsets[atoms] + selves_to[atoms] - 1
    pair_at = np.arange(pairs) + selves_to[columns["i"]]
    merged = {}
    for q, column in columns.items():
        out = np.empty((pairs + len(atoms),) + column.shape[1:], dtype=_EMPTY[q][0])
        out[pair_at] = column
        out[self_at] = atoms if q in "ij" else 0
        merged[q] = out
    return merged


def neighbor_list(quantities, a, cutoff, self_interaction=False, max_nbins=1e6):
    """ase.neighborlist.neighbor_list, computed by tricell: the neighbours of the ase.Atoms
    `a` (its pbc, cell and positions; its atomic numbers for a dict cutoff)."""
    return primitive_neighbor_list(quantities, a.pbc, a.cell.array, a.positions,
                                   cutoff, numbers=a.numbers, self_interaction=self_interaction,
                                   max_nbins=max_nbins)


def first_neighbors(natoms, first_atom):
    """ase.neighborlist.first_neighbors: for i sorted ascending, s with the pairs of atom k at
    s[k]:s[k + 1] (natoms + 1 int64 values)."""
    first_atom = np.asarray(first_atom)
    return np.searchsorted(first_atom, np.arange(natoms + 1), side="left").astype(np.int64)
