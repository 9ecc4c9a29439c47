"""Drop-ins for ASE's neighbour-list classes (ase.neighborlist.NeighborList,
PrimitiveNeighborList, NewPrimitiveNeighborList), re-exported by tricell.ase.

A build searches the pairs with d < (r_i + skin) + (r_j + skin) once, by tricell's per-atom
radii search (tricell._ase_functions.primitive_neighbor_list), and keeps them as the
candidates, each atom's (index, offset) pairs in one flat table. Each later update() asks the library's
rebuild rule (tricell.DisplacementTracker, include/tricell/displacement.hpp) whether the
candidates may miss a pair now; the margin of every pair is 2 * skin and the largest pair
cutoff is 2 * max(r), so the rule rebuilds when some atom moved (minimum image, in the build's
frame) by more than skin - eps * max(r), eps the box's strain since the build: skin while the
cell is unchanged, the same threshold as ASE's. Otherwise update() keeps the candidates and
only moves their offsets along with atoms that jumped by a lattice vector (wrapped), so
positions[j] + offset @ cell - positions[i] stays the same pair's vector.

What update() guarantees: afterwards get_neighbors() contains every pair now within the real
cutoffs (d < r_i + r_j), possibly with others up to the candidates' radius; right after a
rebuild the neighbours are those of ASE's class rebuilt at the same positions (the same set of
(index, offset) per atom, the same half-list orientation).

Where rebuilds differ from ASE's: ASE rebuilds on any change of the cell or pbc and when an
atom's Cartesian coordinates moved more than skin; tricell rebuilds when pbc or the atomic
numbers (numbers=) change, and otherwise only when the rule says so: a changed cell does not
by itself force a rebuild (it shrinks the budget by eps * max(r)), and wrapping atoms into the
cell or moving them by a lattice vector does not count as motion.

Other differences: a cell with zero rows along open axes is completed by the library's rule
(the library's Box, docs/contract.md), as ASE's NeighborList completes it before calling a
primitive class (ASE's NewPrimitiveNeighborList given the zero rows itself misses pairs); each
pair appears once in an atom's list (ASE's PrimitiveNeighborList repeats the self pair with
bothways=True, and pairs with a higher index with sorted=True and bothways=True); sorted=True
orders every atom's neighbours by index, then offset; nneighbors and npbcneighbors count the
pairs of the half list (and those with a nonzero offset) for both primitive classes, where ASE's
NewPrimitiveNeighborList leaves them 0.
"""
import numpy as np

from ._ase_functions import primitive_neighbor_list
from ._tricell import DisplacementTracker, _completed_box

__all__ = ["NeighborList", "PrimitiveNeighborList", "NewPrimitiveNeighborList"]

_NOT_UPDATED = "Must call update(atoms) on your neighborlist first!"


def _lexicographically_positive(v):
    """Rows v with v[0] > 0, or v[0] == 0 and v[1] > 0, or v[0] == v[1] == 0 and v[2] > 0."""
    x, y, z = v.T
    return (x > 0) | ((x == 0) & ((y > 0) | ((y == 0) & (z > 0))))


class _CandidateList:
    """The part both primitive classes share: arguments, candidates, updates. Subclasses say
    which orientation of each pair a half list keeps (_half_mask)."""

    def __init__(self, cutoffs, skin=0.3, sorted=False, self_interaction=True,
                 bothways=False, use_scaled_positions=False):
        try:
            radii = np.asarray(cutoffs, dtype=float)
        except (TypeError, ValueError):
            raise ValueError("cutoffs must be a sequence of numbers, one radius per atom "
                             "(got {!r})".format(cutoffs)) from None
        if radii.ndim != 1:
            raise ValueError("cutoffs must be one radius per atom, a 1-D sequence (got shape "
                             "{})".format(radii.shape))
        if not np.all(np.isfinite(radii)):
            k = int(np.flatnonzero(~np.isfinite(radii))[0])
            raise ValueError("cutoffs[{}] must be finite (got {})".format(k, radii[k]))
        try:
            skin = float(skin)
        except (TypeError, ValueError):
            raise ValueError("skin must be a number (got {!r})".format(skin)) from None
        if not (np.isfinite(skin) and skin >= 0):
            raise ValueError("skin must be finite and >= 0 (got {})".format(skin))
        if np.any(radii + skin < 0):
            k = int(np.flatnonzero(radii + skin < 0)[0])
            raise ValueError("cutoffs[{}] + skin must be >= 0 (got {} + {})"
                             .format(k, radii[k], skin))
        #: The radii of the candidates, cutoff + skin per atom (as ASE stores them).
        self.cutoffs = radii + skin
        self.skin = skin
        self.sorted = bool(sorted)
        self.self_interaction = bool(self_interaction)
        self.bothways = bool(bothways)
        self.use_scaled_positions = bool(use_scaled_positions)
        #: Builds so far.
        self.nupdates = 0
        #: Pairs of the half list of the last build, and those among them with a nonzero offset.
        self.nneighbors = 0
        self.npbcneighbors = 0
        largest = float(radii.max()) if len(radii) else 0.0
        self._tracker = DisplacementTracker(2 * skin, 2 * max(largest, 0.0))
        self._numbers = None

    # -- geometry ------------------------------------------------------------------------------

    def _geometry(self, pbc, cell, positions):
        """(pbc as 3 bools, the completed cell, Cartesian positions), checked."""
        pbc_array = np.asarray(pbc, dtype=bool)
        if pbc_array.shape not in ((), (3,)):
            raise ValueError("pbc must be one bool or three (got shape {})"
                             .format(pbc_array.shape))
        pbc_array = np.broadcast_to(pbc_array, (3,)).copy()
        cell_array = np.asarray(cell, dtype=float)
        if cell_array.shape != (3, 3):
            raise ValueError("cell must be 3 x 3, lattice vectors as rows (got shape {})"
                             .format(cell_array.shape))
        cell_array = _completed_box(cell_array, pbc_array)
        coordinates = np.asarray(positions, dtype=float)
        if coordinates.ndim != 2 or coordinates.shape[1] != 3:
            raise ValueError("positions must be N x 3 (got shape {})".format(coordinates.shape))
        if len(coordinates) != len(self.cutoffs):
            raise ValueError("cutoffs has {} radii for {} atoms (positions)"
                             .format(len(self.cutoffs), len(coordinates)))
        cartesian = coordinates @ cell_array if self.use_scaled_positions else coordinates
        return pbc_array, cell_array, np.ascontiguousarray(cartesian)

    # -- public interface ----------------------------------------------------------------------

    def update(self, pbc, cell, positions, numbers=None):
        """Makes sure the list is up to date for this periodicity (pbc: one bool or three),
        cell (3 x 3, lattice vectors as rows) and positions (N x 3; fractional with
        use_scaled_positions). numbers (optional atomic numbers): a change rebuilds. Returns
        True when it rebuilt the candidates (see the module's doc for when)."""
        pbc, cell, cartesian = self._geometry(pbc, cell, positions)
        numbers = None if numbers is None else np.array(numbers, copy=True)
        same_numbers = (numbers is None or self._numbers is None
                        or np.array_equal(numbers, self._numbers))
        jumps = None
        if self.nupdates > 0 and same_numbers:
            jumps = self._tracker.jumps(cartesian, cell, pbc)
        if jumps is None:
            self._build(pbc, cell, positions, cartesian, numbers)
            return True
        jumps = jumps.astype(np.int64)
        self.offset_vec = (self._build_offsets + jumps[self.pair_second]
                           - jumps[self.pair_first])
        return False

    def build(self, pbc, cell, positions, numbers=None):
        """Builds the list now, whatever the motion (arguments as update())."""
        pbc, cell, cartesian = self._geometry(pbc, cell, positions)
        self._build(pbc, cell, positions, cartesian,
                    None if numbers is None else np.array(numbers, copy=True))

    def get_neighbors(self, a):
        """The neighbours of atom a: (indices, offsets), int64 arrays of shapes (k,) and
        (k, 3); neighbour b's position is positions[b] + offset @ cell. Without bothways a
        pair is listed at one of its two atoms only."""
        if self.nupdates <= 0:
            raise RuntimeError(_NOT_UPDATED)
        count = len(self.first_neigh) - 1
        index = int(a)
        if index < 0:
            index += count
        if not 0 <= index < count:
            raise IndexError("atom index {} is out of range for {} atoms (a)".format(a, count))
        start, stop = self.first_neigh[index], self.first_neigh[index + 1]
        return self.pair_second[start:stop], self.offset_vec[start:stop]

    # -- the build -----------------------------------------------------------------------------

    def _build(self, pbc, cell, positions, cartesian, numbers):
        first, second, offsets = primitive_neighbor_list(
            "ijS", pbc, cell, cartesian, self.cutoffs, self_interaction=self.self_interaction)
        half = self._half_mask(first, second, offsets, pbc, cell, cartesian)
        self.nneighbors = int(half.sum())
        self.npbcneighbors = int(offsets[half].any(axis=1).sum())
        keep = self._kept(first, second, half)
        if keep is not None:
            first, second, offsets = first[keep], second[keep], offsets[keep]
        if self.sorted:
            order = np.lexsort((offsets[:, 2], offsets[:, 1], offsets[:, 0], second, first))
            first, second, offsets = first[order], second[order], offsets[order]
        self.pair_first = first
        self.pair_second = second
        self._build_offsets = offsets
        self.offset_vec = offsets
        self.first_neigh = np.searchsorted(first, np.arange(len(cartesian) + 1)).astype(np.int64)
        self.pbc = pbc
        self.cell = cell
        self._record_positions(np.array(positions, dtype=float, copy=True))
        self._numbers = numbers
        self._tracker.record(cartesian, cell, pbc)
        self.nupdates += 1

    def _kept(self, first, second, half):
        """Which pairs of the full list the list keeps (None: all)."""
        return None if self.bothways else half

    def _record_positions(self, positions):
        self.positions = positions

    def _half_mask(self, first, second, offsets, pbc, cell, cartesian):
        raise NotImplementedError


class NewPrimitiveNeighborList(_CandidateList):
    """ase.neighborlist.NewPrimitiveNeighborList, computed by tricell (see the module's doc).

    cutoffs: one radius per atom (two atoms are neighbours when d < r_i + r_j); skin: the
    margin every radius gets, so that the list survives motion; sorted: order each atom's
    neighbours by index, then offset; self_interaction: list each atom as its own neighbour
    (offset 0); bothways: list every pair at both its atoms (otherwise a pair is listed once,
    at the atom from which its offset is lexicographically positive, or at the lower index
    for offset 0); use_scaled_positions: positions given to update() are fractional.

    After a build: pair_first, pair_second, offset_vec (the pairs, grouped by the first atom)
    and first_neigh (atom a's pairs are first_neigh[a]:first_neigh[a + 1]); pbc, cell and
    positions of the build."""

    def _half_mask(self, first, second, offsets, pbc, cell, cartesian):
        return (_lexicographically_positive(offsets)
                | ((first <= second) & ~offsets.any(axis=1)))


class PrimitiveNeighborList(_CandidateList):
    """ase.neighborlist.PrimitiveNeighborList, computed by tricell (see the module's doc).

    Arguments as NewPrimitiveNeighborList, except where a half list (bothways=False) puts a
    pair: at the atom from which the pair's lattice shift in ASE's Minkowski-reduced cell,
    taken between ASE's wrapped positions, is lexicographically positive (the lower index for
    a zero shift), as ASE's class does; with sorted=True a pair of two different atoms is
    listed at the lower index. update() takes `positions` or, by ASE's name, `coordinates`.

    After a build: neighbors and displacements (per-atom lists of the indices and offsets)
    and the flat pair_first, pair_second, offset_vec, first_neigh; pbc, cell and coordinates
    of the build."""

    def update(self, pbc, cell, coordinates, numbers=None):
        """As NewPrimitiveNeighborList.update (coordinates: N x 3 positions)."""
        return super().update(pbc, cell, coordinates, numbers)

    def build(self, pbc, cell, coordinates, numbers=None):
        """As NewPrimitiveNeighborList.build (coordinates: N x 3 positions)."""
        super().build(pbc, cell, coordinates, numbers)

    @property
    def neighbors(self):
        """Per-atom arrays of the neighbours' indices (as get_neighbors(a)[0])."""
        return [self.get_neighbors(a)[0] for a in range(len(self.first_neigh) - 1)]

    @property
    def displacements(self):
        """Per-atom arrays of the neighbours' offsets (as get_neighbors(a)[1])."""
        return [self.get_neighbors(a)[1] for a in range(len(self.first_neigh) - 1)]

    def _record_positions(self, positions):
        self.coordinates = positions

    def _kept(self, first, second, half):
        if self.sorted:
            # A pair of two atoms is moved to the lower index; an atom's own images stay.
            return (first <= second) if self.bothways else (first < second) | (
                (first == second) & half)
        return super()._kept(first, second, half)

    def _half_mask(self, first, second, offsets, pbc, cell, cartesian):
        """The orientation ASE's class finds each pair in: the one whose shift n in the
        Minkowski-reduced cell (rcell = op @ cell), between the positions wrapped into rcell,
        is lexicographically positive, or zero with first <= second."""
        if len(first) == 0:
            return np.zeros(0, dtype=bool)
        from ase.cell import Cell
        from ase.geometry import minkowski_reduce, wrap_positions

        ase_cell = Cell(cell)
        reduced, op = minkowski_reduce(ase_cell, pbc)
        wrapped = wrap_positions(cartesian, reduced, pbc=pbc, eps=0)
        jump = ase_cell.scaled_positions(wrapped - cartesian).round().astype(np.int64)
        # offset = n @ op + jump[second] - jump[first], op unimodular.
        n = (offsets - jump[second] + jump[first]) @ np.rint(np.linalg.inv(op)).astype(np.int64)
        return _lexicographically_positive(n) | ((first <= second) & ~n.any(axis=1))


_PRIMITIVES = {"PrimitiveNeighborList": PrimitiveNeighborList,
               "NewPrimitiveNeighborList": NewPrimitiveNeighborList}


class NeighborList:
    """ase.neighborlist.NeighborList, computed by tricell (see the module's doc).

    cutoffs: one radius per atom (d < r_i + r_j); skin: the margin that lets the list survive
    motion; sorted, self_interaction, bothways: as in NewPrimitiveNeighborList; primitive: the
    class that does the work, tricell's PrimitiveNeighborList (the default, as in ASE) or
    NewPrimitiveNeighborList; ASE's classes of those names are replaced by tricell's.

        nl = NeighborList(natural_cutoffs(atoms), self_interaction=False, bothways=True)
        nl.update(atoms)
        indices, offsets = nl.get_neighbors(0)

    nl.nl is the primitive list (cutoffs, skin, pair tables, ...)."""

    def __init__(self, cutoffs, skin=0.3, sorted=False, self_interaction=True,
                 bothways=False, primitive=PrimitiveNeighborList):
        if getattr(primitive, "__module__", None) == "ase.neighborlist":
            primitive = _PRIMITIVES.get(getattr(primitive, "__name__", None), primitive)
        self.nl = primitive(cutoffs, skin, sorted, self_interaction=self_interaction,
                            bothways=bothways)

    def update(self, atoms):
        """Makes sure the list is up to date for the ase.Atoms `atoms` (its pbc, cell,
        positions and atomic numbers); returns True when it rebuilt. tricell's primitive
        classes complete the cell themselves; another primitive class gets ASE's completed
        cell, as from ASE's NeighborList."""
        if isinstance(self.nl, _CandidateList):
            return self.nl.update(atoms.pbc, atoms.cell.array, atoms.positions,
                                  numbers=atoms.numbers)
        return self.nl.update(atoms.pbc, atoms.get_cell(complete=True), atoms.positions)

    def get_neighbors(self, a):
        """(indices, offsets) of atom a's neighbours (see NewPrimitiveNeighborList)."""
        if self.nl.nupdates <= 0:
            raise RuntimeError(_NOT_UPDATED)
        return self.nl.get_neighbors(a)

    def get_connectivity_matrix(self, sparse=True):
        """The N x N int8 matrix with 1 at [i, j] when j is among i's neighbours: a scipy
        dok_matrix with sparse=True, a numpy array otherwise (symmetric only with bothways)."""
        if self.nl.nupdates <= 0:
            raise RuntimeError(_NOT_UPDATED)
        if not isinstance(self.nl, _CandidateList):
            from ase.neighborlist import get_connectivity_matrix

            return get_connectivity_matrix(self.nl, sparse)
        count = len(self.nl.cutoffs)
        first = np.repeat(np.arange(count), np.diff(self.nl.first_neigh))
        if not sparse:
            dense = np.zeros((count, count), dtype=np.int8)
            dense[first, self.nl.pair_second] = 1
            return dense
        from scipy import sparse as sp

        links = np.unique(first * count + self.nl.pair_second)
        ones = np.ones(len(links), dtype=np.int8)
        return sp.coo_matrix((ones, (links // count, links % count)), shape=(count, count),
                             dtype=np.int8).todok()

    @property
    def nupdates(self):
        """Builds so far."""
        return self.nl.nupdates

    @property
    def nneighbors(self):
        """Pairs of the half list of the last build."""
        return self.nl.nneighbors

    @property
    def npbcneighbors(self):
        """Pairs of the half list of the last build with a nonzero offset."""
        return self.nl.npbcneighbors
