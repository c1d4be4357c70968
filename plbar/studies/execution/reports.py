"""Progress from inside a running task: the worker reports units done, the study's runner reads them.

A study's progress would otherwise move only when a task ends: a survey of two tasks of a minute each showed
nothing for a minute (issue 30).  :func:`call_task` runs a task inside :func:`reporting`, which points this
process's reports at a small file beside the task's result (``tasks/<key>.progress``); the task function
calls :func:`report` as it works (a survey: trajectories x forcing periods, from the simulator's blocks), and
:func:`plbar.studies.run_study` reads the files of the running tasks every :data:`POLL` seconds.  A worker
that cannot write there (a dask worker on another machine) reports nothing: its task then moves the progress
when it ends, as before.
"""

from __future__ import annotations

import contextlib
import os
import time
from pathlib import Path

__all__ = ["POLL", "read_report", "report", "reporting"]

POLL = 1.0          #: seconds between two reads of the running tasks' reports (and between two writes)

_now: dict = {"path": None, "done": 0, "written": 0.0}   #: this process's running task (one at a time)


@contextlib.contextmanager
def reporting(path):
    """Send :func:`report` of the block to ``path`` (None: reports go nowhere); the file is removed after."""
    old = dict(_now)
    _now.update(path=None if path is None else Path(path), done=0, written=0.0)
    try:
        yield
    finally:
        if _now["path"] is not None:
            with contextlib.suppress(OSError):
                _now["path"].unlink()
        _now.update(old)


def report(units: int) -> None:
    """Add ``units`` done to the running task's report (written at most every :data:`POLL` s, atomically)."""
    _now["done"] += int(units)
    path, now = _now["path"], time.monotonic()
    if path is None or now - _now["written"] < POLL:
        return
    _now["written"] = now
    tmp = path.with_name(f".{path.name}.{os.getpid()}")
    with contextlib.suppress(OSError):
        tmp.write_text(str(_now["done"]))
        os.replace(tmp, path)


def read_report(path) -> int:
    """Units a running task has reported (0 where it has not)."""
    try:
        return int(Path(path).read_text())
    except (OSError, ValueError):
        return 0
