"""Executors for studies: one ``concurrent.futures`` interface for every backend.

:func:`get_executor` returns an object with ``submit``, ``map`` and
``shutdown`` (and usable as a context manager) whose ``submit`` returns
:class:`concurrent.futures.Future` objects, so that a study runner can use
:func:`concurrent.futures.as_completed` whatever runs the tasks:

``"serial"``
    Runs each task in the calling process at ``submit`` (debugging, tests).
``"local"``
    A :class:`~concurrent.futures.ProcessPoolExecutor` over all cores (or
    ``workers``), forked where the platform allows, so that a script that
    runs a study at module level needs no ``if __name__ == "__main__"`` guard.
``"dask"``
    The futures of a ``dask.distributed.Client``: connected to ``address``
    (``tcp://host:8786``, or a scheduler file ``*.json``) or, without an
    address, to a new ``LocalCluster`` with ``workers`` single-threaded
    worker processes.  dask is imported only here, lazily.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import multiprocessing as mp
import os

from ...errors import InputError

__all__ = ["get_executor", "SerialExecutor", "KINDS"]

KINDS = ("local", "serial", "dask")

class SerialExecutor(cf.Executor):
    """Run each task immediately in the calling process; return a finished future."""

    def submit(self, fn, /, *args, **kwargs):
        fut = cf.Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # noqa: BLE001 - handed to the caller through the future
            if isinstance(exc, (KeyboardInterrupt, SystemExit)):
                raise
            fut.set_exception(exc)
        return fut


def _one_thread():
    """Worker initializer: the processes share the cores, so no thread pool inside each (plbar._threads)."""
    os.environ["PLBAR_THREADS"] = "1"


def _local(workers: int) -> cf.ProcessPoolExecutor:
    """A process pool; ``fork`` where available so scripts need no ``__main__`` guard."""
    ctx = mp.get_context("fork") if "fork" in mp.get_all_start_methods() else None
    return cf.ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_one_thread)


class _DaskExecutor(cf.Executor):
    """``concurrent.futures`` view of a dask client (closes what it started)."""

    def __init__(self, client, cluster=None):
        self.client = client
        self.cluster = cluster
        self._ex = client.get_executor(pure=False)

    def submit(self, fn, /, *args, **kwargs):
        return self._ex.submit(fn, *args, **kwargs)

    def map(self, fn, *iterables, timeout=None, chunksize=1):
        return self._ex.map(fn, *iterables, timeout=timeout)

    def shutdown(self, wait=True, *, cancel_futures=False):
        with contextlib.suppress(Exception):
            self._ex.shutdown(wait=wait)
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def _positive_workers(workers):
    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError(f"workers = {workers!r} must be a positive integer")
    return workers


def get_executor(kind: str = "local", address: str | None = None, workers: int | None = None) -> cf.Executor:
    """An executor for study tasks.

    Parameters
    ----------
    kind : {"local", "serial", "dask"}
        Backend (see the module docstring).  An ``address`` implies ``"dask"``.
    address : str, optional
        dask scheduler address (``tcp://...``) or scheduler file (``*.json``).
    workers : int, optional
        Worker processes (local: default all cores; dask without address:
        default chosen by ``LocalCluster`` from the cores; ignored with an address).

    Returns
    -------
    concurrent.futures.Executor
        ``submit`` returns :class:`concurrent.futures.Future`; call
        ``shutdown()`` (or use ``with``) when done.
    """
    if address and kind == "local":
        kind = "dask"
    if kind not in KINDS:
        raise InputError(f"executor kind = {kind!r} must be one of {', '.join(KINDS)}")
    workers = _positive_workers(workers)
    if kind == "serial":
        return SerialExecutor()
    if kind == "local":
        return _local(workers or os.cpu_count() or 1)
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise InputError("the dask executor needs dask[distributed]: pip install 'plbar[dask]'") from exc
    if address:
        if str(address).endswith(".json"):
            return _DaskExecutor(Client(scheduler_file=str(address)))
        return _DaskExecutor(Client(address))
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    return _DaskExecutor(Client(cluster), cluster)
