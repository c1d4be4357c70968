"""Resumable studies: many small tasks, one atomic result file per task.

A study is a folder::

    DIR/study.json          the task list (written first, atomically)
    DIR/tasks/<key>.json    one finished task: {"key", "task", "result"}
    DIR/*.csv, *.json       tables assembled from the task files

A *task* is a small JSON-able dict; its key is a hash of its canonical JSON and of plbar's code (a task is
reused only by the code that computed it; the task files of other code are removed).
:func:`run_study` submits the tasks without a result file to an executor
(:mod:`plbar.executor`), and the *parent* writes each result as it arrives
(temp file + rename, :mod:`plbar.io`), so a killed run leaves only complete
files under final names and a rerun skips them.  Results are always read back
from the task files in task order, so the tables do not depend on which
executor ran the tasks or in which order they finished.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import hashlib
import json
import signal
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from ...errors import OutputExistsError, PlbarError
from ...util.files import write_json
from ...util.progress import progress_bar
from ...util.version import code_hash
from .executor import SerialExecutor
from .reports import POLL, read_report, reporting

__all__ = ["Study", "StudyError", "task_key", "run_study", "load_results", "call_task"]


class StudyError(PlbarError):
    """Some tasks of a study failed (the finished ones are kept)."""


def _canonical(obj) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False)


def task_key(task: dict) -> str:
    """Stable 16-hex-digit key of a task: the hash of its canonical JSON and of plbar's code
    (:func:`plbar.util.version.code_hash`), so that a rerun after plbar changed computes the task again instead of
    reusing what other code computed."""
    return hashlib.sha256((_canonical(task) + code_hash()).encode()).hexdigest()[:16]


@dataclass(frozen=True)
class Study:
    """A named list of tasks and the function that runs one.

    Attributes
    ----------
    name : str
        Kind of study (``"load-sweep"``, ``"refine"``); recorded in ``study.json``.
    func : callable
        A picklable (module-level) task function ``dict -> dict`` whose
        result is JSON-able (floats round-trip exactly through JSON); its
        ``module:name`` is recorded in ``study.json``.
    tasks : tuple of dict
        The tasks, in the order of the final tables.
    params : dict
        How the tasks were made (recorded, not used).
    units : callable, optional
        ``task -> int``: the units of work of a task that its function reports as it works
        (:func:`plbar.studies.execution.reports.report`); the progress then counts units of every task, the
        running ones included.  None: it counts finished tasks.
    unit : str
        The name of one unit.
    cost : callable, optional
        ``task -> float``: a task's predicted cost, in any unit.  The tasks are submitted costliest first (the
        longest-processing-time rule: no worker is left alone with a long task at the end); the tables keep the
        task order.  None: submitted in task order.
    """

    name: str
    func: Callable[[dict], dict]
    tasks: tuple
    params: dict
    units: Callable[[dict], int] | None = None
    unit: str = "task"
    cost: Callable[[dict], float] | None = None

    @property
    def func_name(self) -> str:
        """``module:name`` of the task function (recorded in ``study.json``)."""
        return f"{self.func.__module__}:{self.func.__qualname__}"

    @property
    def keys(self) -> list[str]:
        return [task_key(t) for t in self.tasks]

    def manifest(self) -> dict:
        return {"study": self.name, "func": self.func_name, "params": self.params,
                "tasks": [{"key": k, "task": t} for k, t in zip(self.keys, self.tasks)]}


def call_task(func, task: dict, report_to=None) -> dict:
    """Run ``func`` on ``task`` (in a worker), its progress reports sent to the file ``report_to``
    (:func:`plbar.studies.execution.reports.reporting`)."""
    with reporting(report_to):
        return func(task)


def _report_file(folder: Path, key: str) -> Path:
    return folder / "tasks" / f"{key}.progress"


def _task_file(folder: Path, key: str) -> Path:
    return folder / "tasks" / f"{key}.json"


def _read_task(path: Path, key: str):
    """The stored result of a task, or None if absent or unreadable."""
    try:
        d = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return d["result"] if isinstance(d, dict) and d.get("key") == key and "result" in d else None


def _check_manifest(folder: Path, study: Study, overwrite: bool) -> None:
    path = folder / "study.json"
    new = json.loads(_canonical(study.manifest()))
    if path.exists() and not overwrite:
        try:
            old = json.loads(path.read_text())
        except (OSError, ValueError):
            old = None
        if old is not None and (old.get("study"), old.get("func")) != (new["study"], new["func"]):
            raise OutputExistsError(f"study folder {str(folder)!r} holds a {old.get('study')!r} study; "
                                    "choose another --out or pass --overwrite")
    write_json(path, new)


def run_study(folder, study: Study, executor: cf.Executor | None = None, progress: bool = True,
              overwrite: bool = False) -> list[dict]:
    """Run the unfinished tasks of ``study`` and return all results in task order.

    Parameters
    ----------
    folder : path
        Study folder (created).  Finished task files found there are reused.
    study : Study
    executor : concurrent.futures.Executor, optional
        Default: a serial executor.  Not shut down here.
    progress : bool
        Show the progress on stderr (:func:`plbar.util.progress.progress_bar`).
    overwrite : bool
        Allow a folder that holds another kind of study.

    Returns
    -------
    list of dict
        The task results, read back from the task files, in task order.

    Raises
    ------
    StudyError
        If tasks failed; the finished ones stay on disk, so a rerun resumes.
    """
    folder = Path(folder)
    (folder / "tasks").mkdir(parents=True, exist_ok=True)
    _check_manifest(folder, study, overwrite)
    keys = study.keys
    current = set(keys)
    for old in (folder / "tasks").glob("*.json"):          # tasks of another code or study: never reused
        if old.stem not in current:
            old.unlink(missing_ok=True)
    for old in (folder / "tasks").glob("*.progress"):      # reports of a run that was stopped
        old.unlink(missing_ok=True)
    todo = [(k, t) for k, t in zip(keys, study.tasks) if _read_task(_task_file(folder, k), k) is None]
    todo = list({k: t for k, t in todo}.items())          # duplicate tasks run once
    if study.cost is not None:
        todo.sort(key=lambda kt: -study.cost(kt[1]))         # stable: equal costs keep the task order
    ex = executor or SerialExecutor()
    units = study.units or (lambda _task: 1)
    every = dict(zip(keys, study.tasks))
    total = sum(units(t) for t in every.values())
    with progress_bar(total, progress, study.name, study.unit, initial=total - sum(units(t) for _, t in todo)) as bar:
        failed = _collect(ex, study.func, todo, folder, bar, units)
    if failed:
        lines = "; ".join(f"{k}: {m}" for k, m in failed[:5])
        raise StudyError(f"{len(failed)} of {len(todo)} task(s) failed ({lines}); "
                         "finished tasks are kept, rerun to retry the others")
    return load_results(folder, study)


def _collect(ex, func, todo, folder: Path, bar, units) -> list[tuple[str, str]]:
    """Submit ``todo``, write each result as it arrives, move the progress by the running tasks' reports every
    :data:`.reports.POLL` s; on Ctrl-C cancel the pending tasks and stop the workers."""
    failed: list[tuple[str, str]] = []
    futs: dict = {}
    shown = {k: 0 for k, _ in todo}          # units of each task the progress shows
    try:
        with _no_sigint():                     # Ctrl-C while the pool forks its workers would be lost in a fork
            futs = {ex.submit(call_task, func, t, _report_file(folder, k)): (k, t) for k, t in todo}  # handler:
        pending = set(futs)                                                        # held until they run
        while pending:
            done, pending = cf.wait(pending, timeout=POLL, return_when=cf.FIRST_COMPLETED)
            for fut in done:
                k, t = futs[fut]
                try:
                    res = fut.result()
                except Exception as exc:  # noqa: BLE001 - reported together at the end
                    failed.append((k, f"{type(exc).__name__}: {exc}"))
                else:
                    write_json(_task_file(folder, k), {"key": k, "task": t, "result": res})
                bar.update(units(t) - shown[k])
                shown[k] = units(t)
            for fut in pending:
                k, t = futs[fut]
                now = min(read_report(_report_file(folder, k)), units(t) - 1)
                if now > shown[k]:
                    bar.update(now - shown[k])
                    shown[k] = now
    except KeyboardInterrupt:
        # every finished task is on disk already; cancel the pending ones now, and stop the running ones
        for fut in futs:
            fut.cancel()
        procs = _workers(ex)                   # before the shutdown, which forgets them
        ex.shutdown(wait=False, cancel_futures=True)
        _stop_workers(procs)
        for k, _ in todo:
            _report_file(folder, k).unlink(missing_ok=True)
        raise
    return failed


@contextlib.contextmanager
def _no_sigint():
    """Hold SIGINT (in the main thread) while the block runs; a Ctrl-C pressed meanwhile arrives after it.

    A process pool forks its workers at the first submissions, and a KeyboardInterrupt raised in a fork handler
    is ignored by Python: without this, a Ctrl-C at that instant was lost and the study ran to its end.  The
    workers inherit the held signal: the parent stops them."""
    held = threading.current_thread() is threading.main_thread() and hasattr(signal, "pthread_sigmask")
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT}) if held else None
    try:
        yield
    finally:
        if held:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _workers(ex) -> list:
    """The worker processes of a local process pool (none for another executor, or once it is shut down)."""
    return list((getattr(ex, "_processes", None) or {}).values())


def _stop_workers(procs) -> None:
    """Terminate worker processes (a dask cluster cancels its own futures)."""
    for proc in procs:
        with contextlib.suppress(Exception):
            proc.terminate()


def load_results(folder, study: Study) -> list[dict]:
    """Results of all tasks of ``study`` from ``folder``, in task order.

    Raises
    ------
    StudyError
        If a task has no result file yet.
    """
    folder = Path(folder)
    out = []
    for k in study.keys:
        r = _read_task(_task_file(folder, k), k)
        if r is None:
            raise StudyError(f"task {k} of study {str(folder)!r} has no result yet; run the study first")
        out.append(r)
    return out
