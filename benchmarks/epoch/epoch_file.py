"""The epoch file: the structures of every epoch in the concatenated batch format, as
machine-learning codes hold a batch (benchmarks/epoch/README.md).

Little-endian binary: the magic bytes b"TRICELL-EPOCHS-1", a uint32 count of epochs, then for
each epoch a uint32 name length and the name (UTF-8), a float64 cutoff, uint64 B (structures)
and uint64 N (atoms over all structures), followed by the arrays of the batch:
int64 ptr[B + 1] (structure s owns atoms ptr[s]:ptr[s + 1]), float64 cells[B][3][3] (lattice
vectors as rows; all zero for a molecule), uint8 pbc[B][3] and float64 positions[N][3].
epoch_bench.cpp reads the same layout.
"""
import struct
from typing import List, NamedTuple

import numpy as np

MAGIC = b"TRICELL-EPOCHS-1"


class Epoch(NamedTuple):
    name: str
    cutoff: float
    ptr: np.ndarray        # int64, B + 1
    cells: np.ndarray      # float64, B x 3 x 3, rows are lattice vectors
    pbc: np.ndarray        # bool, B x 3
    positions: np.ndarray  # float64, N x 3

    def structures(self):
        """(positions, cell, pbc) of each structure, in order."""
        for s in range(len(self.cells)):
            yield (self.positions[self.ptr[s]:self.ptr[s + 1]], self.cells[s], self.pbc[s])


def write(path, epochs: List[Epoch]):
    with open(path, "wb") as f:
        f.write(MAGIC + struct.pack("<I", len(epochs)))
        for e in epochs:
            name = e.name.encode()
            f.write(struct.pack("<I", len(name)) + name)
            f.write(struct.pack("<dQQ", e.cutoff, len(e.cells), len(e.positions)))
            f.write(np.ascontiguousarray(e.ptr, "<i8").tobytes())
            f.write(np.ascontiguousarray(e.cells, "<f8").tobytes())
            f.write(np.ascontiguousarray(e.pbc, "u1").tobytes())
            f.write(np.ascontiguousarray(e.positions, "<f8").tobytes())


def read(path) -> List[Epoch]:
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(MAGIC):
        raise ValueError(f"{path} is not an epoch file (it does not start with {MAGIC!r})")
    at = len(MAGIC)

    def take(fmt):
        nonlocal at
        values = struct.unpack_from(fmt, data, at)
        at += struct.calcsize(fmt)
        return values

    def array(dtype, count, shape):
        nonlocal at
        a = np.frombuffer(data, dtype, count, at).reshape(shape)
        at += a.nbytes
        return a

    epochs = []
    (count,) = take("<I")
    for _ in range(count):
        (length,) = take("<I")
        name = data[at:at + length].decode()
        at += length
        cutoff, structures, atoms = take("<dQQ")
        ptr = array("<i8", structures + 1, (structures + 1,)).astype(np.int64)
        cells = array("<f8", 9 * structures, (structures, 3, 3)).astype(np.float64)
        pbc = array("u1", 3 * structures, (structures, 3)).astype(bool)
        positions = array("<f8", 3 * atoms, (atoms, 3)).astype(np.float64)
        epochs.append(Epoch(name, cutoff, ptr, cells, pbc, positions))
    if at != len(data):
        raise ValueError(f"{path}: {len(data) - at} bytes after the last epoch")
    return epochs
