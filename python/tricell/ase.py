"""Drop-in replacements for ase.neighborlist.neighbor_list, primitive_neighbor_list and
first_neighbors, and for the classes NeighborList, PrimitiveNeighborList and
NewPrimitiveNeighborList, computed by tricell.

    from tricell.ase import neighbor_list
    i, j, d, D, S = neighbor_list("ijdDS", atoms, 5.0)

Same signatures and results as ASE's functions: the letters i, j, d, D, S in any order (one
letter returns an array, several a tuple); i, j and S as int64, d and D as float64, with the
same shapes for an empty result; cutoff a float, one radius per atom (a pair counts when
d < r_i + r_j) or a dict keyed by pairs of element symbols or atomic numbers (a pair of
elements not in it never counts; a later key for the same two elements replaces an earlier
one, as in ASE); self_interaction adds each atom's pair with itself at S = 0, first among
that atom's pairs. Pairs come grouped by i in ascending order, as ASE promises (within one
atom, in the order tricell's search found them); the grouping is one counting pass in the
library, no comparison sort. Each thread keeps its last search, so that repeated calls with
one cutoff reuse its memory. max_nbins is accepted and ignored:
tricell bounds its grid memory by the number of atoms.

The classes take ASE's arguments and return ASE's neighbours after every rebuild: the same
(index, offset) set for each atom, int64 indices (k,) and offsets (k, 3), the same half-list
orientation without bothways; sorted=True orders each atom's neighbours by index, then offset. update() rebuilds by the
library's Verlet rule (tricell.DisplacementTracker) rather than ASE's: when some atom moved by
more than skin - eps * max(cutoffs) since the build (minimum image in the build's frame, eps
the cell's strain; skin for an unchanged cell, as in ASE), or pbc or the atomic numbers
changed. A changed cell alone, or atoms wrapped into the cell, need not rebuild (ASE
rebuilds); between rebuilds the neighbours are the build's candidates, offsets following atoms
that jumped by a lattice vector, and contain every pair within the real cutoffs.

The functions live in tricell._ase_functions, the classes in tricell._ase_classes (whose doc
has the details); the classes build on primitive_neighbor_list, and this module only gathers
both. They only translate arguments: the search, including per-atom and per-pair cutoffs,
runs in the C++ library. Array arguments follow the native module's rules, with errors naming
ASE's arguments: positions, cell, pbc, numbers and cutoff (a TypeError for a kind of value that
is no real number, such as complex, str or object; a ValueError for a wrong shape).
"""
from ._ase_classes import NeighborList, NewPrimitiveNeighborList, PrimitiveNeighborList
from ._ase_functions import first_neighbors, neighbor_list, primitive_neighbor_list

__all__ = ["neighbor_list", "primitive_neighbor_list", "first_neighbors", "NeighborList",
           "PrimitiveNeighborList", "NewPrimitiveNeighborList"]
