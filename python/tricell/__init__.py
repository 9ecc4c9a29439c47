"""tricell: periodic neighbour search in general triclinic boxes.

The native part (tricell._tricell, a pybind11 module over the C++ library) provides
NeighborList, VerletList, DisplacementTracker (the Verlet rebuild rule on its own), Rdf,
nearest_neighbors, neighbor_shells (several cutoffs from one search), read() and verify() (any
code's list against an independent search); neighbor_lists gives the lists a model requests
(several cutoffs, full or half) from one search. tricell.ase, tricell.pymatgen,
tricell.mdanalysis and tricell.vesin are drop-in replacements for those codes' neighbour-list
functions built on it.

    import tricell
    nl = tricell.NeighborList(cutoff=5.0)
    i, j, S, d = nl.compute(points, box, periodic=True, quantities="ijSd")

Boxes are 3 x 3 arrays with the lattice vectors as rows (as ASE and pymatgen store them);
D = points[j] - points[i] + S @ box. Bad values raise ValueError, unreadable or malformed
files OSError, with the library's message.
"""
import os
from typing import List, NamedTuple, Tuple

import numpy as np

from ._requests import neighbor_lists
from ._tricell import (DisplacementTracker, NeighborList, Rdf, VerifyReport, VerletList,
                       __version__, _read, backends, nearest_neighbors, neighbor_shells, verify)

__all__ = [
    "NeighborList", "VerletList", "DisplacementTracker", "Rdf", "nearest_neighbors", "Structure",
    "read", "backends", "verify", "VerifyReport", "neighbor_shells", "neighbor_lists",
]


class Structure(NamedTuple):
    """A structure read from a file: lattice vectors as rows, Cartesian positions (N x 3),
    element symbols, periodicity, site occupancies and labels (see tricell.read)."""

    cell: np.ndarray
    positions: np.ndarray
    species: List[str]
    pbc: Tuple[bool, bool, bool]
    occupancies: np.ndarray
    labels: List[str]


def read(path, format=None):
    """Reads a CIF (*.cif), VASP POSCAR/CONTCAR (POSCAR*, CONTCAR*, *.vasp, *.poscar) or
    extended XYZ (*.xyz, *.extxyz) file; format ("cif", "poscar", "xyz") overrides the guess
    from the name. A CIF is expanded to the full unit cell: for each atom-site row in file
    order, its images in symmetry-operator order, wrapped into [0, 1), images of one row closer
    than 0.01 Angstrom kept once (so atoms on special positions appear once); atom indices are
    0-based in that order.
    Raises OSError with "FILE:LINE: what is wrong" for a missing or malformed file."""
    return Structure(*_read(os.fspath(path), format or ""))
