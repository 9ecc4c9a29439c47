"""tricell.vesin: vesin's Python API over tricell, so that code written for vesin runs by
changing its import (``import tricell.vesin as vesin``; ``tricell.vesin.torch`` stands for
vesin-torch).

    from tricell.vesin import NeighborList, ase_neighbor_list
    nl = NeighborList(cutoff=5.0, full_list=True, sorted=False)
    i, j, S, d = nl.compute(points, box, periodic=True, quantities="ijSd")

Names, arguments, defaults, output types and error types are vesin's: i and j (and P) as
uint64, S as int32, d and D in the floating dtype of the points (float64 for integers); a
tuple of arrays even for one letter; ``skin`` > 0 keeps the candidates of a Verlet list and
refreshes the pairs within the cutoff (tricell.VerletList); ``sorted=True`` groups the pairs
by increasing i. Points given as torch tensors give torch tensors back, as vesin does. An
argument of the wrong shape raises ValueError, a search the library refuses RuntimeError, with
tricell's message (which names the value). The search is tricell's: the pairs are exactly
those of tricell.NeighborList for the same arguments.
"""
import numpy as np

import tricell

__all__ = ["NeighborList", "ase_neighbor_list", "__version__"]

__version__ = tricell.__version__

_FLOAT64 = np.dtype(np.float64)

_ALGORITHMS = {"auto": "auto", "cell_list": "dense", "brute_force": "direct"}


def _torch_module(points):
    """torch when `points` is a torch tensor (without importing torch otherwise)."""
    if type(points).__module__.startswith("torch"):
        import torch

        if isinstance(points, torch.Tensor):
            return torch
    return None


class NeighborList:
    """A neighbour-list calculator with vesin's interface (vesin.NeighborList).

    :param cutoff: spherical cutoff: pairs with d < cutoff
    :param full_list: each pair twice (i-j and j-i) or once
    :param sorted: pairs grouped by increasing first index i
    :param algorithm: "auto", "cell_list" or "brute_force" (tricell's "auto", "dense" and
        "direct" backends; the result is the same)
    :param skin: > 0 caches the candidates within cutoff + skin (a Verlet list) until an
        atom moved far enough to need a rebuild; the pairs returned are always those within
        the cutoff
    :param n_threads: threads of a search; 0 uses every core
    """

    def __init__(self, cutoff, full_list, sorted=False, algorithm="auto", skin=0.0,
                 n_threads=0):
        self.cutoff = float(cutoff)
        self.full_list = bool(full_list)
        self.sorted = bool(sorted)
        self.skin = float(skin)
        self.n_threads = int(n_threads)
        if self.n_threads < 0:
            raise ValueError("n_threads must be zero or a positive integer")
        self.algorithm = algorithm
        self._error = None
        try:
            if self.skin > 0:
                self._list = tricell.VerletList(self.cutoff, self.skin, full=self.full_list,
                                                threads=self.n_threads)
            else:
                self._list = tricell.NeighborList(self.cutoff, full=self.full_list,
                                                  grouped=self.sorted, threads=self.n_threads,
                                                  backend=_ALGORITHMS[self._algorithm])
        except ValueError as error:  # vesin refuses a bad cutoff or skin when computing
            self._error = str(error)

    @property
    def algorithm(self):
        """The algorithm: "auto", "cell_list" or "brute_force"."""
        return self._algorithm

    @algorithm.setter
    def algorithm(self, value):
        algorithm = str(value).lower()
        if algorithm not in _ALGORITHMS:
            raise ValueError(f"Unknown algorithm '{algorithm}'. Must be one of 'auto', "
                             "'brute_force', or 'cell_list'.")
        self._algorithm = algorithm
        if getattr(self, "_list", None) is not None and self.skin <= 0:
            self._list = tricell.NeighborList(self.cutoff, full=self.full_list,
                                              grouped=self.sorted, threads=self.n_threads,
                                              backend=_ALGORITHMS[algorithm])

    def compute(self, points, box, periodic, quantities="ij", copy=True):
        """The pairs of `points` (N x 3) in `box` (3 x 3, lattice vectors as rows; all zero
        along open axes) with `periodic` (one bool or three), as a tuple of arrays in the
        order of the letters of `quantities`: i, j (uint64), P (N x 2 uint64), S (N x 3
        int32), d and D (the dtype of the points). copy=False may return views of this
        object's buffers."""
        torch = _torch_module(points)
        device = None
        if torch is not None:
            device = points.device
            if points.requires_grad or (isinstance(box, torch.Tensor) and box.requires_grad):
                raise RuntimeError(
                    "NeighborList.compute does not support autograd for torch tensors")
            points = points.detach().cpu().numpy()
            box = box.detach().cpu().numpy() if isinstance(box, torch.Tensor) else box
            if isinstance(periodic, torch.Tensor):
                periodic = periodic.detach().cpu().numpy()
        points, box = np.asarray(points), np.asarray(box)
        periodic = np.asarray(periodic)
        if box.shape != (3, 3):
            raise ValueError("`box` must be a 3x3 matrix")
        if points.ndim != 2 or points.shape[1] != 3:
            raise ValueError("`points` must be a nx3 array")
        if periodic.shape not in ((), (3,)):
            raise ValueError("`periodic` must be a single boolean or a sequence of three "
                             f"booleans, got {periodic} of type {type(periodic)}")
        if box.dtype != points.dtype:
            raise RuntimeError("`points` and `box` must have the same dtype, "
                               f"got {points.dtype} and {box.dtype}")
        for letter in quantities:
            if letter not in "ijPSdD":
                raise ValueError(f"unexpected character in `quantities`: {letter}")
        if self._error is not None:
            raise RuntimeError(self._error)
        floating = points.dtype if points.dtype.kind == "f" else _FLOAT64
        try:
            if self.skin > 0:
                columns = self._list.update(points, box, periodic, quantities or "i")
                copy = False  # update() returns fresh arrays
            else:
                # Views of the list's buffers: each column is then converted or copied once.
                columns = self._list.compute(points, box, periodic, quantities or "i",
                                             copy=False)
        except ValueError as error:
            raise RuntimeError(str(error)) from None
        if len(quantities) == 1:
            columns = (columns,)
        out = []
        for letter, column in zip(quantities, columns):
            if letter in "ijP":
                column = column.astype(np.uint64)
            elif letter in "dD" and floating != _FLOAT64:
                column = column.astype(floating)
            elif copy:
                column = column.copy()
            out.append(column)
        if torch is not None:
            out = [_to_torch(torch, column, device) for column in out]
        return tuple(out)


def _to_torch(torch, column, device):
    """A numpy column as a tensor on `device` (uint64 as torch's uint64 where torch has it,
    else int64)."""
    if column.dtype == np.uint64:
        if hasattr(torch, "uint64"):
            return torch.from_numpy(column.view(np.int64)).view(torch.uint64).to(device)
        column = column.astype(np.int64)
    return torch.from_numpy(np.ascontiguousarray(column)).to(device)


def ase_neighbor_list(quantities, a, cutoff, self_interaction=False, max_nbins=0):
    """vesin.ase_neighbor_list: ase.neighborlist.neighbor_list's interface (one float cutoff,
    no self interaction), the full list sorted by i, in vesin's output types.

    :param quantities: letters among i, j, d, D, S
    :param a: an ase.Atoms
    :param cutoff: the cutoff radius
    :param self_interaction: must be False
    :param max_nbins: ignored, for ASE's signature
    """
    try:
        import ase
    except ImportError:
        raise ImportError("could not import ase, this function requires ase") from None
    if self_interaction:
        raise ValueError("self_interaction=True is not implemented")
    if not isinstance(cutoff, (float, int)):
        raise ValueError("only a single float cutoff is supported")
    if not isinstance(a, ase.Atoms):
        raise TypeError(f"`a` should be ase.Atoms, got {type(a)} instead")
    calculator = NeighborList(cutoff=float(cutoff), full_list=True, sorted=True)
    return calculator.compute(points=a.positions, box=a.cell[:], periodic=a.pbc,
                              quantities=quantities, copy=True)
