"""tricell.vesin.torch: vesin-torch's NeighborList (vesin_torch, formerly vesin.torch) over
tricell's PyTorch op, usable from TorchScript, so that code written for vesin-torch runs by
changing its import.

    from tricell.vesin.torch import NeighborList
    nl = NeighborList(cutoff=5.0, full_list=True)
    i, j, S, D, d = nl.compute(points, box, periodic=True, quantities="ijSDd")

As vesin-torch: i and j (and P) int64, S int32, D and d in the dtype of the points (float32
or float64) with gradients through the points and the box; periodic a bool or a tensor of
three; a list of tensors in the order of the letters; sorted=True groups the pairs by
increasing i. The pairs come from torch.ops.tricell.neighbor_pairs (tricell.torch), on the
CPU; tensors on another device are searched on the CPU and the results moved back.
"""
from typing import List, Union

import torch

import tricell.torch  # noqa: F401  (loads the op library)

__all__ = ["NeighborList", "__version__"]

__version__ = tricell.__version__


class NeighborList:
    """A neighbour-list calculator with vesin-torch's interface, usable from TorchScript.

    :param cutoff: spherical cutoff: pairs with d < cutoff
    :param full_list: each pair twice (i-j and j-i) or once
    :param sorted: pairs grouped by increasing first index i
    :param algorithm: "auto", "cell_list" or "brute_force" (the result is the same)
    :param n_threads: for vesin's signature (0 or more); the op searches on one thread
    """

    def __init__(self, cutoff: float, full_list: bool, sorted: bool = False,
                 algorithm: str = "auto", n_threads: int = 0):
        if n_threads < 0:
            raise ValueError("n_threads must be zero or a positive integer")
        if algorithm not in ("auto", "cell_list", "brute_force"):
            raise ValueError("Unknown algorithm '" + algorithm + "'. Must be one of 'auto', "
                             "'brute_force', or 'cell_list'.")
        self.cutoff = float(cutoff)
        self.full_list = full_list
        self.sorted = sorted
        self.algorithm = algorithm
        self.n_threads = n_threads

    def compute(self, points: torch.Tensor, box: torch.Tensor,
                periodic: Union[bool, torch.Tensor], quantities: str = "ij",
                copy: bool = True) -> List[torch.Tensor]:
        """The pairs of `points` (N x 3) in `box` (3 x 3, lattice vectors as rows; all zero
        along open axes) with `periodic` (a bool or three), as tensors in the order of the
        letters of `quantities` among i, j, P, S, d, D. copy is accepted for vesin's
        signature: the tensors are always the caller's own."""
        for letter in quantities:
            if letter not in "ijPSdD":
                raise ValueError("unexpected character in `quantities`: " + letter)
        if points.device != box.device:
            raise ValueError("expected `points` and `box` to have the same device, got "
                             + str(points.device) + " and " + str(box.device))
        if box.dtype != points.dtype:
            raise RuntimeError("`points` and `box` must have the same dtype, got "
                               + str(points.dtype) + " and " + str(box.dtype))
        if points.device.type == "meta":
            raise RuntimeError("points are on device meta, which holds no values")
        if isinstance(periodic, bool):
            flags = [periodic, periodic, periodic]
        else:
            axes = periodic.to(torch.device("cpu"), torch.bool).reshape(-1)
            if axes.shape[0] not in (1, 3):
                raise ValueError("periodic must be one bool or three (got "
                                 + str(axes.shape[0]) + ")")
            flags = [bool(axes[k % axes.shape[0]]) for k in range(3)]
        device = points.device
        dtype = points.dtype if points.is_floating_point() else torch.float64
        x = points.to(torch.device("cpu"), dtype)
        h = box.to(torch.device("cpu"), dtype)
        i, j, S = torch.ops.tricell.neighbor_pairs(x, h, flags, self.cutoff, self.full_list,
                                                   self.sorted)
        D, d = torch.empty(0), torch.empty(0)
        if "D" in quantities or "d" in quantities:
            offsets = torch.tensor([0, i.shape[0]], dtype=torch.int64)
            D, d = torch.ops.tricell.pair_vectors(x, h.unsqueeze(0), i, j, S, offsets)
        out: List[torch.Tensor] = []
        for letter in quantities:
            if letter == "i":
                out.append(i.to(device))
            elif letter == "j":
                out.append(j.to(device))
            elif letter == "P":
                out.append(torch.stack([i, j], dim=1).to(device))
            elif letter == "S":
                out.append(S.to(torch.int32).to(device))
            elif letter == "D":
                out.append(D.to(device))
            else:
                out.append(d.to(device))
        return out
