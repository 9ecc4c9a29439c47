"""A drop-in replacement for pymatgen's Structure.get_neighbor_list, computed by tricell.

    from tricell.pymatgen import get_neighbor_list
    centers, points, images, distances = get_neighbor_list(structure, 5.0)

Returns what structure.get_neighbor_list(r, numerical_tol=..., exclude_self=...) returns:
centre and neighbour indices (int64), images as float64 lattice translations (N x 3) and
distances, with pymatgen's rule d <= r + numerical_tol and the lattice's periodicity.
exclude_self=False adds each site's pair with itself at image 0 (distance 0), as pymatgen
does; with exclude_self=True (the default) no such pair is reported. Pairs are sorted by
centre, then neighbour, then image. (pymatgen's optional `sites` argument is not supported.)
"""
import numpy as np

from ._tricell import NeighborList

__all__ = ["get_neighbor_list"]


def get_neighbor_list(structure, r, numerical_tol=1e-8, exclude_self=True):
    """Neighbours of every site of a pymatgen Structure within r (d <= r + numerical_tol)."""
    positions = np.asarray(structure.cart_coords, dtype=float).reshape(-1, 3)
    n = len(positions)
    if n == 0:
        return (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros(0))
    lattice = structure.lattice
    pbc = getattr(lattice, "pbc", (True, True, True))
    # d <= r + tol is d < the next double above r + tol.
    cutoff = np.nextafter(float(r) + float(numerical_tol), np.inf)
    i, j, S, d = NeighborList(cutoff, sorted=True).compute(positions, lattice.matrix, pbc, "ijSd")
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
