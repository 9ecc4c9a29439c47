#!/usr/bin/python3
"""The epoch benchmark: every way of computing the neighbour lists of a machine-learning
epoch, on the same structures in the same run (benchmarks/epoch/README.md).

Reads the epoch file (make_epochs.py writes it when it is missing) and times, for the crystal,
molecule and cluster epochs, full lists of i, j, S, d at each epoch's cutoff:
  - tricell, one compute_neighbors() call per structure, and one compute_neighbors_batch() call
    (C++: build/benchmarks/epoch_bench, pinned to one core, interleaved rounds);
  - numpy batch: tricell.NeighborList.compute_batch(points, boxes, pbc, "ijSd",
    batch_ptr=ptr) on the concatenated arrays (global i and j);
  - torch batch: tricell.torch.NeighborList's batch call on the same tensors (float64);
  - ASE's neighbor_list("ijSd", atoms, cutoff) per structure, the Debian peer (fewer rounds);
  - the C++ batch call with two threads, and two one-thread processes at once (one per core):
    two threads' throughput as a share of theirs.
Every list is checked before anything is timed: each structure's pairs from the numpy and torch
batches equal, array for array, tricell.NeighborList.compute() on that structure (torch's d
within 1e-14 relative, as it computes D from the caller's positions; the C++ driver checks its
batch against its own calls); ASE's pairs (i, j, S) equal tricell's as sets,
pairs within 1e-9 A of the cutoff either way. Times are medians of interleaved rounds after a
warm-up.

  run_epochs.py [--build DIR] [--data FILE] [--repeat K] [--ase-repeat K] [--core N]
                [--scale F] [--readme]

--readme rewrites the epoch section of benchmarks/README.md with the table.
"""
import argparse
import datetime
import os
import platform
import re
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import epoch_file  # noqa: E402

README_HEADING = "## The machine-learning epochs"


def cpp_driver(build, data, args, cores, ways, threads, repeat):
    """{(epoch, way, threads): seconds}, {epoch: (structures, atoms, pairs)}, {epoch: error}."""
    command = ["taskset", "-c", cores, os.path.join(build, "benchmarks", "epoch_bench"), data,
               "--ways", ways, "--threads", threads, "--repeat", str(repeat)]
    out = subprocess.run(command, check=False, capture_output=True, text=True)
    if out.returncode not in (0, 1):
        raise SystemExit("epoch_bench failed: %s" % out.stderr.strip())
    times, sizes, errors = {}, {}, {}
    for line in out.stdout.splitlines():
        words = line.split()
        if words[0] == "time":
            times[words[1], words[2], int(words[3])] = float(words[4])
        elif words[0] == "epoch":
            sizes[words[1]] = tuple(int(words[k]) for k in (3, 5, 7))
        elif words[0] == "error":
            for way in ways.split(","):
                errors[words[1], way] = " ".join(words[2:])
    return times, sizes, errors


def two_processes(build, data, repeat, first, second):
    """Median seconds of the one-thread batch in each of two processes run at once, one on
    each core: {epoch: (seconds in the first, seconds in the second)}."""
    command = lambda core: ["taskset", "-c", str(core),  # noqa: E731
                            os.path.join(build, "benchmarks", "epoch_bench"), data, "--ways",
                            "batch", "--threads", "1", "--repeat", str(repeat)]
    runs = [subprocess.Popen(command(core), stdout=subprocess.PIPE, text=True)
            for core in (first, second)]
    results = {}
    for run in runs:
        for line in run.communicate()[0].splitlines():
            words = line.split()
            if words[0] == "time":
                results.setdefault(words[1], []).append(float(words[4]))
    return results


def check_front(name, epoch, offsets, columns, nl, global_indices, d_rtol=0.0):
    """Each structure's slice of a batch equals its own compute() call, array for array (d
    within d_rtol relative: torch computes D from the caller's positions, not the wrapped ones
    the native call rounds from, docs/contract.md)."""
    for s, (x, h, pbc) in enumerate(epoch.structures()):
        a, b = offsets[s], offsets[s + 1]
        mine = [np.asarray(c[a:b]) for c in columns]
        if global_indices:
            mine[0] = mine[0] - epoch.ptr[s]
            mine[1] = mine[1] - epoch.ptr[s]
        alone = nl.compute(x, h, pbc, "ijSd")
        for letter, m, t in zip("ijSd", mine, alone):
            m = m.astype(t.dtype)
            same = np.allclose(m, t, rtol=d_rtol, atol=0) if letter == "d" and d_rtol > 0 \
                else np.array_equal(m, t)
            if m.shape != t.shape or not same:
                raise SystemExit("%s, %s epoch, structure %d: %s differs from compute()'s"
                                 % (name, epoch.name, s, letter))


def check_ase(epoch, lists, nl):
    """ASE's pairs (i, j, S) equal tricell's as sets, but for pairs within 1e-9 A of the
    cutoff (either way)."""
    for s, ((x, h, pbc), (i, j, S, d)) in enumerate(zip(epoch.structures(), lists)):
        ti, tj, tS, td = nl.compute(x, h, pbc, "ijSd")
        key = lambda i, j, S, d: {(a, b) + tuple(c) for a, b, c, e in  # noqa: E731
                                  zip(i.tolist(), j.tolist(), S.tolist(), d.tolist())
                                  if abs(e - epoch.cutoff) > 1e-9}
        if key(i, j, S, d) != key(ti, tj, tS, td):
            raise SystemExit("ASE, %s epoch, structure %d: other pairs than tricell's"
                             % (epoch.name, s))


def median(values):
    return float(np.median(values)) if values else float("nan")


def python_ways(epochs, repeat, ase_repeat, threads):
    """{(epoch, way, threads): seconds} and {epoch: error} of the numpy and torch batches and
    ASE, after checking each."""
    import tricell
    from ase import Atoms
    from ase.neighborlist import neighbor_list
    try:
        import torch
        import tricell.torch as tt
    except ImportError as error:
        print("torch batch skipped: %s" % error)
        torch = None
    times, errors = {}, {}
    for epoch in epochs:
        nl = tricell.NeighborList(epoch.cutoff)
        batch = tricell.NeighborList(epoch.cutoff, threads=threads)
        ways = {}
        try:
            offsets, *columns = batch.compute_batch(epoch.positions, epoch.cells, epoch.pbc,
                                                    "ijSd", batch_ptr=epoch.ptr)
            check_front("numpy batch", epoch, offsets, columns, nl, True)
            ways["numpy batch"] = lambda: batch.compute_batch(
                epoch.positions, epoch.cells, epoch.pbc, "ijSd", batch_ptr=epoch.ptr)
        except (ValueError, TypeError) as error:
            errors[epoch.name, "numpy batch"] = str(error)
        if torch is not None and hasattr(tt.NeighborList, "compute_batch"):
            tnl = tt.NeighborList(epoch.cutoff, threads=threads)
            x, h = torch.from_numpy(epoch.positions), torch.from_numpy(epoch.cells)
            pbc, ptr = torch.from_numpy(epoch.pbc), torch.from_numpy(epoch.ptr)
            try:
                offsets, *columns = tnl.compute_batch(x, h, pbc, ptr, "ijSd")
                check_front("torch batch", epoch, offsets.numpy(),
                            [c.detach().numpy() for c in columns], nl, True, d_rtol=1e-14)
                ways["torch batch"] = lambda: tnl.compute_batch(x, h, pbc, ptr, "ijSd")
            except RuntimeError as error:
                errors[epoch.name, "torch batch"] = str(error).split("\n")[0]
        if threads == 1:
            atoms = [Atoms(positions=x, cell=h, pbc=p) for x, h, p in epoch.structures()]
            lists = [neighbor_list("ijSd", a, epoch.cutoff) for a in atoms]
            try:
                check_ase(epoch, lists, nl)
            except ValueError as error:  # tricell refuses the epoch: nothing to check against
                print("ASE, %s epoch: unchecked, tricell refuses it (%s)" % (epoch.name, error))
            ways["ASE"] = lambda: [neighbor_list("ijSd", a, epoch.cutoff) for a in atoms]
        seconds = {way: [] for way in ways}
        for round in range(repeat + 1):
            for way, run in ways.items():
                if way == "ASE" and round >= ase_repeat:
                    continue
                start = time.perf_counter()
                run()
                if round > 0 or way == "ASE":  # ASE takes a minute a round: no warm-up
                    seconds[way].append(time.perf_counter() - start)
        for way, values in seconds.items():
            times[epoch.name, way, threads] = median(values)
    return times, errors


def fmt(seconds):
    return "%.3g ms" % (1e3 * seconds) if seconds == seconds else "—"


def table(epochs, sizes, times, errors, shares):
    rows = ["| epoch | structures (atoms; pairs) | tricell, one call per structure | C++ batch "
            "(over the loop) | numpy batch (over C++ batch) | torch batch (over C++ batch) | "
            "ASE, one call per structure (over tricell's loop) | C++ batch, 2 threads "
            "(speed-up; share of 2 processes) |",
            "|---|---|---|---|---|---|---|---|"]

    def cell(name, way, threads=1, over=None, digits=2):
        t = times.get((name, way, threads))
        if t is None:
            message = errors.get((name, way))
            return "refused: %s" % message[:60].replace("|", "\\|") if message else "—"
        if over is None or over != over:
            return fmt(t)
        return "%s (%.*f×)" % (fmt(t), digits, t / over)

    for e in epochs:
        name = e.name
        loop = times.get((name, "loop", 1), float("nan"))
        batch = times.get((name, "batch", 1), float("nan"))
        pairs = sizes.get(name, (len(e.cells), len(e.positions), 0))
        cells = [name, "%d (%d; %d)" % pairs, cell(name, "loop"),
                 cell(name, "batch", over=loop), cell(name, "numpy batch", over=batch),
                 cell(name, "torch batch", over=batch), cell(name, "ASE", over=loop, digits=0)]
        t2 = times.get((name, "batch", 2))
        cells.append("%s (%.2f×; %.0f %%)" % (fmt(t2), batch / t2, 100 * shares[name])
                     if t2 and name in shares else "—")
        rows.append("| " + " | ".join(cells) + " |")
    return rows


def write_readme(lines):
    path = os.path.join(ROOT, "benchmarks", "README.md")
    with open(path) as f:
        text = f.read()
    start = text.find(README_HEADING)
    if start < 0:
        text = text.rstrip("\n") + "\n\n"
    else:
        end = text.find("\n## ", start + len(README_HEADING))
        text = text[:start] + (text[end + 1:] if end >= 0 else "")
        text = text.rstrip("\n") + "\n\n"
    with open(path, "w") as f:
        f.write(text + "\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--data", help="the epoch file (default: BUILD/benchmarks/epochs.bin)")
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--ase-repeat", type=int, default=1)
    parser.add_argument("--core", type=int, default=min(os.sched_getaffinity(0)))
    parser.add_argument("--scale", type=float, default=1.0,
                        help="fewer structures (written to a file of its own)")
    parser.add_argument("--readme", action="store_true")
    args = parser.parse_args()
    build = os.path.abspath(args.build)
    sys.path.insert(0, os.path.join(build, "python"))
    data = args.data or os.path.join(build, "benchmarks", "epochs%s.bin" % (
        "" if args.scale == 1 else "-%g" % args.scale))
    if not os.path.exists(data):
        subprocess.run([sys.executable, os.path.join(HERE, "make_epochs.py"), data,
                        "--scale", str(args.scale)], check=True)
    epochs = epoch_file.read(data)
    other = min(c for c in os.sched_getaffinity(0) if c != args.core) \
        if len(os.sched_getaffinity(0)) > 1 else None
    load = os.getloadavg()[0]

    times, sizes, errors = cpp_driver(build, data, args, str(args.core), "loop,batch", "1",
                                      args.repeat)
    shares = {}
    if other is not None:
        two, _, _ = cpp_driver(build, data, args, "%d,%d" % (args.core, other), "batch", "2",
                               args.repeat)
        times.update(two)
        for name, (a, b) in two_processes(build, data, args.repeat, args.core, other).items():
            # Two processes do two epochs in max(a, b); two threads one epoch in t2.
            shares[name] = max(a, b) / (2 * times[name, "batch", 2])
    os.sched_setaffinity(0, {args.core})
    py_times, py_errors = python_ways(epochs, args.repeat, args.ase_repeat, 1)
    times.update(py_times)
    errors.update(py_errors)

    import tricell
    from ase import __version__ as ase_version
    lines = [README_HEADING, "",
             "Generated by `benchmarks/epoch/run_epochs.py%s` on %s (tricell %s, ASE %s, %s, "
             "%d cores, load average %.1f at the start)." % (
                 " --readme" if args.readme else "", datetime.date.today().isoformat(),
                 tricell.__version__, ase_version, platform.processor() or platform.machine(),
                 os.cpu_count(), load), "",
             "The epochs of benchmarks/epoch/make_epochs.py (crystals with Matbench's size "
             "profile, g2 and s22 molecules, clusters of QMugs's size; cutoff %g A): full lists of "
             "i, j, S, d, one core pinned unless said, medians of %d interleaved rounds (ASE: %d). "
             "Every list is checked equal to tricell's single call first (torch's d within "
             "1e-14 relative)." % (
                 epochs[0].cutoff, args.repeat, args.ase_repeat), ""]
    lines += table(epochs, sizes, times, errors, shares)
    print("\n".join(lines))
    if args.readme:
        write_readme(lines)


if __name__ == "__main__":
    main()
