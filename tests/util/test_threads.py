"""The thread pool (plbar._threads): results do not depend on the thread count, and forked children work."""

import multiprocessing as mp

import numpy as np
import pytest

import plbar
from plbar.util import threads as _threads


def _solve_points(threads, monkeypatch):
    monkeypatch.setenv("PLBAR_THREADS", str(threads))
    res = plbar.solve(plbar.Case(signatures="paper", grid=(60, 60)))
    return np.concatenate([np.c_[b.T1, b.T2, b.phi, b.xi, b.max_abs_multiplier] for b in res.paper])


def test_same_bits_with_one_or_two_threads(monkeypatch):
    a = _solve_points(1, monkeypatch)
    b = _solve_points(2, monkeypatch)
    assert a.shape == b.shape and np.array_equal(a, b)


def test_map_chunks_order_and_bounds(monkeypatch):
    monkeypatch.setenv("PLBAR_THREADS", "3")
    out = _threads.map_chunks(lambda a, b: list(range(a, b)), 1000, 100, 150)
    assert sum(out, []) == list(range(1000))
    assert max(len(c) for c in out) <= 150
    assert _threads.map_chunks(lambda a, b: (a, b), 10, 100) == [(0, 10)]


def _child(q):
    q.put(sum(_threads.map_chunks(lambda a, b: b - a, 10000, 100)))


@pytest.mark.skipif("fork" not in mp.get_all_start_methods(), reason="needs fork")
def test_forked_child_after_the_pool_was_used(monkeypatch):
    """A child forked after the parent's pool started has none of its threads: it must start its own."""
    monkeypatch.setenv("PLBAR_THREADS", "2")
    assert sum(_threads.map_chunks(lambda a, b: b - a, 10000, 100)) == 10000     # the parent's pool is up
    ctx = mp.get_context("fork")
    q = ctx.Queue()
    p = ctx.Process(target=_child, args=(q,))
    p.start()
    p.join(60)
    alive = p.is_alive()
    if alive:
        p.kill()
    assert not alive, "the forked child hung on the parent's thread pool"
    assert q.get(timeout=5) == 10000


@pytest.mark.parametrize("val, n", [("1", 1), ("3", 3), ("0", 1), ("x", 1)])
def test_thread_count_from_environment(monkeypatch, val, n):
    monkeypatch.setenv("PLBAR_THREADS", val)
    assert _threads.n_threads() == n


def test_single_thread_blas_sets_one_thread_and_restores_after_the_last_exit():
    """plbar.util.blas through threadpoolctl: one BLAS thread inside, nested and threaded uses counted."""
    import threading

    from threadpoolctl import threadpool_info

    from plbar.util import single_thread_blas

    def counts():
        return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

    before, inside = counts(), []

    def worker():
        with single_thread_blas:
            inside.append(counts())

    with single_thread_blas:
        assert all(n == 1 for n in counts())
        with single_thread_blas:
            t = threading.Thread(target=worker)
            t.start()
            t.join()
        assert all(n == 1 for n in counts())        # the worker's exit and the nested one are not the last
    assert inside and all(n == 1 for n in inside[0]) and counts() == before


def test_single_thread_blas_from_a_worker_that_enters_first():
    """A pool worker may be the first to enter (map_chunks after a scan): it still sets one thread.

    threadpoolctl lets only the first thread that set OpenBLAS's shared pool set it again; a worker's
    set was silently ignored, and BLAS kept two threads inside two workers.
    """
    from concurrent.futures import ThreadPoolExecutor

    from threadpoolctl import threadpool_info, threadpool_limits

    from plbar.util import single_thread_blas

    def counts():
        return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

    def worker():
        with single_thread_blas:
            return counts()

    with threadpool_limits(limits=2, user_api="blas"):
        if not counts() or max(counts()) < 2:
            raise AssertionError(f"BLAS pools should accept 2 threads here: {counts()}")
        with single_thread_blas:            # the main thread sets (and, before the fix, kept control)
            pass
        with ThreadPoolExecutor(1) as ex:
            inside = ex.submit(worker).result()
        after = counts()
    assert all(n == 1 for n in inside), inside
    assert all(n == 2 for n in after), after


def test_serial_blas_only_where_blas_could_thread():
    """A small call skips the switch (about 10 us, 4 % of a find_response); a large one takes it."""
    import contextlib

    from plbar.util import single_thread_blas
    from plbar.util.blas import SERIAL_WORK, serial_blas_for

    assert isinstance(serial_blas_for(SERIAL_WORK), contextlib.nullcontext)
    assert serial_blas_for(SERIAL_WORK + 1) is single_thread_blas
    # work = B m^2 (B points, m modes): at most SERIAL_WORK means m <= SERIAL_WORK^(1/2), so a GEMM has at most
    # B m^3 <= SERIAL_WORK^(3/2) multiply-adds and a GEMV B m <= SERIAL_WORK; OpenBLAS's own rule keeps one
    # thread below 65536 x 4 (GEMM) and 2304 x 4 (GEMV)
    assert SERIAL_WORK ** 1.5 <= 65536 * 4 and SERIAL_WORK <= 2304 * 4
