"""Many Python threads searching at once (the GIL is released during every search).

The reference lists come first, from serial calls (threads=1) on the main thread. Then 12
threads each run every case several times: through a tricell.NeighborList of their own (reused
across cases, 1 to 4 internal threads, copies and copy=False views), through one NeighborList
shared by no one else per case, and through tricell.ase.primitive_neighbor_list, whose search is
kept per thread (python/tricell/ase.py). Every result must equal the reference bit for bit.
"""
import os
import threading

import numpy as np

import tricell
import tricell.ase

LIGHT = "asan" in os.environ.get("LD_PRELOAD", "")
CALLERS = 6 if LIGHT else 12
ROUNDS = 1 if LIGHT else 3


def _cases(count=8, max_atoms=1600, seed=20261203):
    rng = np.random.default_rng(seed)
    cases = []
    for c in range(count):
        n = int(rng.integers(60, max_atoms))
        side = (n / 0.1) ** (1 / 3)
        box = np.eye(3) * side
        box[1, 0], box[2, 0], box[2, 1] = 0.3 * side * (rng.random(3) - 0.5)
        points = rng.random((n, 3)) @ box
        periodic = (True, c % 3 != 1, c % 4 != 2)
        cutoff = 2.5 + 1.5 * rng.random()
        options = dict(full=c % 2 == 0, sorted=c % 3 == 0, grouped=c % 3 == 1)
        cases.append((points, box, periodic, cutoff, options))
    return cases


QUANTITIES = "ijSdD"


def _reference(cases):
    out = []
    for points, box, periodic, cutoff, options in cases:
        nl = tricell.NeighborList(cutoff, threads=1, **options)
        out.append(nl.compute(points, box, periodic=periodic, quantities=QUANTITIES))
    return out


def _same(a, b):
    return len(a) == len(b) and all(x.dtype == y.dtype and x.shape == y.shape and
                                    x.tobytes() == y.tobytes() for x, y in zip(a, b))


def _run_threads(target):
    errors = []
    barrier = threading.Barrier(CALLERS)

    def wrapped(t):
        try:
            barrier.wait()
            target(t)
        except BaseException as e:  # noqa: BLE001 - reported by the main thread
            errors.append(f"thread {t}: {e!r}")

    threads = [threading.Thread(target=wrapped, args=(t,)) for t in range(CALLERS)]
    for th in threads:
        th.start()
    for th in threads:
        th.join(timeout=120)
        assert not th.is_alive(), "a thread did not finish (deadlock?)"
    assert not errors, errors[:5]


def test_native_lists_in_many_threads_match_serial():
    cases = _cases()
    reference = _reference(cases)

    def work(t):
        own = {}
        for r in range(ROUNDS):
            for k in range(len(cases)):
                c = (k + t) % len(cases)
                points, box, periodic, cutoff, options = cases[c]
                threads = 1 + (t + r + c) % 4
                key = (c, threads)
                if key not in own:
                    own[key] = tricell.NeighborList(cutoff, threads=threads, **options)
                got = own[key].compute(points, box, periodic=periodic, quantities=QUANTITIES,
                                       copy=(r % 2 == 0))
                assert _same(reference[c], got), f"case {c}, threads {threads}"

    _run_threads(work)


def test_batches_in_many_threads_match_serial():
    cases = [c for c in _cases(6, 500, 3) if c[4]["full"]]
    points = [c[0] for c in cases]
    boxes = [c[1] for c in cases]
    serial = tricell.NeighborList(3.0, threads=1).compute_batch(points, boxes, periodic=True,
                                                                quantities="ijSd")

    def work(t):
        nl = tricell.NeighborList(3.0, threads=1 + t % 4)
        for _ in range(ROUNDS):
            got = nl.compute_batch(points, boxes, periodic=True, quantities="ijSd")
            assert _same(serial, got)

    _run_threads(work)


def test_ase_drop_in_thread_local_search_matches_serial():
    cases = _cases(6, 1200, 17)
    reference = []
    for points, box, periodic, cutoff, _ in cases:
        reference.append(tricell.ase.primitive_neighbor_list("ijSdD", periodic, box, points,
                                                             cutoff))

    def work(t):
        for _ in range(ROUNDS):
            for k in range(len(cases)):
                c = (k + t) % len(cases)
                points, box, periodic, cutoff, _ = cases[c]
                got = tricell.ase.primitive_neighbor_list("ijSdD", periodic, box, points, cutoff)
                assert _same(reference[c], got), f"case {c}"

    _run_threads(work)


def test_one_neighbor_list_shared_by_many_threads_matches_serial():
    # Calls on one object from several threads take turns (a mutex in python/src/neighbors.cpp);
    # each caller's copies are its own.
    cases = _cases(4, 1200, 29)
    reference = _reference(cases)
    shared = {c: tricell.NeighborList(cases[c][3], threads=2, **cases[c][4])
              for c in range(len(cases))}

    def work(t):
        for _ in range(ROUNDS):
            for k in range(len(cases)):
                c = (k + t) % len(cases)
                points, box, periodic, _, _ = cases[c]
                got = shared[c].compute(points, box, periodic=periodic, quantities=QUANTITIES)
                assert _same(reference[c], got), f"case {c}"

    _run_threads(work)
