"""The load studies of the real motion: the survey at every load position or amplitude, a (T, s) or (T, A)
table and map (issues 28 and 41).

The periodic responses are the same for every load (paper Sec. 4.2, Lemma 1: ``plbar sweep-loads`` sweeps the
position from one solve), but the motion from rest is not: where the bar settles, and on what, depends on
where the load acts.  Nothing about a nonsmooth trajectory is linear in the load's position, so every cell
``(T, s)`` is its own simulation from rest; the compiled simulator makes that a matter of seconds (the
default case: 161 forcing periods x 20 positions, 1,000 periods each).

A unit point force at ``s`` in ``(0, L]`` (:class:`plbar.Case` ``load_points``; on the chain a position
between two DOFs shares the force between them linearly, the paper's Sec. 4.2).  Default positions: every
node and evenly spaced points between (:func:`load_positions`, about 20 in all).  With several sizes ``N``
(an FE bar under refinement) the same physical positions on every mesh.

``survey_loads.csv``: the columns of ``survey.csv`` (:data:`plbar.studies.survey.COLUMNS`) with ``N`` and
``s`` first; ``summary.json``: counts, the energy budget, and per ``N`` the worst position per forcing period
and the mean ``xi_eq`` per position; the map (``survey_loads.png``/``.pdf``): ``xi_eq`` and ``xi_w`` of the
real motion over ``(T, s)``, periodic cells dotted, the worst position per forcing period drawn over it.

The amplitude study (:data:`AMPLITUDES`, ``plbar survey --amplitudes A ...``) is the same study along another axis:
the case's load times ``A`` (every force; a structure file's ``q``), ``survey_amplitudes.csv`` with ``N`` and
``A`` first.  Without a gap or a constant load the motion is proportional to the load (FORMULATION §9,
homogeneity) and ``xi_eq`` does not depend on ``A``; with either it does, through ``A / |gap|``: the curve
engineers work with (a damping ratio as a function of the amplitude).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ...app import Case
from ...errors import InputError
from ...motion import COMPILE_NOTE, KINDS, compiled, prepare
from ...util.files import write_csv, write_json
from ...util.outputs import claim_folder, fingerprint
from ...util.progress import message
from ...util.reprs import build, rng
from ..execution import SerialExecutor, Study, run_options, run_study
from ..loads import check_positions
from .points import COLUMNS
from .study import (INT_COLUMNS, TEXT_COLUMNS, case_title, check_forcing_periods, columns_of, default_periods,
                    default_record)
from .tasks import balanced_parts, case_fields, survey_task, task_cost, task_units

__all__ = ["SurveyLoads", "Axis", "POSITIONS", "AMPLITUDES", "LOADS_COLUMNS", "SURVEY_LOADS_OWNED",
           "load_positions", "survey_loads", "run_survey_loads", "survey_loads_study", "survey_loads_task"]

LOAD_PER_TASK = 12   #: forcing periods of a load study's task (:func:`survey_loads_study`)
#: the columns of survey_loads.csv
LOADS_COLUMNS = ("N", "s") + COLUMNS
#: default number of positions (at least this many: every node and evenly spaced points between)
DEFAULT_POSITIONS = 20


def load_positions(case: Case, per_element: int | None = None) -> np.ndarray:
    """Unit-force positions over the bar: ``per_element`` per element, ``left + k h / per_element`` for
    ``k = 1 .. per_element`` (every node but the clamps and a crack, and points between; the chain's elements are
    its springs).  Default: the fewest per element that give at least :data:`DEFAULT_POSITIONS`."""
    bar = case.bar()
    x = np.asarray(bar.nodes, float)
    x = np.unique(x[np.isfinite(x)])
    if per_element is None:
        per_element = max(1, -(-DEFAULT_POSITIONS // (x.size - 1)))
    if isinstance(per_element, bool) or int(per_element) != per_element or per_element < 1:
        raise InputError(f"per_element = {per_element!r} must be a positive integer (positions per element, "
                         "--per-element K)")
    k = np.arange(1, int(per_element) + 1) / int(per_element)
    s = (x[:-1, None] + k[None, :] * np.diff(x)[:, None]).ravel()
    held = ([bar.crack_at] if getattr(bar, "crack_at", None) is not None else []) + \
        ([bar.length] if getattr(bar, "supports", "clamped-free") == "clamped-clamped" else [])
    return s[~np.isin(s, held)]             # not on a crack (both faces) nor on a far clamp


def _check_positions(case: Case, positions) -> np.ndarray:
    check_positions(case, positions)                     # the one rule of sweep-loads: 0 < s <= L
    return np.minimum(np.unique(np.asarray(positions, float).ravel()), case.bar().length)


def _at(case: Case, s: float) -> Case:
    """The case with a unit force at ``s`` instead of its load."""
    return replace(case, load_nodes=(), load_points=((float(s), 1.0),))


def _scaled(case: Case, A: float) -> Case:
    """The case with its load times ``A`` (every force and a base acceleration; a structure file's ``q``)."""
    if case.matrices is not None:
        return replace(case, load_scale=case.load_scale * float(A))
    return replace(case, load_nodes=tuple((k, a * float(A)) for k, a in case.load_nodes),
                   load_points=tuple((p, a * float(A)) for p, a in case.load_points), base=case.base * float(A))


def _positions(case: Case, positions) -> np.ndarray:
    if case.base:
        raise InputError(f"base = {case.base:g}: a load study over positions puts a unit force at each one in "
                         "place of the case's load, and a shaking support is not a force at a position; drop the "
                         "base or survey it alone (or over --amplitudes)")
    return _check_positions(case, positions)


def _check_amplitudes(case: Case, amplitudes) -> np.ndarray:
    try:
        A = np.unique(np.asarray(amplitudes, float).ravel())
    except (TypeError, ValueError):
        raise InputError(f"amplitudes = {amplitudes!r} must be positive numbers") from None
    if not A.size or not np.all(np.isfinite(A)) or np.any(A <= 0):
        raise InputError(f"amplitudes = {amplitudes!r} must be positive numbers (factors on the case's load)")
    return A


@dataclass(frozen=True)
class Axis:
    """What a load study varies beside the forcing period: the column, its name in words, the case at a value,
    the check of the values, the files' stem."""

    column: str
    word: str
    at: Callable
    check: Callable
    stem: str
    label: str

    @property
    def columns(self) -> tuple:
        return ("N", self.column) + COLUMNS

    @property
    def owned(self) -> tuple:
        return (f"{self.stem}.csv", "summary.json", f"{self.stem}.png", f"{self.stem}.pdf", "study.json", "tasks",
                ".*.part.*")


#: the load study over positions (a unit force at ``s``) and over amplitudes (the case's load times ``A``)
POSITIONS = Axis("s", "position", _at, _positions, "survey_loads", "load position s")
AMPLITUDES = Axis("A", "amplitude", _scaled, _check_amplitudes, "survey_amplitudes", "load amplitude factor A")
_AXES = {a.column: a for a in (POSITIONS, AMPLITUDES)}
#: what a load study owns in its folder
SURVEY_LOADS_OWNED = POSITIONS.owned


@dataclass(frozen=True)
class SurveyLoads:
    """The real motion over forcing periods, load positions (and sizes ``N``).

    Attributes
    ----------
    case : Case
        The study's case (its load is replaced by a unit force at each position, or scaled by each amplitude).
    table : dict of ndarray
        The columns of ``survey_loads.csv`` (:data:`LOADS_COLUMNS`; ``A`` for ``s`` along :data:`AMPLITUDES`),
        sorted by ``N``, the axis, ``T``.
    summary : dict
    files : dict
    column : str
        The axis: ``"s"`` (positions) or ``"A"`` (amplitudes).
    """

    case: Case
    table: dict = field(repr=False)
    summary: dict = field(repr=False)
    files: dict = field(default_factory=dict, repr=False)
    column: str = "s"

    def __len__(self) -> int:
        return int(self.table["T"].size)

    @property
    def sizes(self) -> np.ndarray:
        return np.unique(self.table["N"])

    @property
    def values(self) -> np.ndarray:
        """The axis' values (positions or amplitudes)."""
        return np.unique(self.table[self.column])

    @property
    def positions(self) -> np.ndarray:
        return self.values

    @property
    def T(self) -> np.ndarray:
        return np.unique(self.table["T"])

    def grid(self, column: str, N: int | None = None) -> np.ndarray:
        """``column`` over (position or amplitude, forcing period) of size ``N`` (default: the first), (S, K)."""
        return _grid(self.table, column, self.sizes[0] if N is None else N, self.column)

    def worst(self, column: str = "xi_eq", N: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Per forcing period, the position with the largest ``column`` and that value: ``(s, value)`` (K,)."""
        g = self.grid(column, N)
        i = np.nanargmax(np.where(np.isfinite(g), g, -np.inf), axis=0)
        return self.values[i], g[i, np.arange(g.shape[1])]

    def __repr__(self) -> str:
        t = self.table
        return build("SurveyLoads", {"cells": len(self), "N": self.sizes.tolist(), _AXES[self.column].word + "s":
                                     self.values.size,
                                     "T": rng(t["T"]), "kinds": self.summary.get("kinds", {}),
                                     "xi_eq": rng(t["xi_eq"]), "files": len(self.files)})


def _grid(table: dict, column: str, N: int, axis: str = "s") -> np.ndarray:
    sel = table["N"] == N
    s, T = np.unique(table[axis][sel]), np.unique(table["T"][sel])
    g = np.full((s.size, T.size), "", dtype=object) if column in TEXT_COLUMNS else np.full((s.size, T.size), np.nan)
    g[np.searchsorted(s, table[axis][sel]), np.searchsorted(T, table["T"][sel])] = table[column][sel]
    return g


def survey_loads_task(task: dict) -> dict:
    """One position or amplitude (and size) over its forcing periods: the survey's rows with ``N`` and the axis'
    value (``s`` or ``A``)."""
    res = survey_task(task)
    col = "A" if "A" in task else "s"
    for r in res["rows"]:
        r.update({"N": int(task["N"]), col: float(task[col])})
    return res


def survey_loads_study(case: Case, T, positions, sizes=None, periods: int = 1000, record: int | None = None,
                       axis: Axis = POSITIONS) -> Study:
    """The tasks of a load study: per (size, position), its forcing periods from rest in runs of about
    :data:`LOAD_PER_TASK` (contiguous in ``T``, balanced by their total ``T``: :func:`.tasks.balanced_parts`), so
    that a study of a few positions keeps many workers busy (one task per position left all but ``positions``
    workers idle; measured on 2 workers, 5 positions x 41 periods: 0.82 of the ideal)."""
    T = check_forcing_periods(T)
    if int(periods) != periods or periods < 2:
        raise InputError(f"periods = {periods!r} must be an integer >= 2 (forcing periods simulated)")
    record = default_record(periods) if record is None else record
    if int(record) != record or not 1 <= record < periods:
        raise InputError(f"record = {record!r} must be an integer in [1, periods - 1]")
    s = axis.check(case, positions)
    sizes = [None] if not sizes else sorted({int(n) for n in sizes})
    tasks, N = [], []
    runs = balanced_parts(T, -(-len(T) // LOAD_PER_TASK))
    for n in sizes:
        cn = replace(case, n=n) if n is not None else case
        for si in s:
            c = axis.at(cn, si)
            tasks += [{"case": case_fields(c), "periods": int(periods), "record": int(record), "mode": "rest",
                       "T": [float(T[i]) for i in run], axis.column: float(si), "N": int(c.n_eff)} for run in runs]
        N.append(int(c.n_eff))
    params = {"periods": int(periods), "record": int(record), "T": [float(t) for t in T],
              axis.word + "s": [float(v) for v in s], "sizes": N}
    return Study(axis.stem.replace("_", "-"), survey_loads_task, tuple(tasks), params, task_units, "period", task_cost)


def _table(results: list[dict], axis: Axis = POSITIONS) -> dict:
    rows = [r for res in results for r in res["rows"]]
    rows.sort(key=lambda r: (r["N"], r[axis.column], r["T"]))
    return columns_of(rows, axis.columns)


def _summary(case: Case, table: dict, study: Study, seconds: float, axis: Axis = POSITIONS) -> dict:
    from ...util.version import __version__

    by_n, w, col = {}, axis.word, axis.column
    for n in np.unique(table["N"]):
        sel = table["N"] == n
        s, T = np.unique(table[col][sel]), np.unique(table["T"][sel])
        xi = _grid(table, "xi_eq", n, col)
        xw = _grid(table, "xi_w", n, col)
        kind = _grid(table, "kind", n, col)
        i = np.nanargmax(np.where(np.isfinite(xi), xi, -np.inf), axis=0)
        mean = np.nanmean(xi, axis=1)
        per = np.mean(kind == "periodic", axis=1)
        by_n[str(int(n))] = {
            "kinds": {k: int(np.sum(table["kind"][sel] == k)) for k in KINDS},
            f"worst_{w}_per_T": [float(v) for v in s[i]],
            "worst_xi_eq_per_T": [float(v) for v in xi[i, np.arange(T.size)]],
            f"mean_xi_eq_per_{w}": [float(v) for v in mean],
            f"mean_xi_w_per_{w}": [float(v) for v in np.nanmean(xw, axis=1)],
            f"periodic_fraction_per_{w}": [float(v) for v in per],
            f"{w}_of_largest_mean_xi_eq": float(s[int(np.nanargmax(mean))]),
            f"{w}s": [float(v) for v in s]}
    return {"plbar_version": __version__, "case": case_fields(case), **study.params, "cells": int(table["T"].size),
            "kinds": {k: int(np.sum(table["kind"] == k)) for k in KINDS},
            "energy_residual_max": float(np.nanmax(np.abs(table["energy_residual"]))),
            "by_N": by_n, "seconds": round(seconds, 3)}


def _write(folder: Path, table: dict, summary: dict, axis: Axis = POSITIONS) -> dict:
    cols = list(axis.columns)
    fmts = ["%s" if c in TEXT_COLUMNS else ("%d" if c in INT_COLUMNS else "%.17g") for c in cols]
    return {"table": write_csv(folder / f"{axis.stem}.csv", cols, [table[c] for c in cols], fmts),
            "summary": write_json(folder / "summary.json", summary)}


def _defaults(case: Case, T, positions, per_element, axis: Axis = POSITIONS):
    T = default_periods(case) if T is None else T
    if positions is None:
        if axis is not POSITIONS:
            raise InputError("an amplitude study needs its amplitudes (--amplitudes A1 A2 ...)")
        positions = load_positions(case, per_element)
    return T, positions


def survey_loads(case: Case | None = None, T=None, positions=None, per_element: int | None = None, sizes=None,
                 periods: int = 1000, record: int | None = None, executor=None,
                 axis: Axis = POSITIONS) -> SurveyLoads:
    """The real motion from rest at every forcing period ``T`` and load position, in memory (no files).

    Parameters
    ----------
    case : Case, optional
        Default: the paper's chain.  Its load is replaced by a unit force at each position.
    T : array_like, optional
        Forcing periods (default :func:`plbar.studies.survey.default_periods`).
    positions : array_like, optional
        Unit-force positions in ``(0, L]`` (default :func:`load_positions` with ``per_element``).
    sizes : sequence of int, optional
        Sizes ``N`` (the same physical positions on each mesh); default the case's.
    periods, record : int
        As :func:`plbar.studies.survey.survey`.
    executor : concurrent.futures.Executor, optional
        Default serial.
    axis : Axis
        :data:`POSITIONS` (default: ``positions`` are unit-force positions) or :data:`AMPLITUDES` (``positions``
        are factors on the case's load).
    """
    case = case or Case()
    t0 = time.perf_counter()
    T, positions = _defaults(case, T, positions, per_element, axis)
    study = survey_loads_study(case, T, positions, sizes, periods, record, axis)
    ex = executor or SerialExecutor()
    results = [f.result() for f in [ex.submit(survey_loads_task, t) for t in study.tasks]]
    table = _table(results, axis)
    return SurveyLoads(case, table, _summary(case, table, study, time.perf_counter() - t0, axis), column=axis.column)


def run_survey_loads(case: Case, T=None, positions=None, per_element: int | None = None, sizes=None,
                     periods: int = 1000, record: int | None = None, out="plbar-survey-loads",
                     axis: Axis = POSITIONS, **options) -> SurveyLoads:
    """Run (or resume) a load study into ``out``: ``survey_loads.csv``, ``summary.json`` and the map (PNG + PDF).

    A task per (size, position) is written as it finishes (``tasks/``), so a killed study resumes; the same
    study resumes in its folder, another is refused unless ``overwrite`` (:func:`plbar.util.outputs.claim_folder`).
    ``case, T, positions, per_element, sizes, periods, record, axis`` as :func:`survey_loads` (along
    :data:`AMPLITUDES` the files are ``survey_amplitudes.csv`` and ``.png``/``.pdf``); the keyword options
    ``executor, progress, overwrite, plot`` are the study's run options (:class:`plbar.studies.RunOptions`).
    """
    opts = run_options(options, "run_survey_loads")
    executor, progress = opts.executor, opts.progress
    t0 = time.perf_counter()
    folder = Path(out)
    T, positions = _defaults(case, T, positions, per_element, axis)
    study = survey_loads_study(case, T, positions, sizes, periods, record, axis)
    claim = claim_folder(folder, study.name, fingerprint(list(study.tasks)), axis.owned, opts.overwrite)
    try:
        if progress and not compiled(case.problem()):
            message(f"plbar: {COMPILE_NOTE}")
        if executor is not None and not isinstance(executor, SerialExecutor):
            prepare(case.problem())
        results = run_study(folder, study, executor, progress=progress, overwrite=True)
    except BaseException as exc:
        claim.abandon(("tasks/*.json",), exc)
        raise
    table = _table(results, axis)
    summary = _summary(case, table, study, time.perf_counter() - t0, axis)
    files = _write(folder, table, summary, axis)
    if opts.plot:
        from ...visuals import survey_loads_plot
        from ...visuals.style import unit_note

        files["figure"] = survey_loads_plot(table, folder, axis.stem, title=case_title(case),
                                            units=unit_note(case.bar()) if case.structure is None else "",
                                            column=axis.column, label=axis.label)
    return SurveyLoads(case, table, summary, files, axis.column)
