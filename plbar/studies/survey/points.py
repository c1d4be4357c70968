"""One chunk of a survey: simulate forcing periods together and characterise what each settles on.

The result of a chunk is JSON-able (one dict per forcing period, the columns of
``survey.csv``), so a study task can return it and a checkpoint can hold it.
Where the motion is periodic with ``m = 1``, one impact and a stuck phase of
positive length (the paper's class), the exact response at that period is
polished from the simulation (:func:`plbar.find_response`, the stuck time as the
guess) and its loss and ``xi_eq`` are reported beside the simulated ones.
"""

from __future__ import annotations

import numpy as np

from ...app import Case
from ...motion import KINDS, Padded, Start, padded, run, steady
from ...response import NoResponseError, find_response

__all__ = ["COLUMNS", "survey_chunk", "start_of", "start_json"]

#: the columns of survey.csv, in order (the first thirteen are the issue's minimum)
COLUMNS = ("T", "kind", "m", "impacts_per_T", "loss_per_T", "loss_min", "loss_max", "xi_eq", "xi_min", "xi_max",
           "xi_w", "amp_c", "stuck_fraction", "loss_std", "xi_std", "amp_c_max", "work_per_T", "distance",
           "energy_residual", "exact_loss", "exact_xi", "exact_T1", "status")


def start_json(s: Start, i: int) -> dict:
    """Row ``i`` of a start as JSON (exact floats)."""
    return {"state": int(s.state[i]), "eta": [float(v) for v in s.eta[i]], "vel": [float(v) for v in s.vel[i]]}


def start_of(rows: list[dict]) -> Start:
    """A :class:`Start` from JSON rows (:func:`start_json`)."""
    return Start(np.array([r["state"] for r in rows], int), np.array([r["eta"] for r in rows], float),
                 np.array([r["vel"] for r in rows], float))


def _polish(prob, T: float, stuck: float, loss: float) -> dict:
    """The exact response of the paper's class at ``T`` nearest the simulated stuck time (or empty fields)."""
    try:
        r = find_response(prob, T, stuck)
    except (NoResponseError, ValueError, ArithmeticError):
        return {}
    if not abs(r.dPL - loss) <= 1e-3 * max(loss, 1e-300):
        return {}                          # another response of the class: not the one simulated
    return {"exact_loss": float(r.dPL), "exact_xi": float(r.xi), "exact_T1": float(r.T1)}


def survey_chunk(case: Case, T, periods: int, record: int, start: Start | None = None, pad: Padded | None = None,
                 progress=None) -> tuple[list[dict], Start]:
    """Simulate the forcing periods ``T`` together and characterise each; returns ``(rows, final states)``.

    Parameters
    ----------
    case : Case
    T : sequence of float
    periods, record : int
        Forcing periods simulated, and the last ones recorded (:func:`plbar.motion.run`).
    start : Start, optional
        Initial states (default: at rest against the wall, load ``q cos(2 pi t / T)``).
    """
    prob = case.problem()
    pad = pad or padded(prob)
    T = np.asarray(T, float)
    r = run(pad, T, 0.0, periods, record, start, progress)
    s = steady(r)
    rows = []
    for i in range(T.size):
        row = {c: float(getattr(s, c)[i]) for c in COLUMNS if hasattr(s, c) and c not in ("kind", "m")}
        row.update(kind=KINDS[int(s.kind[i])], m=int(s.m[i]), status=int(r.status[i]))
        if row["kind"] == "periodic" and row["m"] == 1 and row["impacts_per_T"] == 1 and row["stuck_fraction"] > 0:
            row.update(_polish(prob, float(T[i]), row["stuck_fraction"] * float(T[i]), row["loss_per_T"]))
        rows.append(row)
    return rows, r.final
