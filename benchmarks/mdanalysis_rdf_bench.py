#!/usr/bin/env python3
"""MDAnalysis's InterRDF with its own search and with tricell's (tricell.mdanalysis.install()),
in one run on one pinned core: the same analysis on the same trajectory, the two interleaved,
median wall time of each over the rounds; then whether the g(r) agree. Also the searches alone
on the first frame: MDAnalysis's capped_distance (its automatic method) and tricell's.

    /usr/bin/python3 benchmarks/mdanalysis_rdf_bench.py TOPOLOGY TRAJECTORY \\
        [--select "name OW"] [--rmax 15] [--bins 75] [--rounds 3] [--build-python build/python]

For example on MDAnalysis's test data (adk_oplsaa.tpr and adk_oplsaa.xtc of its test suite:
AdK in water, 47681 atoms, 10 frames).
"""
import argparse
import os
import statistics
import sys
import time
import warnings


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("topology")
    parser.add_argument("trajectory")
    parser.add_argument("--select", default="name OW", help="both groups of InterRDF")
    parser.add_argument("--rmax", type=float, default=15.0)
    parser.add_argument("--bins", type=int, default=75)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--build-python", default=os.path.join(here, "..", "build", "python"))
    args = parser.parse_args()
    sys.path.insert(0, args.build_python)
    warnings.simplefilter("ignore", DeprecationWarning)

    import MDAnalysis
    import numpy as np
    from MDAnalysis.analysis.rdf import InterRDF
    from MDAnalysis.lib import distances

    import tricell.mdanalysis

    os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    u = MDAnalysis.Universe(args.topology, args.trajectory)
    group = u.select_atoms(args.select)
    print(f"{args.trajectory}: {len(u.atoms)} atoms, {len(u.trajectory)} frames; "
          f"InterRDF of '{args.select}' ({len(group)} atoms) with itself, range (0, {args.rmax}), "
          f"{args.bins} bins; box {u.dimensions.tolist()}; MDAnalysis {MDAnalysis.__version__}, "
          f"tricell {tricell.__version__}; one core ({sorted(os.sched_getaffinity(0))})")

    def rdf():
        start = time.perf_counter()
        result = InterRDF(group, group, nbins=args.bins, range=(0.0, args.rmax)).run().results
        return time.perf_counter() - start, result

    def searches(function):
        start = time.perf_counter()
        pairs, _ = function(group.positions, group.positions, args.rmax, box=u.dimensions)
        return time.perf_counter() - start, len(pairs)

    times = {"MDAnalysis": [], "tricell": []}
    search_times = {"MDAnalysis": [], "tricell": []}
    u.trajectory[0]
    for _ in range(args.rounds):
        seconds, theirs = rdf()
        times["MDAnalysis"].append(seconds)
        seconds, their_pairs = searches(distances.capped_distance)
        search_times["MDAnalysis"].append(seconds)
        tricell.mdanalysis.install()
        try:
            seconds, mine = rdf()
            times["tricell"].append(seconds)
        finally:
            tricell.mdanalysis.uninstall()
        seconds, my_pairs = searches(tricell.mdanalysis.capped_distance)
        search_times["tricell"].append(seconds)
    median = {name: statistics.median(values) for name, values in times.items()}
    for name in times:
        print(f"InterRDF {name:10s} {median[name]:8.3f} s  (rounds: "
              f"{', '.join(f'{t:.3f}' for t in times[name])})")
    print(f"ratio MDAnalysis / tricell: {median['MDAnalysis'] / median['tricell']:.2f}")
    for name, pairs in (("MDAnalysis", their_pairs), ("tricell", my_pairs)):
        print(f"capped_distance alone, frame 0, {name:10s} "
              f"{statistics.median(search_times[name]):8.3f} s  ({pairs} pairs)")
    moved = int(np.abs(mine.count - theirs.count).sum())
    print(f"g(r): counts equal in {int((mine.count == theirs.count).sum())} of {args.bins} bins, "
          f"{moved / 2:g} of {int(theirs.count.sum())} pair counts in another bin; largest rdf "
          f"difference {np.abs(mine.rdf - theirs.rdf).max():.3g}")


if __name__ == "__main__":
    main()
