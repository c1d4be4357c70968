"""The survey's tasks: a chunk of forcing periods from rest, or a sweep that carries the state from period to period.

A *rest* task simulates its forcing periods together from rest.  A *sweep*
task (``up`` or ``down``) simulates its forcing periods one after the other,
each from the final state of the previous one (the first from rest), so that
hysteresis and coexisting motions show; every forcing period is checkpointed
(``DIR/sweeps/<key>/T00012.json``, written atomically with the final state),
so a killed sweep resumes where it stopped.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

from ...app import Case
from ...errors import InputError
from ...motion import padded
from ...util.files import write_json
from ...util.version import code_hash
from ..execution import report
from .points import survey_chunk, start_json, start_of

__all__ = ["survey_task", "task_units", "task_cost", "make_tasks", "balanced_parts", "sweep_key", "MODES",
           "default_chunks", "case_fields", "case_of"]

#: Case fields that apply to one model only
_CHAIN_ONLY = ("m", "k")
_FE_ONLY = ("element", "mass", "length", "EA", "rhoA", "grading", "mesh_file", "point_masses")


def case_fields(case: Case) -> dict:
    """The fields of ``case`` that define its bar, load and modes, as JSON (a task round-trips through it).

    A :class:`plbar.Structure` in memory has no such fields (its matrices are its own): refused by name, with the way
    to give it (a structure file, ``--model matrices``), rather than failing in every task."""
    if case.model == "structure":
        raise InputError("a study's tasks carry the case as data, and a plbar.Structure given in memory cannot "
                         "travel: write it to a structure file (plbar.io.write_structure(path, structure)) and "
                         "give plbar.Case(model='matrices', matrices=path) (--model matrices --matrices FILE)")
    d = json.loads(json.dumps(case.to_dict(), default=list))
    for k in _FE_ONLY if d["model"] == "chain" else _CHAIN_ONLY:
        d.pop(k, None)
    if d.get("mesh_file"):
        d["mesh_file"] = str(Path(d["mesh_file"]).resolve())
        d.pop("n", None)
        d.pop("length", None)
        d.pop("grading", None)
    for k in ("grid", "T1", "T2", "method", "signatures"):
        d.pop(k, None)
    return d

MODES = ("rest", "up", "down")


PER_TASK = 4   #: forcing periods of a from-rest survey task (:func:`default_chunks`)


def default_chunks(k: int) -> int:
    """Tasks a from-rest survey of ``k`` forcing periods is split into: about :data:`PER_TASK` each, at least 2.

    Fixed by ``k`` alone, so that a rerun with another executor or number of workers finds the same tasks (and
    resumes them).  Small tasks are what an interrupted survey keeps: with about 96 forcing periods a task, the
    default survey was two tasks, and a Ctrl-C at 90 % kept nothing.  A task's fixed cost is milliseconds
    (measured: the default survey took the same time in 2, 21 and 41 tasks; an FE bar N = 64 spends about 20 ms
    a task building its model), and a trajectory does not depend on its batch but for the last bits of the drift
    statistics (1e-16 relative).  Four forcing periods a task, submitted costliest first (:func:`task_cost`),
    keep two workers busy to the end: from measured trajectory costs, 0.95 of the ideal on 2 workers for 50
    forcing periods of that FE bar (eight a task, in order: 0.89), 0.99 for the default survey.
    """
    return max(2, -(-k // PER_TASK)) if k > 1 else 1


def balanced_parts(T, n: int) -> list[np.ndarray]:
    """``n`` contiguous runs of the indices of ``T`` with about equal total ``T`` (a trajectory's work grows with
    its duration, periods x T: equal counts of forcing periods leave the core with the long ones last)."""
    T = np.asarray(T, float)
    k = T.size
    n = max(1, min(int(n), k))
    w = np.cumsum(np.abs(T))
    cuts, prev = [], 0
    for i in range(1, n):
        c = int(np.searchsorted(w, w[-1] * i / n, side="right"))
        prev = min(max(c, prev + 1), k - (n - i))              # every run keeps at least one forcing period
        cuts.append(prev)
    return np.split(np.arange(k), cuts)


def make_tasks(case: Case, T, periods: int, record: int, modes=("rest",), chunks: int | None = None,
               checkpoints=None) -> list[dict]:
    """The task list of a survey (JSON-able dicts)."""
    T = [float(t) for t in np.asarray(T, float)]
    base = {"case": case_fields(case), "periods": int(periods),
            "record": int(record)}
    tasks = []
    for mode in modes:
        if mode == "rest":
            n = chunks or default_chunks(len(T))
            for part in balanced_parts(T, n):
                if part.size:
                    tasks.append({**base, "mode": "rest", "T": [T[i] for i in part]})
        else:
            order = sorted(T, reverse=(mode == "down"))
            t = {**base, "mode": mode, "T": order}
            if checkpoints is not None:
                t["checkpoints"] = str(Path(checkpoints).resolve())
            tasks.append(t)
    return tasks


def case_of(fields: dict) -> Case:
    """The :class:`Case` of :func:`case_fields`."""
    c = dict(fields)
    for k in ("load_nodes", "load_points", "point_masses"):
        if k in c and c[k] is not None:
            c[k] = tuple(tuple(p) for p in c[k])
    return Case(**c)


def sweep_key(task: dict) -> str:
    """The folder name of a sweep's checkpoints (a hash of what defines it and of plbar's code)."""
    core = {k: task[k] for k in ("case", "periods", "record", "mode", "T")}
    core["code"] = code_hash()
    return hashlib.sha256(json.dumps(core, sort_keys=True).encode()).hexdigest()[:16]


def _sweep(task: dict, case: Case) -> list[dict]:
    """The rows of a sweep, each forcing period from the previous final state (checkpointed per period)."""
    folder = Path(task["checkpoints"]) / sweep_key(task) if task.get("checkpoints") else None
    pad = padded(case.problem())
    rows, start = [], None
    for i, T in enumerate(task["T"]):
        path = folder / f"T{i:05d}.json" if folder else None
        got = None
        if path is not None and path.is_file():
            try:
                got = json.loads(path.read_text())
            except (OSError, ValueError):
                got = None
        if got is None or got.get("T") != T:
            r, fin = survey_chunk(case, [T], task["periods"], task["record"], start, pad, report)
            got = {"T": T, "row": r[0], "final": start_json(fin, 0)}
            if path is not None:
                write_json(path, got)
        else:
            report(task["periods"])
        rows.append(got["row"])
        start = start_of([got["final"]])
    return rows


def task_cost(task: dict) -> float:
    """A survey task's predicted cost: the time it simulates, ``periods x sum(T)`` (the events of a trajectory
    grow with its duration; measured on an FE bar N = 64, end mass 0.5, the cost of a trajectory correlates 0.83
    with its ``T``): :attr:`plbar.studies.execution.Study.cost`, the costliest submitted first."""
    return float(task["periods"]) * float(np.sum(task["T"]))


def task_units(task: dict) -> int:
    """A survey task's work: trajectories x forcing periods simulated (what :func:`survey_task` reports as it
    goes, :func:`plbar.studies.execution.reports.report`)."""
    return len(task["T"]) * int(task["periods"])


def survey_task(task: dict) -> dict:
    """Run one survey task: ``{"mode", "rows"}`` (one row per forcing period, in the task's order); its progress
    is reported in :func:`task_units`."""
    case = case_of(task["case"])
    if task["mode"] == "rest":
        B = 1 if case.model == "continuum" else len(task["T"])     # the continuum reports one trajectory at a time
        rows, _ = survey_chunk(case, task["T"], task["periods"], task["record"], progress=lambda n: report(n * B))
    else:
        rows = _sweep(task, case)
    return {"mode": task["mode"], "rows": rows}
