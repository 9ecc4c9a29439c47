"""A drop-in replacement for pymatgen's Structure.get_neighbor_list, computed by tricell.

    from tricell.pymatgen import get_neighbor_list
    centers, points, images, distances = get_neighbor_list(structure, 5.0)

Returns what structure.get_neighbor_list(r, numerical_tol=..., exclude_self=...) returns:
centre and neighbour indices (int64), images as float64 lattice translations (N x 3) and
distances, with pymatgen's rule d <= r + numerical_tol and the lattice's periodicity.
exclude_self=False adds each site's pair with itself at image 0 (distance 0), as pymatgen
does; with exclude_self=True (the default) no such pair is reported. Pairs are sorted by
centre, then neighbour, then image. (pymatgen's optional `sites` argument is not supported.)
Arrays follow the native module's rules, with TypeError and ValueError naming
structure.cart_coords, structure.lattice.matrix, structure.lattice.pbc, r or numerical_tol.
"""
import numpy as np

from ._tricell import NeighborList, _as_array

__all__ = ["get_neighbor_list"]


def _number(value, name):
    """One real number (float or int), with the native module's TypeError for other kinds."""
    value = _as_array(value, name, "real")
    if value.ndim != 0:
        raise ValueError(f"{name} must be one number (got shape {value.shape})")
    return float(value)


def get_neighbor_list(structure, r, numerical_tol=1e-8, exclude_self=True):
    """Neighbours of every site of a pymatgen Structure within r (d <= r + numerical_tol)."""
    r, numerical_tol = _number(r, "r"), _number(numerical_tol, "numerical_tol")
    positions = _as_array(structure.cart_coords, "structure.cart_coords", "points")
    n = len(positions)
    if n == 0:
        return (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros(0))
    lattice = structure.lattice
    matrix = _as_array(lattice.matrix, "structure.lattice.matrix", "box")
    pbc = _as_array(getattr(lattice, "pbc", True), "structure.lattice.pbc", "periodic")
    # d <= r + tol is d < the next double above r + tol.
    cutoff = np.nextafter(r + numerical_tol, np.inf)
    i, j, S, d = NeighborList(cutoff, sorted=True).compute(positions, matrix, pbc, "ijSd")
    centers, points, images = i.astype(np.int64), j.astype(np.int64), S.astype(np.float64)
    if not exclude_self:
        atoms = np.arange(n, dtype=np.int64)
        centers = np.concatenate([centers, atoms])
        points = np.concatenate([points, atoms])
        images = np.concatenate([images, np.zeros((n, 3))])
        d = np.concatenate([d, np.zeros(n)])
        order = np.lexsort((images[:, 2], images[:, 1], images[:, 0], points, centers))
        centers, points, images, d = centers[order], points[order], images[order], d[order]
    return centers, points, images, d
