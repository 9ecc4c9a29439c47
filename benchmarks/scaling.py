#!/usr/bin/python3
"""Cost per atom as the system grows: a full list (i, j, S, d) of random atoms in a triclinic
cell at 0.05 atoms/A^3, cutoff 3.5 A (about 9 pairs per atom), from Python with copy=False,
at 1e5, 1e6 and 1e7 atoms on one and two threads.

Each (size, threads, build) runs in a fresh process of its own, one after another, so that its
first call meets memory the process never touched: the first call is timed apart, then the
best of --repeat further calls, each after the previous result was dropped (the NeighborList
then writes into the same buffers again). Printed per run: pairs; the first and the best warm
call (s, and ns per atom) and their ratio; the CPU time of all threads in the first and the
least in a warm call (s; less disturbed than the wall time by other processes on the core);
the minor page faults of the first and the last call; the growth of the resident peak over the
calls (the list and the search's O(N) memory) over the returned arrays; and the time to touch
fresh memory of the list's size once per page, the floor of a first call, which writes its list
into pages the system must first find and zero. Then the warm cost per atom of each size over
the smallest size's, and the speed-up of more threads.

  /usr/bin/python3 benchmarks/scaling.py [--build DIR ...] [--sizes 1e5,1e6,1e7]
                                         [--threads 1,2] [--repeat 3] [--rounds 1]
                                         [--core 1] [--cores 0,1]

One thread runs pinned to --core, two threads to --cores (taskset). Several --build directories
are interleaved round by round (an A/B run); with --rounds K each figure is the median of the
K rounds. A 1e7-atom run holds about 3.5 GB; runs never overlap.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

DENSITY = 0.05  # atoms per cubic Angstrom
CUTOFF = 3.5
QUANTITIES = "ijSd"
BYTES_PER_PAIR = 4 + 4 + 12 + 8


def child(n, threads, repeat):
    import mmap
    import resource
    import time

    import numpy as np
    import tricell

    rng = np.random.default_rng(12345)
    unit = np.array([[1.0, 0.0, 0.0], [0.25, 1.05, 0.0], [-0.2, 0.15, 0.95]])
    cell = unit * (n / DENSITY / abs(np.linalg.det(unit))) ** (1 / 3)
    points = rng.random((n, 3)) @ cell
    nl = tricell.NeighborList(CUTOFF, full=True, threads=threads)

    def faults():
        return resource.getrusage(resource.RUSAGE_SELF).ru_minflt

    with open("/proc/self/statm") as f:  # resident before the first call
        resident = int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    times, cpu, fault_counts, pairs = [], [], [], 0
    for _ in range(1 + repeat):
        before = faults()
        start, start_cpu = time.perf_counter(), time.process_time()
        result = nl.compute(points, cell, True, QUANTITIES, copy=False)
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
        fault_counts.append(faults() - before)
        pairs = len(result[0])
        del result
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    del nl  # its lists' memory goes back to the system
    # The floor of a first call: the first touch of fresh memory of the list's size, advised for
    # huge pages as the list's columns are.
    fresh = mmap.mmap(-1, max(pairs * BYTES_PER_PAIR, mmap.PAGESIZE))
    if hasattr(mmap, "MADV_HUGEPAGE"):
        fresh.madvise(mmap.MADV_HUGEPAGE)
    pages = np.frombuffer(fresh, dtype=np.uint8)
    start = time.perf_counter()
    pages[::mmap.PAGESIZE] = 1
    touch = time.perf_counter() - start
    del pages
    fresh.close()
    print(json.dumps({"pairs": pairs, "times": times, "cpu": cpu, "faults": fault_counts, "peak": peak,
                      "before": resident, "touch": touch}))


def run(build, n, threads, repeat, cpus):
    env = dict(os.environ, PYTHONPATH=os.path.join(os.path.abspath(build), "python"))
    cmd = ["taskset", "-c", cpus, sys.executable, os.path.abspath(__file__), "--child",
           str(n), str(threads), str(repeat)]
    out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "--child":
        child(int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]))
        return
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--build", action="append", help="build directory (repeat for an A/B run)")
    p.add_argument("--sizes", default="1e5,1e6,1e7")
    p.add_argument("--threads", default="1,2")
    p.add_argument("--repeat", type=int, default=3, help="warm calls after the first")
    p.add_argument("--rounds", type=int, default=1)
    p.add_argument("--core", default="1", help="the core of one-thread runs")
    p.add_argument("--cores", default="0,1", help="the cores of multi-thread runs")
    a = p.parse_args()
    builds = a.build or [os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build")]
    sizes = [int(float(s)) for s in a.sizes.split(",")]
    thread_counts = [int(t) for t in a.threads.split(",")]

    results = {}  # (build, n, threads) -> list of rounds
    for _ in range(a.rounds):
        for n in sizes:
            for t in thread_counts:
                for b in builds:
                    r = run(b, n, t, a.repeat, a.core if t == 1 else a.cores)
                    results.setdefault((b, n, t), []).append(r)

    def med(values):
        return statistics.median(values)

    print("random triclinic, %g atoms/A^3, rc %g, full list %s from Python (copy=False); "
          "median of %d round(s); warm = best of %d calls after the first"
          % (DENSITY, CUTOFF, QUANTITIES, a.rounds, a.repeat))
    print("%-24s %9s %3s %10s %8s %8s %8s %8s %6s %8s %8s %9s %9s %6s %7s" % (
        "build", "atoms", "thr", "pairs", "first s", "warm s", "first ns", "warm ns", "f/w",
        "cpu 1st", "cpu warm", "faults 1st", "faults warm", "peak/list", "touch s"))
    warm_ns = {}
    for b in builds:
        for n in sizes:
            for t in thread_counts:
                rounds = results[(b, n, t)]
                first = med([r["times"][0] for r in rounds])
                warm = med([min(r["times"][1:]) for r in rounds])
                pairs = rounds[0]["pairs"]
                list_bytes = pairs * BYTES_PER_PAIR
                peak = med([(r["peak"] - r["before"]) / max(list_bytes, 1) for r in rounds])
                warm_ns[(b, n, t)] = (warm / n * 1e9,
                                      med([min(r["cpu"][1:]) for r in rounds]) / n * 1e9)
                print("%-24s %9d %3d %10d %8.3f %8.3f %8.0f %8.0f %6.2f %8.3f %8.3f %9d %9d %6.2f %7.3f" % (
                    os.path.relpath(b)[-24:], n, t, pairs, first, warm, first / n * 1e9,
                    warm / n * 1e9, first / warm, med([r["cpu"][0] for r in rounds]),
                    med([min(r["cpu"][1:]) for r in rounds]), med([r["faults"][0] for r in rounds]),
                    med([r["faults"][-1] for r in rounds]), peak,
                    med([r["touch"] for r in rounds])))
    for b in builds:
        base = warm_ns[(b, sizes[0], thread_counts[0])]
        for n in sizes[1:]:
            cost = warm_ns[(b, n, thread_counts[0])]
            print("%s: warm cost per atom at %d over %d atoms, %d thread(s): %.2fx (CPU time "
                  "%.2fx)" % (os.path.relpath(b), n, sizes[0], thread_counts[0],
                              cost[0] / base[0], cost[1] / base[1]))
        for t in thread_counts[1:]:
            for n in sizes:
                print("%s: %d threads over %d at %d atoms: %.2fx" % (
                    os.path.relpath(b), t, thread_counts[0], n,
                    warm_ns[(b, n, thread_counts[0])][0] / warm_ns[(b, n, t)][0]))


if __name__ == "__main__":
    main()
