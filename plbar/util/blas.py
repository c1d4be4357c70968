"""OpenBLAS on one thread while many small matrices are processed (a reference-counted context manager).

The solver works on batches of small matrices; OpenBLAS threading gains
nothing there and, on a loaded machine, makes every small product wait for
the scheduler (10x-100x slower).  numpy's and scipy's OpenBLAS builds are
found in the process maps and set through ``openblas_set_num_threads`` (a
no-op where none is found).
"""

from __future__ import annotations

__all__ = ["single_thread_blas"]


class _SingleThreadBLAS:
    """Context manager: OpenBLAS (numpy's and scipy's) on one thread while the core runs.

    The core works on many small matrices; OpenBLAS threading gains nothing
    there and, on a loaded machine, makes every small product wait for the
    scheduler (10x-100x slower).  Nested and concurrent (threaded) uses are
    reference counted: the first entry saves and sets, the last exit restores.
    A no-op where the libraries are not found.
    """

    def __init__(self):
        import threading

        self._lock = threading.Lock()
        self._depth = 0
        self._libs = None
        self._saved = []

    def _find(self):
        import ctypes

        libs = []
        try:
            with open("/proc/self/maps") as fh:
                paths = sorted({ln.split()[-1] for ln in fh if "openblas" in ln.lower() and ".so" in ln})
        except OSError:
            paths = []
        for p in paths:
            try:
                lib = ctypes.CDLL(p)
            except OSError:
                continue
            for pre in ("scipy_openblas", "openblas"):
                for suf in ("64_", "", "_64"):
                    get = getattr(lib, f"{pre}_get_num_threads{suf}", None)
                    put = getattr(lib, f"{pre}_set_num_threads{suf}", None)
                    if get is not None and put is not None:
                        libs.append((get, put))
                        break
                else:
                    continue
                break
        return libs

    def __enter__(self):
        with self._lock:
            if self._depth == 0:
                if self._libs is None:
                    self._libs = self._find()
                self._saved = [get() for get, _ in self._libs]
                for _, put in self._libs:
                    put(1)
            self._depth += 1
        return self

    def __exit__(self, *exc):
        with self._lock:
            self._depth -= 1
            if self._depth == 0:
                for (_, put), n in zip(self._libs, self._saved):
                    put(n)
        return False


single_thread_blas = _SingleThreadBLAS()
