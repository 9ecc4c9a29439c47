"""multiprocessing with the fork start method after threaded searches in the parent.

The parent computes every list threaded (threads=3) and serially first; a pool of forked
workers then computes the same lists (threaded and serial, through NeighborList and the ASE
drop-in) and returns them. Every child's result must equal the parent's bit for bit, and the
pool must finish within a timeout: a helper thread or lock that did not survive the fork would
hang it. The library's thread team lives only for the duration of a call
(lib/detail/parallel.hpp), so nothing of it is left to inherit.
"""
import multiprocessing
import os

import numpy as np
import pytest

import tricell
import tricell.ase

pytestmark = pytest.mark.skipif("fork" not in multiprocessing.get_all_start_methods(),
                                reason="no fork start method on this platform")

TIMEOUT = 120


def _case(c):
    rng = np.random.default_rng(100 + c)
    n = 300 + 400 * c
    side = (n / 0.1) ** (1 / 3)
    box = np.eye(3) * side
    box[1, 0], box[2, 0] = 0.2 * side, -0.1 * side
    points = rng.random((n, 3)) @ box
    return points, box, (True, c % 2 == 0, True), 3.0 + 0.2 * c


CASES = 5


def _lists(c, threads):
    points, box, periodic, cutoff = _case(c)
    native = tricell.NeighborList(cutoff, threads=threads, sorted=c % 2 == 0).compute(
        points, box, periodic=periodic, quantities="ijSdD")
    ase = tricell.ase.primitive_neighbor_list("ijSd", periodic, box, points, cutoff)
    return [np.ascontiguousarray(a) for a in (*native, *ase)]


def _child(job):
    c, threads = job
    return os.getpid(), _lists(c, threads)


def _same(a, b):
    return len(a) == len(b) and all(x.dtype == y.dtype and x.shape == y.shape and
                                    x.tobytes() == y.tobytes() for x, y in zip(a, b))


def test_fork_pool_after_threaded_call_matches_parent():
    parent = {c: _lists(c, 3) for c in range(CASES)}  # threaded calls before any fork
    for c in range(CASES):
        assert _same(parent[c], _lists(c, 1))
    context = multiprocessing.get_context("fork")
    jobs = [(c, threads) for c in range(CASES) for threads in (1, 2, 4)]
    with context.Pool(3) as pool:
        results = pool.map_async(_child, jobs).get(timeout=TIMEOUT)
    assert {pid for pid, _ in results} - {os.getpid()}, "the work ran in forked children"
    for (c, threads), (_, got) in zip(jobs, results):
        assert _same(parent[c], got), f"case {c}, threads {threads} differs in the child"


def test_fork_pool_twice_and_parent_still_works():
    context = multiprocessing.get_context("fork")
    expected = {c: _lists(c, 2) for c in range(2)}
    for _ in range(2):
        with context.Pool(2) as pool:
            results = pool.map_async(_child, [(0, 4), (1, 3), (0, 1)]).get(timeout=TIMEOUT)
        assert _same(expected[0], results[0][1])
        assert _same(expected[1], results[1][1])
        assert _same(expected[0], results[2][1])
        assert _same(expected[0], _lists(0, 4))  # the parent after its children
