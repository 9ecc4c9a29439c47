#!/usr/bin/env python3
"""The ASE drop-in against the native call and ASE's own function, in one run on one pinned
core: random triclinic argon-like systems (density 0.05 per cubic Angstrom, cutoff 6) of 10^4
and 10^5 atoms, "ijSd", medians of interleaved rounds (ASE only for the rounds it can afford).
Columns: the native NeighborList.compute with copies and with views (copy=False), the drop-in
tricell.ase.neighbor_list, and ase.neighborlist.neighbor_list; then the ratios.

    /usr/bin/python3 benchmarks/ase_dropin_bench.py [BUILD_PYTHON_DIR]   # default build/python
"""
import os
import statistics
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "build", "python"))

import numpy as np  # noqa: E402
from ase import Atoms  # noqa: E402
from ase import neighborlist as ase_neighborlist  # noqa: E402

import tricell  # noqa: E402
import tricell.ase  # noqa: E402


def random_system(n, seed=1):
    rng = np.random.default_rng(seed)
    cell = np.array([[1.0, 0, 0], [0.31, 0.95, 0], [-0.22, 0.27, 0.93]])
    cell *= (n / 0.05) ** (1 / 3) / abs(np.linalg.det(cell)) ** (1 / 3)
    return Atoms("Ar%d" % n, positions=rng.random((n, 3)) @ cell, cell=cell, pbc=True)


def seconds(call):
    start = time.perf_counter()
    call()
    return time.perf_counter() - start


def main():
    os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    cutoff = 6.0
    for atoms_count, rounds, ase_rounds in [(10000, 9, 3), (100000, 7, 1)]:
        a = random_system(atoms_count)
        native = tricell.NeighborList(cutoff)
        calls = {
            "native, copies": lambda: native.compute(a.positions, a.cell.array, a.pbc, "ijSd"),
            "native, views": lambda: native.compute(a.positions, a.cell.array, a.pbc, "ijSd",
                                                    copy=False),
            "drop-in": lambda: tricell.ase.neighbor_list("ijSd", a, cutoff),
            "ASE": lambda: ase_neighborlist.neighbor_list("ijSd", a, cutoff),
        }
        times = {name: [] for name in calls}
        for name, call in calls.items():
            if name != "ASE":
                call()  # warm: the lists' memory
        for r in range(rounds):
            for name, call in calls.items():
                if name != "ASE" or r < ase_rounds:
                    times[name].append(seconds(call))
        median = {name: statistics.median(values) for name, values in times.items()}
        pairs = len(native.compute(a.positions, a.cell.array, a.pbc, "i"))
        print(f"random {atoms_count} atoms, {pairs} pairs: " +
              ", ".join(f"{name} {value * 1e3:.1f} ms" for name, value in median.items()))
        print(f"  drop-in / native with copies {median['drop-in'] / median['native, copies']:.2f}, "
              f"/ native views {median['drop-in'] / median['native, views']:.2f}; "
              f"ASE / drop-in {median['ASE'] / median['drop-in']:.0f}")


if __name__ == "__main__":
    main()
