"""The real motion against the coefficient of restitution: the survey at every ``e`` (issue 31).

The paper assumes a perfectly plastic impact (Eq. (10)): the contact stops dead and loses ``S v_c^2 / 2``
(Eq. (14)), so its ``xi_eq`` (Eq. (22)) "can be considered an upper limit" -- a real impact is partly elastic.
With Newton's law (:class:`plbar.Case` ``restitution``: the contact leaves the wall at ``e`` times the speed
it hit it with) an impact loses ``(1 - e^2) S v_c^2 / 2``, but the motion changes too: more impacts, other
amplitudes, other periodic motions or none.  Nothing here is a scaling of the plastic result: every cell
``(e, T)`` is its own simulation from rest, with the survey's tasks (:func:`.study.survey_study`), one
simulator (:mod:`plbar.motion`).

The table has the survey's columns (:data:`plbar.studies.survey.COLUMNS`) with ``e`` first, one row per
``(e, T)``; the summary holds, per ``e``, the median and 10-90 % quantiles over ``T`` of ``xi_eq``, ``xi_w``
and the loss per forcing period, the ratio of the median ``xi_eq`` to the plastic one (``e = 0``), how many
forcing periods damp more than the plastic impact at the same ``T`` (the bound holds for the range, not period
by period), and the kinds.  For ``e > 0`` a periodic motion's exact orbit has ``R`` (a rebound) in its
signature; the settling test stays the plastic impact's (a motion is periodic where its states repeat).
"""

from __future__ import annotations

import concurrent.futures as cf
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ...app import Case
from ...errors import InputError
from ...motion import KINDS
from ...util.files import write_csv, write_json
from ...util.progress import progress_bar
from ...util.reprs import build, rng
from ..execution import SerialExecutor, Study
from .points import COLUMNS
from .study import INT_COLUMNS, TEXT_COLUMNS, columns_of, default_periods, survey_study
from .tasks import case_fields, survey_task, task_cost, task_units

__all__ = ["SurveyRestitution", "RESTITUTION_COLUMNS", "RESTITUTIONS", "QUANTILES", "check_restitutions",
           "survey_restitution", "survey_restitution_study", "survey_restitution_task", "write_restitution"]

#: the columns of the table (``restitution.csv``)
RESTITUTION_COLUMNS = ("e",) + COLUMNS
#: default coefficients of restitution: 0, 0.1, ..., 1
RESTITUTIONS = tuple(round(0.1 * i, 1) for i in range(11))
#: the quantiles over the forcing periods in the summary (the band of the figure and the median)
QUANTILES = (0.1, 0.5, 0.9)


def check_restitutions(restitutions) -> np.ndarray:
    """Coefficients of restitution as a sorted array of distinct numbers in ``[0, 1]``, at least one."""
    bad = (f"restitutions = {restitutions!r} must be coefficients of restitution e in [0, 1] (0: plastic, the "
           "paper; 1: elastic), at least one")
    if isinstance(restitutions, (str, bytes)):
        raise InputError(bad)
    try:
        e = np.atleast_1d(np.asarray(restitutions, dtype=float)).ravel()
    except (TypeError, ValueError):
        raise InputError(bad) from None
    if not e.size or not np.all(np.isfinite(e) & (e >= 0.0) & (e <= 1.0)) or \
            any(isinstance(v, bool) for v in np.atleast_1d(np.asarray(restitutions, dtype=object)).ravel()):
        raise InputError(bad)
    return np.unique(e)


@dataclass(frozen=True)
class SurveyRestitution:
    """The real motion from rest over coefficients of restitution ``e`` and forcing periods ``T``.

    Attributes
    ----------
    case : Case
        The study's case (its ``restitution`` is replaced by each ``e``).
    table : dict of ndarray
        The columns :data:`RESTITUTION_COLUMNS`, one row per ``(e, T)``, sorted by ``e``, ``T``.
    summary : dict
        Settings, counts, the energy budget, and ``by_e``: per ``e`` the kinds, the median and quantiles
        (:data:`QUANTILES`), mean and largest over ``T`` of ``xi_eq``, ``xi_w``, ``loss_per_T`` and
        ``impacts_per_T``, ``ratio_to_plastic`` (median ``xi_eq`` over the one at ``e = 0``) and
        ``above_plastic`` (how many forcing periods damp more than the plastic impact at the same ``T``); both
        None without ``e = 0``.
    files : dict
        Written files (:func:`write_restitution`).
    """

    case: Case
    table: dict = field(repr=False)
    summary: dict = field(repr=False)
    files: dict = field(default_factory=dict, repr=False)

    def __len__(self) -> int:
        return int(self.table["T"].size)

    @property
    def restitutions(self) -> np.ndarray:
        return np.unique(self.table["e"])

    @property
    def T(self) -> np.ndarray:
        return np.unique(self.table["T"])

    def grid(self, column: str) -> np.ndarray:
        """``column`` over (restitution, forcing period), shape ``(E, K)``."""
        e, T = self.restitutions, self.T
        g = np.full((e.size, T.size), "", dtype=object) if column in TEXT_COLUMNS else np.full((e.size, T.size),
                                                                                                np.nan)
        g[np.searchsorted(e, self.table["e"]), np.searchsorted(T, self.table["T"])] = self.table[column]
        return g

    def quantile(self, column: str = "xi_eq", q: float = 0.5) -> np.ndarray:
        """Per ``e``, the ``q`` quantile of ``column`` over the forcing periods (nan-aware), shape ``(E,)``."""
        return np.nanquantile(self.grid(column), q, axis=1)

    def ratio_to_plastic(self, column: str = "xi_eq") -> np.ndarray:
        """Per ``e``, the median of ``column`` over ``T`` divided by the plastic one (``e = 0``; nan without it)."""
        med = self.quantile(column, 0.5)
        e = self.restitutions
        return med / med[0] if e[0] == 0.0 else np.full(e.size, np.nan)

    def __repr__(self) -> str:
        t = self.table
        return build("SurveyRestitution", {"rows": len(self), "e": [float(v) for v in self.restitutions],
                                           "T": rng(t["T"]), "kinds": self.summary.get("kinds", {}),
                                           "xi_eq": rng(t["xi_eq"]), "loss_per_T": rng(t["loss_per_T"]),
                                           "files": len(self.files)})


def survey_restitution_task(task: dict) -> dict:
    """One survey task (:func:`plbar.studies.survey.survey_task`) at the restitution of its case: its rows with
    ``e``."""
    res = survey_task(task)
    for r in res["rows"]:
        r["e"] = float(task["e"])
    return res


def survey_restitution_study(case: Case, T, restitutions, periods: int = 1000, record: int | None = None) -> Study:
    """The tasks of a restitution study: at every ``e`` the survey's tasks from rest (:func:`.study.survey_study`,
    the same chunks as :func:`plbar.studies.survey.survey`), with ``e`` added."""
    e = check_restitutions(restitutions)
    tasks, params = [], None
    for v in e:
        s = survey_study(replace(case, restitution=float(v)), T, periods, record)
        params = params or s.params
        tasks += [dict(t, e=float(v)) for t in s.tasks]
    params = {"periods": params["periods"], "record": params["record"], "T": params["T"],
              "restitutions": [float(v) for v in e]}
    return Study("survey-restitution", survey_restitution_task, tuple(tasks), params, task_units, "period", task_cost)


def _table(results: list[dict]) -> dict:
    rows = [r for res in results for r in res["rows"]]
    rows.sort(key=lambda r: (r["e"], r["T"]))
    return columns_of(rows, RESTITUTION_COLUMNS)


def _stats(v: np.ndarray) -> dict:
    v = np.asarray(v, float)
    v = v[np.isfinite(v)]
    if not v.size:
        return {"median": None, "q10": None, "q90": None, "mean": None, "max": None}
    q = np.quantile(v, QUANTILES)
    return {"median": float(q[1]), "q10": float(q[0]), "q90": float(q[2]), "mean": float(v.mean()),
            "max": float(v.max())}


def _summary(case: Case, table: dict, study: Study, seconds: float) -> dict:
    from ...util.version import __version__

    e = np.unique(table["e"])
    by_e, plastic = {}, None
    xi = SurveyRestitution(case, table, {}).grid("xi_eq")
    for i, v in enumerate(e):
        sel = table["e"] == v
        d = {"kinds": {k: int(np.sum(table["kind"][sel] == k)) for k in KINDS}, "xi_eq": _stats(table["xi_eq"][sel]),
             "xi_w": _stats(table["xi_w"][sel]), "loss_per_T": _stats(table["loss_per_T"][sel]),
             "impacts_per_T": _stats(table["impacts_per_T"][sel])}
        if v == 0.0:
            plastic = d["xi_eq"]["median"]
        # the forcing periods where this e damps more than the plastic impact at the same T
        d["above_plastic"] = int(np.sum(xi[i] > xi[0])) if e[0] == 0.0 else None
        by_e[f"{v:g}"] = d
    for d in by_e.values():
        med = d["xi_eq"]["median"]
        d["ratio_to_plastic"] = med / plastic if plastic and med is not None else None
    return {"plbar_version": __version__, "case": case_fields(case), **study.params, "rows": int(table["T"].size),
            "kinds": {k: int(np.sum(table["kind"] == k)) for k in KINDS},
            "energy_residual_max": float(np.nanmax(np.abs(table["energy_residual"]))), "by_e": by_e,
            "seconds": round(seconds, 3)}


def _run(study: Study, executor, progress: bool) -> list[dict]:
    """The tasks' results in order; the bar counts finished tasks (a serial executor runs each as submitted)."""
    ex = executor or SerialExecutor()
    with progress_bar(len(study.tasks), progress, "survey over e", unit="task") as bar:
        futures, pending = [], []
        for t in study.tasks:
            futures.append(ex.submit(study.func, t))
            if futures[-1].done():
                bar.update(1)
            else:
                pending.append(futures[-1])
        for f in cf.as_completed(pending):
            f.result()
            bar.update(1)
    return [f.result() for f in futures]


def survey_restitution(case: Case | None = None, T=None, restitutions=RESTITUTIONS, periods: int = 1000,
                       record: int | None = None, executor=None, progress: bool = False) -> SurveyRestitution:
    """The real motion from rest at every coefficient of restitution ``e`` and forcing period ``T``, in memory.

    At each ``e`` the survey of :func:`plbar.studies.survey.survey` with ``case.restitution = e``: Newton's
    impact law at the contact (a rebound keeps ``e`` of the contact's speed and loses ``(1 - e^2) S v_c^2 / 2``,
    Eq. (14) times ``1 - e^2``), ``xi_eq`` of the motion by Eq. (22).  ``e = 0`` is the paper's plastic impact,
    whose ``xi_eq`` the paper calls an upper limit: its rows are the plain survey's, bit for bit.

    Parameters
    ----------
    case : Case, optional
        Default: the paper's chain.  Its ``restitution`` is replaced by each ``e``.
    T : array_like, optional
        Forcing periods (default :func:`plbar.studies.survey.default_periods` of the case: ``[6, 14]`` for the
        paper's chain, whatever its ``e``).
    restitutions : array_like
        Coefficients of restitution in ``[0, 1]``, at least one (default :data:`RESTITUTIONS`).
    periods, record : int
        As :func:`plbar.studies.survey.survey`.
    executor : concurrent.futures.Executor, optional
        Default serial (in this process).
    progress : bool
        Count the finished tasks on stderr (:func:`plbar.util.progress.progress_bar`).

    Returns
    -------
    SurveyRestitution
    """
    case = case or Case()
    t0 = time.perf_counter()
    T = default_periods(case) if T is None else T
    study = survey_restitution_study(case, T, restitutions, periods, record)
    table = _table(_run(study, executor, progress))
    return SurveyRestitution(case, table, _summary(case, table, study, time.perf_counter() - t0))


def write_restitution(folder, result: SurveyRestitution, name: str = "restitution") -> dict:
    """``name.csv`` (the table, :data:`RESTITUTION_COLUMNS`) and ``name.json`` (the summary), atomically."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    cols = list(RESTITUTION_COLUMNS)
    fmts = ["%s" if c in TEXT_COLUMNS else ("%d" if c in INT_COLUMNS else "%.17g") for c in cols]
    return {"table": write_csv(folder / f"{name}.csv", cols, [result.table[c] for c in cols], fmts),
            "summary": write_json(folder / f"{name}.json", result.summary)}
