"""Chunked maps over a small thread pool (numpy and LAPACK release the GIL on large batches).

``PLBAR_THREADS`` sets the number of threads (default: the CPUs this process
may use, at most 4; ``1`` runs everything in the calling thread).  Nested
calls from a worker run serially, so a chunked function may call another.
Results are concatenated in chunk order: they do not depend on the thread
count.
"""

from __future__ import annotations

import os
import queue
import signal
import threading
from concurrent.futures import Future, ThreadPoolExecutor, wait

__all__ = ["n_threads", "map_chunks", "off_main", "signals_to_main"]

_local = threading.local()
_pool: ThreadPoolExecutor | None = None
_pool_lock = threading.Lock()
_helper: queue.SimpleQueue | None = None      #: the jobs of the one thread :func:`off_main` runs them on


def n_threads() -> int:
    """Threads used by :func:`map_chunks` (``PLBAR_THREADS``, else the usable CPUs, at most 4)."""
    env = os.environ.get("PLBAR_THREADS", "").strip()
    if env:
        try:
            return max(1, int(env))
        except ValueError:
            return 1
    try:
        cpus = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cpus = os.cpu_count() or 1
    return max(1, min(cpus, 4))


def signals_to_main() -> None:
    """Block SIGINT in the calling thread (a helper thread, at its start), so that the kernel delivers a Ctrl-C to
    the main thread: where the main thread holds it (a study forking its workers), it waits there, instead of
    being taken by a helper and raised in the main thread in the middle of a fork (a worker then left behind)."""
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})


def _get_pool(n: int) -> ThreadPoolExecutor:
    global _pool
    with _pool_lock:
        if _pool is None or _pool._max_workers != n:
            _pool = ThreadPoolExecutor(max_workers=n, thread_name_prefix="plbar", initializer=signals_to_main)
        return _pool


def _after_fork_in_child():
    """A forked child (process pools of the studies) has none of the parent's threads: start afresh."""
    global _pool, _pool_lock, _helper
    _pool = _helper = None
    _pool_lock = threading.Lock()
    _local.__dict__.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


def _run(fn, args):
    _local.worker = True
    try:
        return fn(*args)
    finally:
        _local.worker = False


def map_chunks(fn, size: int, min_chunk: int, max_chunk: int | None = None, done=None) -> list:
    """``[fn(a, b) for (a, b) in chunks of range(size)]``, in parallel where it pays.

    Parameters
    ----------
    fn : callable
        ``fn(start, stop)`` for a chunk ``[start, stop)``.
    size : int
    min_chunk : int
        No chunk is smaller (below ``2 min_chunk`` items everything runs in one call).
    max_chunk : int, optional
        No chunk is larger (memory bound).
    done : callable, optional
        Called in the calling thread with ``stop - start`` as each chunk's result comes in, in order (a
        progress bar).  The chunks are the same with or without it, so are the results, bit for bit (a
        batch's size can change the last bits of a BLAS product).
    """
    n = n_threads() if not getattr(_local, "worker", False) else 1
    # the chunks do not depend on the thread count (bitwise the same results with 1 or 4 threads)
    k = max(1, min(4, size // max(min_chunk, 1)))
    if max_chunk:
        k = max(k, -(-size // max_chunk))
    bounds = [(size * i // k, size * (i + 1) // k) for i in range(k)]
    results = (fn(a, b) for a, b in bounds) if n == 1 or k == 1 else \
        _get_pool(n).map(lambda ab: _run(fn, ab), bounds)
    out = []
    for (a, b), r in zip(bounds, results):
        out.append(r)
        if done is not None:
            done(b - a)
    return out


def _serve(jobs: queue.SimpleQueue) -> None:
    """The helper thread of :func:`off_main`: run each ``(fn, future)`` and settle its future."""
    signals_to_main()
    while True:
        fn, fut = jobs.get()
        try:
            fut.set_result(fn())
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting caller
            fut.set_exception(exc)


def off_main(fn, stop, grace: float = 1.0):
    """``fn()``, run on a helper thread when called from the main thread, so that a Ctrl-C arrives at once.

    Python runs its SIGINT handler in the main thread between bytecodes: while the main thread is in a compiled
    kernel, a Ctrl-C waits for the kernel to return.  Here the main thread only waits (a wait that the signal
    interrupts); on any exception there ``stop()`` is called (it sets the kernels' halt flag), the helper is
    given ``grace`` s to return (a kernel returns within microseconds of the flag; a first compile does not, and a
    Ctrl-C must end the command within 2 s), and the exception goes on.  The helper is a daemon thread: the
    interpreter's exit does not wait for it (a kernel's first compile, which no flag stops).  From any other thread
    ``fn()`` runs in place.
    """
    global _helper
    if threading.current_thread() is not threading.main_thread():
        return fn()
    with _pool_lock:
        if _helper is None:
            _helper = queue.SimpleQueue()
            threading.Thread(target=_serve, args=(_helper,), name="plbar-kernel", daemon=True).start()
        fut: Future = Future()
        _helper.put((fn, fut))
    try:
        return fut.result()
    except BaseException:
        stop()
        wait([fut], timeout=grace)
        raise
