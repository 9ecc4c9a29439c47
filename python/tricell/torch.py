"""tricell.torch: a neighbour list for PyTorch tensors, with autograd, usable from TorchScript.

    import torch, tricell.torch
    nl = tricell.torch.NeighborList(cutoff=5.0, full=True)
    i, j, S, D, d = nl(points, box, [True, True, True], "ijSDd")

The pairs (i, j, S) come from the op torch.ops.tricell.neighbor_pairs (the op library
_tricell_torch.so next to this file, loaded on import), which runs tricell's search on detached
float64 copies and returns int64 tensors. D = points[j] - points[i] + S @ box and d = |D| are
computed here with ordinary torch ops, so gradients flow through points and box, in eager mode
and in TorchScript alike; D and d have the dtype of the inputs (float32 or float64). Boxes have
the lattice vectors as rows; periodic is a list of three bools.

Importing raises ImportError when the op library was not built (tricell configured without
libtorch, or the sanitizer build) or when PyTorch is missing.
"""
import os

_OP_LIBRARY = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_tricell_torch.so")
if not os.path.exists(_OP_LIBRARY):
    raise ImportError(
        f"tricell.torch needs the op library {_OP_LIBRARY}, which was not built: configure "
        "tricell with libtorch installed (Debian: apt-get install libtorch-dev python3-torch) "
        "and TRICELL_BUILD_TORCH=ON, outside a sanitizer build",
        name="tricell._tricell_torch", path=_OP_LIBRARY)

from typing import List  # noqa: E402

import torch  # noqa: E402

torch.ops.load_library(_OP_LIBRARY)

__all__ = ["NeighborList", "QUANTITIES"]

QUANTITIES = "ijSDd"
"""The letters compute() takes: i, j (int64), S (int64, pairs x 3), D (pairs x 3), d."""


class NeighborList(torch.nn.Module):
    """Periodic neighbour list of a cutoff for torch tensors (see the module docstring).

    NeighborList(cutoff, full=True): pairs with d < cutoff, except (i, i, 0); full=False keeps
    each pair once (i < j, or i == j with S lexicographically positive), as tricell.NeighborList
    does. Calling the module is compute(points, box, periodic, quantities)."""

    cutoff: float
    full: bool
    letters: torch.jit.Final[str] = QUANTITIES

    def __init__(self, cutoff: float, full: bool = True):
        super().__init__()
        self.cutoff = float(cutoff)
        self.full = bool(full)

    def forward(self, points: torch.Tensor, box: torch.Tensor, periodic: List[bool],
                quantities: str = QUANTITIES) -> List[torch.Tensor]:
        return self.compute(points, box, periodic, quantities)

    @torch.jit.export
    def compute(self, points: torch.Tensor, box: torch.Tensor, periodic: List[bool],
                quantities: str = QUANTITIES) -> List[torch.Tensor]:
        """The tensors of the letters of quantities, in their order, for N x 3 points and a
        3 x 3 box (rows are lattice vectors) of one dtype on the CPU."""
        for letter in quantities:
            if letter not in self.letters:
                raise ValueError(f"quantities: unknown letter '{letter}' in '{quantities}' "
                                 f"(letters of '{self.letters}')")
        i, j, S = torch.ops.tricell.neighbor_pairs(points, box, periodic, self.cutoff, self.full)
        D = torch.empty(0)
        d = torch.empty(0)
        if "D" in quantities or "d" in quantities:
            D = points.index_select(0, j) - points.index_select(0, i) + S.to(box.dtype) @ box
            d = torch.linalg.norm(D, dim=1)
        out: List[torch.Tensor] = []
        for letter in quantities:
            if letter == "i":
                out.append(i)
            elif letter == "j":
                out.append(j)
            elif letter == "S":
                out.append(S)
            elif letter == "D":
                out.append(D)
            else:
                out.append(d)
        return out

    def extra_repr(self) -> str:
        return f"cutoff={self.cutoff}, full={self.full}"
