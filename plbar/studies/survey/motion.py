"""The motion a survey found, again: one forcing period of a survey folder simulated as the survey did (issue 28).

``plbar export --from SURVEY --T 7 --periods 20`` and ``plbar render --from SURVEY --T 7`` show what the
survey characterised: the same case, the same simulation (the compiled kernel is deterministic: the same
start, periods and forcing give the same trajectory, bit for bit), its last ``periods`` periods as a
:func:`plbar.motion.motion_series`.  ``start``: ``rest`` (the survey's runs from rest), or ``up`` / ``down``
(a sweep of the survey: the motion at ``T`` from the final state the sweep left at the forcing period before
it, read from the sweep's checkpoints).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ...app import Case, case_start
from ...errors import InputError
from ...motion import Series, motion_series, padded, run
from ...util.outputs import read_owner
from .points import start_of
from .tasks import MODES, case_of, sweep_key

__all__ = ["SurveyMotion", "survey_motion", "is_survey", "surveyed_period", "PERIOD_RTOL"]

#: a forcing period asked for is taken as the surveyed one within this relative distance (or half the spacing
#: to the next surveyed period, if smaller): ``--T 2.5`` picks a survey's 2.499581703
PERIOD_RTOL = 1e-3


def is_survey(folder) -> bool:
    """Whether ``folder`` holds a survey (``plbar survey`` from rest or swept; not a load study)."""
    own = read_owner(folder)
    return own is not None and own.command == "survey" and (Path(folder) / "study.json").is_file()


@dataclass(frozen=True)
class SurveyMotion:
    """One motion of a survey: its case, the series of its last periods and what the survey said of it."""

    case: Case
    series: Series              # or a plbar.continuum.ContinuumSeries (model = "continuum")
    row: dict
    start: str
    T: float = float("nan")     # the surveyed forcing period shown (the one nearest the T asked for)

    @property
    def info(self) -> dict:
        """What the export records beside the fields (``response.json``)."""
        keep = ("kind", "m", "signature", "loss_per_T", "xi_eq", "xi_w", "impacts_per_T", "exact_loss", "exact_xi")
        return {"survey_" + k: (v if isinstance(v, (str, int)) else float(v)) for k, v in self.row.items()
                if k in keep and not (isinstance(v, float) and np.isnan(v))} | {"start": self.start}


def surveyed_period(Ts, T: float) -> float:
    """The surveyed forcing period (of ``Ts``) that ``T`` stands for, else :class:`~plbar.errors.InputError`.

    ``T`` stands for the nearest surveyed period within ``PERIOD_RTOL * T`` and within half the spacing from that
    period to its neighbours; the refusal names the surveyed periods on either side of ``T``.
    """
    Ts = np.unique(np.asarray(Ts, float))
    i = int(np.argmin(np.abs(Ts - T)))
    gaps = np.abs(np.diff(Ts[max(i - 1, 0):i + 2]))
    tol = min(PERIOD_RTOL * abs(T), 0.5 * gaps.min() if gaps.size else np.inf)
    if abs(Ts[i] - T) <= tol:
        return float(Ts[i])
    below, above = Ts[Ts < T], Ts[Ts > T]
    near = " and ".join(f"{v:.10g}" for v in (below[-1:].tolist() + above[:1].tolist()))
    raise InputError(f"T = {T:.10g} is not a forcing period of this survey ({Ts.size} in [{Ts.min():.10g}, "
                     f"{Ts.max():.10g}]; the nearest: {near})")


def _study(folder: Path) -> dict:
    try:
        return json.loads((folder / "study.json").read_text())
    except (OSError, ValueError):
        raise InputError(f"{str(folder)!r} holds no readable study.json: not a finished 'plbar survey'") from None


def survey_motion(folder, T: float, periods: int = 10, start: str = "rest") -> SurveyMotion:
    """The motion at forcing period ``T`` of the survey in ``folder``, its last ``periods`` periods.

    Raises :class:`plbar.errors.InputError` when ``folder`` is not a survey, ``T`` is not one of its forcing
    periods, ``start`` not one of its starts or ``periods`` longer than its simulation.
    """
    folder = Path(folder)
    if not is_survey(folder):
        raise InputError(f"{str(folder)!r} is not the folder of a 'plbar survey' (no survey study there)")
    if start not in MODES:
        raise InputError(f"--start {start!r} must be one of {', '.join(MODES)}")
    study = _study(folder)
    tasks = [t["task"] for t in study["tasks"] if t["task"]["mode"] == start]
    if not tasks:
        got = sorted({t["task"]["mode"] for t in study["tasks"]})
        raise InputError(f"the survey in {str(folder)!r} has no '{start}' start (it has {', '.join(got)}); "
                         "run it with --continue up/down for a sweep")
    T = surveyed_period(np.array([t for task in tasks for t in task["T"]], float), T)
    task = next(tk for tk in tasks if any(abs(t - T) <= 1e-12 * abs(t) for t in tk["T"]))
    total = int(task["periods"])
    if isinstance(periods, bool) or int(periods) != periods or not 1 <= periods <= total:
        raise InputError(f"--periods {periods!r} must be an integer in [1, {total}] (the survey simulated {total})")
    case = case_of(task["case"])
    s0 = None
    if start != "rest":
        j = [abs(t - T) <= 1e-12 * abs(T) for t in task["T"]].index(True)
        if j > 0:
            ck = Path(task["checkpoints"]) / sweep_key(task) / f"T{j - 1:05d}.json"
            try:
                s0 = start_of([json.loads(ck.read_text())["final"]])
            except (OSError, ValueError, KeyError):
                raise InputError(f"the sweep's checkpoint {str(ck)!r} is missing: rerun the survey") from None
    row = _row(folder, T, start)
    if case.model == "continuum" and case.rayleigh is not None:
        raise InputError("export and render of the damped continuum's motions are not built (its modal solution "
                         "keeps no field history); export the motion of a fine FE mesh (--model fe -N 256 "
                         "--element P2 --mass redistributed), which agrees with it to 1e-4 over 20 periods")
    if case.model == "continuum":                  # the same march again (deterministic), its line kept
        from ...continuum import ContinuumSeries, simulate

        cr = simulate(case.continuum(), T, periods=total, steps_per_L=case.n_eff, record=int(periods))
        grid = replace(case, model="fe").problem()     # P1 on the continuum's grid: the mesh the samples sit on
        return SurveyMotion(case, ContinuumSeries(cr, int(periods), grid), row, start, T)
    prob = case.problem()
    s0 = case_start(case, prob, 1) if s0 is None else s0       # the case's start (a sweep's first period), or rest
    r = run(padded(prob), np.array([T]), 0.0, total, int(periods), s0)
    return SurveyMotion(case, motion_series(prob, r, 0, int(periods)), row, start, T)


def _row(folder: Path, T: float, start: str) -> dict:
    """The survey's row of ``T`` and ``start`` (from survey.csv; empty if the table is missing)."""
    import csv

    try:
        with open(folder / "survey.csv", newline="") as f:
            for row in csv.DictReader(f):
                if row.get("start", "rest") == start and abs(float(row["T"]) - T) <= 1e-12 * abs(T):
                    out = {}
                    for k, v in row.items():
                        try:
                            out[k] = int(v) if k in ("m", "status") else (float(v) if v else np.nan)
                        except ValueError:
                            out[k] = v
                    return out
    except OSError:
        pass
    return {}
