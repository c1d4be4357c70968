"""BLAS on one thread while many small matrices are processed (a reference-counted context manager).

The solver works on batches of small matrices; BLAS threading gains nothing
there and, on a loaded machine, makes every small product wait for the
scheduler (10x-100x slower).  The BLAS libraries loaded in the process
(numpy's and scipy's OpenBLAS, MKL, BLIS, ...) are found and set by
`threadpoolctl <https://github.com/joblib/threadpoolctl>`_.
"""

from __future__ import annotations

import contextlib
import threading

__all__ = ["single_thread_blas", "serial_blas_for", "SERIAL_WORK"]

#: ``B m^2`` (points x modes^2) at or below which every BLAS call of the period map runs on one thread anyway:
#: its GEMMs have at most ``SERIAL_WORK^1.5`` multiply-adds and its GEMVs ``SERIAL_WORK``, below OpenBLAS's
#: own thresholds (65536 x 4 and 2304 x 4); :func:`serial_blas_for` skips the switch there
SERIAL_WORK = 4096


class _SingleThreadBLAS:
    """Context manager: every BLAS library of the process on one thread while the core runs.

    Nested and concurrent (threaded) uses are reference counted: the first entry
    saves and sets, the last exit restores (``threadpoolctl.threadpool_limits``
    alone would restore too early when two threads overlap).  The libraries are
    looked up once, at the first entry, and driven through threadpoolctl's
    controllers (about 11 us an entry, see :func:`serial_blas_for`).

    Any thread may be the first to enter (the pool workers of
    :func:`plbar.util.threads.map_chunks` do): threadpoolctl lets only one
    "controlling" thread set a shared OpenBLAS pool and silently ignores the
    others, so every set here first releases that claim (our own lock already
    serialises the sets) and releases it again after.  Without this, BLAS kept
    two threads inside two workers after a scan (FE N = 20 solve 11 % slower).
    """

    def __init__(self):
        self._lock = threading.Lock()
        self._depth = 0
        self._libs = None
        self._saved: list[int] = []

    @staticmethod
    def _find() -> list:
        from threadpoolctl import ThreadpoolController

        return list(ThreadpoolController().select(user_api="blas").lib_controllers)

    def __enter__(self):
        with self._lock:
            if self._depth == 0:
                if self._libs is None:
                    self._libs = self._find()
                self._saved = [lib.num_threads for lib in self._libs]
                _set(self._libs, [1] * len(self._libs))
            self._depth += 1
        return self

    def __exit__(self, *exc):
        with self._lock:
            self._depth -= 1
            if self._depth == 0:
                _set(self._libs, self._saved)
        return False


def _set(libs, counts) -> None:
    """Set each library's thread count from whichever thread calls (see :class:`_SingleThreadBLAS`)."""
    for lib, n in zip(libs, counts):
        release = getattr(type(lib), "clear_controlling_thread", None)   # OpenBLAS without OpenMP
        if release is not None:
            release(force=True)
        lib.set_num_threads(n)
        if release is not None:
            release(force=True)


single_thread_blas = _SingleThreadBLAS()


def serial_blas_for(work: float):
    """:data:`single_thread_blas` where the BLAS calls of a batch ``work = B m^2`` could use threads, else a no-op.

    A single small response (``plbar.find_response`` on the chain) never reaches BLAS threading; switching
    the pools there costs about 10 us a call, 4 % of the call.  The result is the same bit for bit: below the
    threshold the library runs on one thread whatever its setting.
    """
    return single_thread_blas if work > SERIAL_WORK else contextlib.nullcontext()
