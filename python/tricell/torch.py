"""tricell.torch: a neighbour list for PyTorch tensors, with autograd, usable from TorchScript.

    import torch, tricell.torch
    nl = tricell.torch.NeighborList(cutoff=5.0, full=True)
    i, j, S, D, d = nl(points, box, [True, True, True], "ijSDd")
    offsets, i, j, S, D, d = nl.compute_batch(points, boxes, pbc, batch_ptr, "ijSDd")
    mapping, system_mapping, shifts_idx = tricell.torch.torchsim_nl(
        positions, cell, pbc, cutoff, system_idx)

The pairs (i, j, S) come from the ops torch.ops.tricell.neighbor_pairs (one structure) and
torch.ops.tricell.batch_pairs (a batch in the concatenated layout) of the op library
_tricell_torch.so next to this file, loaded on import; they run tricell's search on detached
float64 copies and return int64 tensors. D = points[j] - points[i] + S @ box comes from the op
torch.ops.tricell.pair_vectors with d = |D|, which has a backward (and double backward) pass,
so gradients flow through points and every box, in eager mode and in TorchScript
alike; D and d have the dtype of the inputs (float32 or float64). Boxes have the lattice
vectors as rows.

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

from typing import List, Tuple  # noqa: E402

import torch  # noqa: E402

torch.ops.load_library(_OP_LIBRARY)

__all__ = ["NeighborList", "QUANTITIES", "torchsim_nl", "neighbor_lists", "neighbor_lists_batch"]

QUANTITIES = "ijSDd"
"""The letters compute() takes: i, j (int64), S (int64, pairs x 3), D (pairs x 3), d."""


class NeighborList(torch.nn.Module):
    """Periodic neighbour list of a cutoff for torch tensors (see the module docstring).

    NeighborList(cutoff, full=True, threads=1, max_neighbors=0, tie_tolerance=0.0,
    symmetric=False): pairs with d < cutoff, except (i, i, 0); full=False keeps each pair once
    (i < j, or i == j with S lexicographically positive), as tricell.NeighborList does; threads
    work across the structures of compute_batch (0: every core). max_neighbors=k > 0 keeps the
    k nearest within the cutoff of each centre (a full list, each centre's pairs nearest first,
    ties by (d, j, S)), with every pair within tie_tolerance of the k-th distance too, and with
    symmetric=True (j, i, -S) wherever (i, j, S) is kept. Calling the module is
    compute(points, box, periodic, quantities)."""

    cutoff: float
    full: bool
    threads: int
    max_neighbors: int
    tie_tolerance: float
    symmetric: bool

    def __init__(self, cutoff: float, full: bool = True, threads: int = 1,
                 max_neighbors: int = 0, tie_tolerance: float = 0.0, symmetric: bool = False):
        super().__init__()
        self.cutoff = float(cutoff)
        self.full = bool(full)
        self.threads = int(threads)
        self.max_neighbors = int(max_neighbors)
        self.tie_tolerance = float(tie_tolerance)
        self.symmetric = bool(symmetric)

    def forward(self, points: torch.Tensor, box: torch.Tensor, periodic: List[bool],
                quantities: str = QUANTITIES) -> List[torch.Tensor]:
        return self.compute(points, box, periodic, quantities)

    @torch.jit.export
    def compute(self, points: torch.Tensor, box: torch.Tensor, periodic: List[bool],
                quantities: str = QUANTITIES) -> List[torch.Tensor]:
        """The tensors of the letters of quantities, in their order, for N x 3 points and a
        3 x 3 box (rows are lattice vectors) of one dtype on the CPU."""
        _check_quantities(quantities)
        i, j, S = torch.ops.tricell.neighbor_pairs(points, box, periodic, self.cutoff, self.full,
                                                   False, self.max_neighbors, self.tie_tolerance,
                                                   self.symmetric)
        D, d = torch.empty(0), torch.empty(0)
        if "D" in quantities or "d" in quantities:
            D, d = _vectors(points, box, i, j, S)
        return _columns(quantities, i, j, S, D, d)

    @torch.jit.export
    def compute_batch(self, points: torch.Tensor, boxes: torch.Tensor, periodic: torch.Tensor,
                      batch_ptr: torch.Tensor, quantities: str = QUANTITIES) -> List[torch.Tensor]:
        """The lists of a batch in one call, in the concatenated layout: points N x 3 (all
        structures one after the other), boxes B x 3 x 3 (rows are lattice vectors; one 3 x 3
        box for all), periodic B x 3 or 3 bools, batch_ptr B + 1 integers (structure s owns
        rows batch_ptr[s]:batch_ptr[s + 1]). Returns [offsets, *the letters of quantities]:
        structure s owns pairs offsets[s]:offsets[s + 1]; i and j index the rows of points; D
        and d flow gradients to points and to each structure's box."""
        _check_quantities(quantities)
        count = batch_ptr.shape[0] - 1 if batch_ptr.dim() == 1 else -1
        if boxes.dim() == 2 and count >= 0:
            boxes = boxes.expand(count, 3, 3)
        if periodic.dim() == 1 and count >= 0:
            periodic = periodic.expand(count, 3)
        i, j, S, offsets, _ = torch.ops.tricell.batch_pairs(
            points, boxes, periodic, batch_ptr, self.cutoff, self.full, self.threads, [],
            self.max_neighbors, self.tie_tolerance, self.symmetric)
        D, d = torch.empty(0), torch.empty(0)
        if "D" in quantities or "d" in quantities:
            D, d = _batch_vectors(points, boxes, i, j, S, offsets)
        return [offsets] + _columns(quantities, i, j, S, D, d)

    def extra_repr(self) -> str:
        text = f"cutoff={self.cutoff}, full={self.full}, threads={self.threads}"
        if self.max_neighbors > 0:
            text += (f", max_neighbors={self.max_neighbors}, tie_tolerance={self.tie_tolerance}"
                     f", symmetric={self.symmetric}")
        return text


def _check_quantities(quantities: str):
    """ValueError naming a letter of quantities that is not one of QUANTITIES."""
    for letter in quantities:
        if letter not in "ijSDd":  # QUANTITIES (TorchScript reads no global string)
            raise ValueError(f"quantities: unknown letter '{letter}' in '{quantities}' "
                             f"(letters of 'ijSDd')")


def _vectors(points: torch.Tensor, box: torch.Tensor, i: torch.Tensor, j: torch.Tensor,
             S: torch.Tensor) -> Tuple[torch.Tensor, torch.Tensor]:
    """D = points[j] - points[i] + S @ box and d = |D|, differentiable in points and box (the op
    pair_vectors with one structure)."""
    offsets = torch.tensor([0, i.shape[0]], dtype=torch.int64)
    return torch.ops.tricell.pair_vectors(points, box.unsqueeze(0), i, j, S, offsets)


def _batch_vectors(points: torch.Tensor, boxes: torch.Tensor, i: torch.Tensor, j: torch.Tensor,
                   S: torch.Tensor, offsets: torch.Tensor) -> Tuple[torch.Tensor, torch.Tensor]:
    """D = points[j] - points[i] + S @ boxes[s] and d = |D| for the pairs of each structure s
    (contiguous, structure s owning pairs offsets[s]:offsets[s + 1]), differentiable in points
    and every box (the op pair_vectors: one pass over the pairs, no copy of a box per pair)."""
    return torch.ops.tricell.pair_vectors(points, boxes, i, j, S, offsets)


def _columns(quantities: str, i: torch.Tensor, j: torch.Tensor, S: torch.Tensor,
             D: torch.Tensor, d: torch.Tensor) -> List[torch.Tensor]:
    """The tensors of the letters of quantities, in their order (D and d empty unless asked)."""
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


def torchsim_nl(positions: torch.Tensor, cell: torch.Tensor, pbc: torch.Tensor, cutoff: float,
                system_idx: torch.Tensor, self_interaction: bool = False
                ) -> Tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """TorchSim's neighbour-list function (torch_sim.neighbors.torchsim_nl), one tricell batch
    call for all systems: the full list of every system within cutoff.

    positions [N, 3]; cell [B, 3, 3] or [3, 3] (rows are lattice vectors); pbc [B, 3] or [3];
    system_idx [N] integers, the system of each atom, each system's atoms contiguous and in
    order (B = len(cell), or system_idx.max() + 1 for one 3 x 3 cell). Returns mapping [2, P]
    int64 (i, j, indices into positions), system_mapping [P] int64 and shifts_idx [P, 3] in the
    dtype of positions, with positions[j] - positions[i] + shifts_idx @ cell[system] the
    pair's vector; self_interaction=True appends (k, k, 0) for every atom. On the device of
    positions (the search runs on the CPU)."""
    if system_idx.dim() != 1 or system_idx.shape[0] != positions.shape[0]:
        raise ValueError(f"torchsim_nl: system_idx must have one entry per atom, shape "
                         f"[{positions.shape[0]}] (got shape {list(system_idx.shape)})")
    if system_idx.is_floating_point() or system_idx.dtype == torch.bool:
        raise ValueError(f"torchsim_nl: system_idx must hold integers (got {system_idx.dtype})")
    if pbc.is_floating_point() or pbc.is_complex():
        raise ValueError(f"torchsim_nl: pbc must be bools (got {pbc.dtype})")
    device = positions.device
    systems = system_idx.detach().to(torch.device("cpu"), torch.int64)
    if cell.dim() == 3:
        count = cell.shape[0]
    elif systems.shape[0] > 0:
        count = int(systems.max()) + 1
    else:
        count = 1
    if systems.shape[0] > 0:
        steps = systems[1:] - systems[:-1]
        if bool((steps < 0).any()):
            k = int(torch.nonzero(steps < 0)[0, 0]) + 1
            raise ValueError(f"torchsim_nl: system_idx must not decrease, each system's atoms "
                             f"contiguous (got system_idx[{k}] = {int(systems[k])} after "
                             f"system_idx[{k - 1}] = {int(systems[k - 1])})")
        if int(systems[0]) < 0 or int(systems[-1]) >= count:
            raise ValueError(f"torchsim_nl: system_idx must lie in [0, {count}), one system per "
                             f"cell (got values from {int(systems[0])} to {int(systems[-1])})")
    ptr = torch.zeros(count + 1, dtype=torch.int64)
    ptr[1:] = torch.cumsum(torch.bincount(systems, minlength=count), 0)
    cpu = torch.device("cpu")
    cells = cell.detach().to(cpu)
    flags = pbc.detach().to(cpu, torch.bool)
    if cells.dim() == 2:
        cells = cells.expand(count, 3, 3)
    if flags.dim() == 1:
        flags = flags.expand(count, 3)
    i, j, S, offsets, _ = torch.ops.tricell.batch_pairs(
        positions.detach().to(cpu), cells, flags, ptr, float(cutoff), True, 1)
    system_mapping = torch.repeat_interleave(torch.arange(count), offsets[1:] - offsets[:-1])
    mapping = torch.stack([i, j])
    shifts = S.to(positions.dtype)
    if self_interaction:
        atoms = torch.arange(positions.shape[0])
        mapping = torch.cat([mapping, torch.stack([atoms, atoms])], dim=1)
        system_mapping = torch.cat([system_mapping, systems])
        shifts = torch.cat([shifts, torch.zeros(positions.shape[0], 3, dtype=shifts.dtype)])
    return mapping.to(device), system_mapping.to(device), shifts.to(device)



def _requested_cutoffs(requests: List[Tuple[float, bool]]) -> Tuple[List[float], bool]:
    """The distinct cutoffs of the requests, increasing, and whether every request is full
    (then the search is a full list; otherwise a half list, full lists derived from it)."""
    if len(requests) == 0:
        raise ValueError("requests must hold at least one request (got none)")
    cutoffs: List[float] = []
    search_full = True
    for request in requests:
        if request[0] not in cutoffs:
            cutoffs.append(request[0])
        search_full = search_full and request[1]
    return sorted(cutoffs), search_full


def _with_reversals(i: torch.Tensor, j: torch.Tensor, S: torch.Tensor
                    ) -> Tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """A full list from a half one: each pair, then each reversed (j, i, -S)."""
    return torch.cat([i, j]), torch.cat([j, i]), torch.cat([S, -S])


def neighbor_lists(points: torch.Tensor, box: torch.Tensor, periodic: List[bool],
                   requests: List[Tuple[float, bool]], quantities: str = QUANTITIES
                   ) -> List[List[torch.Tensor]]:
    """The lists of several requests (cutoff, full) from one search at the largest cutoff
    (torch.ops.tricell.neighbor_shells): one list of tensors per request, in their order, the
    letters of quantities as NeighborList(cutoff, full).compute gives them, with exactly its
    pairs (in the order of the shells) and D and d differentiable in points and box."""
    _check_quantities(quantities)
    cutoffs, search_full = _requested_cutoffs(requests)
    i, j, S, offsets = torch.ops.tricell.neighbor_shells(points, box, periodic, cutoffs,
                                                         search_full)
    out: List[List[torch.Tensor]] = []
    for request in requests:
        n = int(offsets[cutoffs.index(request[0]) + 1])
        ri, rj, rS = i[:n], j[:n], S[:n]
        if request[1] and not search_full:
            ri, rj, rS = _with_reversals(ri, rj, rS)
        D, d = torch.empty(0), torch.empty(0)
        if "D" in quantities or "d" in quantities:
            D, d = _vectors(points, box, ri, rj, rS)
        out.append(_columns(quantities, ri, rj, rS, D, d))
    return out


def neighbor_lists_batch(points: torch.Tensor, boxes: torch.Tensor, periodic: torch.Tensor,
                         batch_ptr: torch.Tensor, requests: List[Tuple[float, bool]],
                         quantities: str = QUANTITIES, threads: int = 1
                         ) -> List[List[torch.Tensor]]:
    """neighbor_lists for a batch in the concatenated layout (as NeighborList.compute_batch
    takes it): one batch search at the largest cutoff, then per request [offsets, *the letters]
    as compute_batch returns them, each structure's pairs exactly those of a separate call (a
    derived full list: each structure's pairs, then their reversals)."""
    _check_quantities(quantities)
    cutoffs, search_full = _requested_cutoffs(requests)
    count = batch_ptr.shape[0] - 1 if batch_ptr.dim() == 1 else -1
    if boxes.dim() == 2 and count >= 0:
        boxes = boxes.expand(count, 3, 3)
    if periodic.dim() == 1 and count >= 0:
        periodic = periodic.expand(count, 3)
    i, j, S, offsets, shell = torch.ops.tricell.batch_pairs(
        points, boxes, periodic, batch_ptr, cutoffs[-1], search_full, threads, cutoffs)
    system = torch.repeat_interleave(torch.arange(count), offsets[1:] - offsets[:-1])
    out: List[List[torch.Tensor]] = []
    for request in requests:
        keep = shell <= cutoffs.index(request[0])
        ri, rj, rS, rsystem = i[keep], j[keep], S[keep], system[keep]
        if request[1] and not search_full:
            ri, rj, rS = _with_reversals(ri, rj, rS)
            order = torch.sort(torch.cat([rsystem, rsystem]), stable=True)[1]
            ri, rj, rS = ri[order], rj[order], rS[order]
            rsystem = torch.cat([rsystem, rsystem])[order]
        kept = torch.zeros(count + 1, dtype=torch.int64)
        kept[1:] = torch.cumsum(torch.bincount(rsystem, minlength=count), 0)
        D, d = torch.empty(0), torch.empty(0)
        if "D" in quantities or "d" in quantities:
            D, d = _batch_vectors(points, boxes, ri, rj, rS, kept)
        out.append([kept] + _columns(quantities, ri, rj, rS, D, d))
    return out
