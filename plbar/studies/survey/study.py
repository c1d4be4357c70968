"""``run_survey``: the survey as a resumable study, its table, summary and figure; ``survey`` in memory."""

from __future__ import annotations

import time
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
from .points import COLUMNS
from .tasks import MODES, case_fields, make_tasks, survey_task, task_cost, task_units

__all__ = ["Survey", "survey", "run_survey", "survey_study", "SURVEY_OWNED", "check_forcing_periods", "default_record"]

#: what a survey owns in its folder (cleared before another survey is written there)
SURVEY_OWNED = ("survey.csv", "summary.json", "survey.png", "survey.pdf", "study.json", "tasks", "sweeps", ".*.part.*",
                "vtk", "render")             # and the exports and renders of its motions

INT_COLUMNS = ("N", "m", "status", "steady")             #: columns of integers in the survey's tables
TEXT_COLUMNS = ("kind", "start", "signature")   #: columns of text


@dataclass(frozen=True)
class Survey:
    """What the bar really does at every forcing period of a survey.

    Attributes
    ----------
    case : Case
    table : dict of ndarray
        The columns of ``survey.csv`` (one row per forcing period and start), sorted by start and ``T``.
    summary : dict
        Counts by kind, ranges, settings and times (``summary.json``).
    files : dict
        Written files (empty for :func:`survey`).
    """

    case: Case
    table: dict = field(repr=False)
    summary: dict = field(repr=False)
    files: dict = field(default_factory=dict, repr=False)

    def __len__(self) -> int:
        return int(self.table["T"].size)

    def rows(self, start: str = "rest") -> dict:
        """The columns of the rows of one start (``rest``, ``up``, ``down``)."""
        sel = self.table["start"] == start
        return {k: v[sel] for k, v in self.table.items()}

    def __repr__(self) -> str:
        t = self.table
        return build("Survey", {"rows": len(self), "T": rng(t["T"]), "kinds": self.summary.get("kinds", {}),
                                "xi_eq": rng(t["xi_eq"]), "loss_per_T": rng(t["loss_per_T"]),
                                "files": len(self.files)})


def check_forcing_periods(T) -> np.ndarray:
    """Forcing periods as a sorted array of distinct finite positive numbers (one-line error otherwise)."""
    try:
        T = np.atleast_1d(np.asarray(T, float)).ravel()
    except (TypeError, ValueError):
        raise InputError(f"T = {T!r} must be forcing periods (numbers > 0)") from None
    if not T.size or not np.all(np.isfinite(T) & (T > 0)):
        raise InputError(f"forcing periods T must be finite and > 0, got {T.tolist()[:5]}")
    return np.unique(T)


def default_record(periods: int) -> int:
    """The periods recorded when not given: the last 100, or the last tenth of ``periods`` when that is fewer
    (at least 1), so that any ``periods >= 2`` works without ``record``."""
    return max(1, min(100, int(periods) // 10))


def survey_study(case: Case, T, periods: int = 1000, record: int | None = None, modes=("rest",), chunks=None,
                 checkpoints=None) -> Study:
    """The tasks of a survey (see :mod:`.tasks`)."""
    T = check_forcing_periods(T)
    bad = [m for m in modes if m not in MODES]
    if bad or not modes:
        raise InputError(f"start = {bad[0] if bad else modes!r} must be one of {', '.join(MODES)}")
    if int(periods) != periods or periods < 2:
        raise InputError(f"periods = {periods!r} must be an integer >= 2 (forcing periods simulated)")
    record = default_record(periods) if record is None else record
    if int(record) != record or not 1 <= record < periods:
        raise InputError(f"record = {record!r} must be an integer in [1, periods - 1] (the last periods, "
                         "after the transient)")
    if case.model == "continuum" and tuple(modes) != ("rest",):
        raise InputError("model = 'continuum' is surveyed from rest only: drop --continue (a sweep carries the "
                         "state of a mesh from period to period)")
    tasks = make_tasks(case, T, int(periods), int(record), tuple(modes), chunks, checkpoints)
    params = {"periods": int(periods), "record": int(record), "modes": list(modes), "T": [float(t) for t in T]}
    return Study("survey", survey_task, tuple(tasks), params, task_units, "period", task_cost)


def columns_of(rows: list[dict], cols) -> dict:
    """The table of ``rows`` (dicts): one array per column, text as objects, counts as integers, the rest floats
    (a missing field is nan)."""
    kind = lambda c: object if c in TEXT_COLUMNS else (int if c in INT_COLUMNS else float)
    return {c: np.array([r.get(c, np.nan) for r in rows], dtype=kind(c)) for c in cols}


def _table(results: list[dict]) -> dict:
    rows = [dict(r, start=res["mode"]) for res in results for r in res["rows"]]
    rows.sort(key=lambda r: (MODES.index(r["start"]), r["T"]))
    return columns_of(rows, COLUMNS + ("start",))


def _summary(case: Case, table: dict, study: Study, seconds: float) -> dict:
    from ...util.version import __version__

    kinds = {k: int(np.sum(table["kind"] == k)) for k in KINDS}
    per = {}
    for s in dict.fromkeys(table["start"]):
        sel = table["start"] == s
        per[s] = {"kinds": {k: int(np.sum(table["kind"][sel] == k)) for k in KINDS},
                  "periodic_by_m": {str(m): int(np.sum(sel & (table["m"] == m))) for m in
                                    sorted(set(table["m"][sel & (table["kind"] == "periodic")].tolist()))}}
    res = np.abs(table["energy_residual"])
    return {"plbar_version": __version__, "case": case_fields(case), **study.params, "rows": int(table["T"].size),
            "kinds": kinds, "by_start": per, "drifting": int(np.sum(table["steady"] == 0) - kinds.get("failed", 0)),
            "xi_eq": _span(table["xi_eq"]), "loss_per_T": _span(table["loss_per_T"]),
            "energy_residual_max": float(res[np.isfinite(res)].max()) if np.isfinite(res).any() else None,
            "seconds": round(seconds, 3)}


def _span(a) -> list | None:
    """``[min, max]`` of the finite values (None where there are none: every motion failed, e.g. a continuum march
    stopped by chatter)."""
    a = np.asarray(a, float)
    fin = np.isfinite(a)
    return [float(a[fin].min()), float(a[fin].max())] if fin.any() else None


def write_survey(folder, table: dict, summary: dict) -> dict:
    """``survey.csv`` and ``summary.json`` (atomically)."""
    folder = Path(folder)
    cols = list(COLUMNS) + ["start"]
    fmts = ["%s" if c in TEXT_COLUMNS else ("%d" if c in INT_COLUMNS else "%.17g") for c in cols]
    return {"table": write_csv(folder / "survey.csv", cols, [table[c] for c in cols], fmts),
            "summary": write_json(folder / "summary.json", summary)}


def survey(case: Case | None = None, T=None, periods: int = 1000, record: int | None = None, modes=("rest",),
           executor=None, progress: bool = False, chunks=None) -> Survey:
    """What the bar does at every forcing period ``T``, in memory (no files).

    Parameters
    ----------
    case : Case, optional
        Default: the paper's chain.
    T : array_like
        Forcing periods (default :func:`default_periods`).
    periods, record : int
        Forcing periods simulated from the start, and how many of the last are recorded (default
        :func:`default_record`: 100, or a tenth of ``periods`` when that is fewer).
    modes : sequence of {"rest", "up", "down"}
        Starts: from rest, and sweeps that carry the final state to the next period up or down.
    executor : concurrent.futures.Executor, optional
        Default serial (in this process).
    """
    case = case or Case()
    T = default_periods(case) if T is None else T
    t0 = time.perf_counter()
    study = survey_study(case, T, periods, record, modes, chunks)
    ex = executor or SerialExecutor()
    results = [f.result() for f in [ex.submit(survey_task, t) for t in study.tasks]]
    table = _table(results)
    return Survey(case, table, _summary(case, table, study, time.perf_counter() - t0))


def default_periods(case: Case, num: int = 161) -> np.ndarray:
    """Default forcing periods: ``[6, 14]`` for the paper's case, ``[0.6, 1.4] T0^I`` for another chain and
    ``[0.75, 2.25] T0^I`` for an FE bar (``T/L`` in ``[1.5, 4.5]`` for a uniform bar, ``T0^I = 2 L / c``), never
    beyond the forcing periods ``plbar run`` searches by default (:func:`plbar.app.signatures.search_window`:
    ``(T0^I + T0^II) / 2``, ``T/L = 3`` for a uniform FE bar), so that the figure's exact branches cover it.
    The bar and load decide, not the search options nor the contact's restitution (the natural periods are
    those of the plastic contact whatever ``e``)."""
    from ...app.signatures import search_window
    from ...paths.branches import default_domain

    if case_fields(replace(case, restitution=0.0)) == case_fields(Case()):
        return np.linspace(6.0, 14.0, num)
    if case.model == "continuum":                # the same window as the FE bar's, from the exact natural periods
        from ...continuum import natural_periods

        TI, TII = natural_periods(case.continuum())
        return np.linspace(0.75 * TI, min(2.25 * TI, 0.5 * (TI + TII)), num)
    prob = case.problem()
    T0 = prob.system.T0[0]
    lo, hi = (0.6, 1.4) if case.model == "chain" else (0.75, 2.25)
    return np.linspace(lo * T0, min(hi * T0, search_window(prob, default_domain(prob))[1]), num)


def _claim(folder: Path, study: Study, overwrite: bool):
    """The one ownership rule (:func:`plbar.util.outputs.claim_folder`): the same survey (its tasks, whatever
    plbar computes them) resumes; another command's or survey's folder is refused unless ``overwrite``."""
    return claim_folder(folder, "survey", fingerprint(list(study.tasks)), SURVEY_OWNED, overwrite)


def run_survey(case: Case, T, periods: int = 1000, record: int | None = None, out="plbar-survey", modes=("rest",),
               chunks=None, paths=None, **options) -> Survey:
    """Run (or resume) a survey into ``out``: ``survey.csv``, ``summary.json`` and the figure (PNG + PDF).

    Parameters
    ----------
    case, T, periods, record, modes
        As :func:`survey`.
    chunks : int, optional
        Tasks the from-rest periods are split into (default :func:`plbar.studies.survey.tasks.default_chunks`).
    out : path
        The study folder (a killed survey resumes there).
    paths : plbar.Paths, optional
        The branches of the paper's class (:attr:`plbar.Result.paper`), drawn under the survey: the exact
        periodic responses of the paper's class, stable and unstable.

    Other Parameters
    ----------------
    executor, progress, overwrite, plot
        The study's run options (:class:`plbar.studies.RunOptions`): where the tasks run (default
        serial), the progress on stderr, whether another study's folder may be replaced, the figure.
    """
    opts = run_options(options, "run_survey")
    executor, progress = opts.executor, opts.progress
    t0 = time.perf_counter()
    folder = Path(out)
    study = survey_study(case, T, periods, record, modes, chunks, checkpoints=folder / "sweeps")
    claim = _claim(folder, study, opts.overwrite)
    try:
        if progress and case.model != "continuum" and not compiled(case.problem()):   # built once (Case.problem)
            message(f"plbar: {COMPILE_NOTE}")
        if executor is not None and not isinstance(executor, SerialExecutor) and case.model != "continuum":
            prepare(case.problem())              # forked workers inherit the loaded (or first compiled) kernel
        results = run_study(folder, study, executor, progress=progress, overwrite=True)
    except BaseException as exc:
        # nothing finished: nothing left to block a corrected rerun (and an interrupt says that nothing was kept)
        claim.abandon(("tasks/*.json", "sweeps/*"), exc)
        raise
    table = _table(results)
    summary = _summary(case, table, study, time.perf_counter() - t0)
    files = write_survey(folder, table, summary)
    if opts.plot:
        from ...visuals import survey_plot
        from ...visuals.style import unit_note

        files["figure"] = survey_plot(table, folder, "survey", paths=paths, title=case_title(case),
                                      units=unit_note(case.bar() if case.structure is None else None))
    return Survey(case, table, summary, files)


def case_title(case: Case) -> str:
    """A figure title naming the model: ``chain N = 5``, ``FE P1 lumped, N = 16, end mass 0.5``."""
    if case.structure is not None:
        where = f" ({Path(case.matrices).name})" if case.matrices else ""
        return f"structure of {case.structure.n} DOFs{where}"
    if case.model == "chain":
        return f"chain N = {case.n_eff}"
    if case.model == "continuum":
        return f"continuum (characteristics, {case.n_eff} steps per L/c)" + (
            f", end mass {case.end_mass:g}" if case.end_mass else "")
    s = f"FE {case.element} {case.mass}, N = {case.n_eff}"
    return s + (f", end mass {case.end_mass:g}" if case.end_mass else "")
