"""One chunk of a survey: simulate forcing periods together and characterise what each settles on.

The result of a chunk is JSON-able (one dict per forcing period, the columns of
``survey.csv``), so a study task can return it and a checkpoint can hold it.
Where the motion is periodic, its exact periodic response is polished from the
simulation (:func:`plbar.periodic.from_motion`: the state at the start of the last
``m`` periods carried to an impact, the switches of ``m`` periods as the guess,
Newton): its signature (``1P`` is the paper's class, ``1Z`` one impact without a
stuck phase, ``2PZ`` ...), loss and ``xi_eq`` are reported beside the simulated ones,
with the orbit's largest multiplier and the window's distance from it.  A motion
that does not repeat over the window yet but approaches a stable orbit is shown
to settle (:mod:`.settle`) and reported periodic, with its distance and rate.
"""

from __future__ import annotations

import numpy as np

from ...app import Case, case_start
from ...motion import KINDS, Padded, Start, padded, run, steady
from ...errors import InputError, PlbarError
from ...model import rayleigh_ratio
from ...response import NoResponseError, find_response
from .linear import LINEAR_COLUMNS, linear_fields, linear_models
from .settle import Approach, approach, orbit_of, settle

__all__ = ["COLUMNS", "survey_chunk", "start_of", "start_json"]

#: the columns of survey.csv, in order (the first thirteen are the issue's minimum)
COLUMNS = ("T", "kind", "m", "impacts_per_T", "loss_per_T", "loss_min", "loss_max", "xi_eq", "xi_min", "xi_max",
           "xi_w", "amp_c", "stuck_fraction", "loss_std", "xi_std", "amp_c_max", "work_per_T", "distance",
           "energy_residual", "exact_loss", "exact_xi", "signature", "status", "viscous_per_T", "xi_total",
           "max_abs_multiplier", "orbit_distance", "rate", "steady", "drift_loss", "drift_vMv", *LINEAR_COLUMNS)


def start_json(s: Start, i: int) -> dict:
    """Row ``i`` of a start as JSON (exact floats)."""
    return {"state": int(s.state[i]), "eta": [float(v) for v in s.eta[i]], "vel": [float(v) for v in s.vel[i]]}


def start_of(rows: list[dict]) -> Start:
    """A :class:`Start` from JSON rows (:func:`start_json`)."""
    return Start(np.array([r["state"] for r in rows], int), np.array([r["eta"] for r in rows], float),
                 np.array([r["vel"] for r in rows], float))


def _orbit_fields(a: Approach) -> dict:
    """The row's fields of an orbit (JSON: a missing field is a blank of the table, never a nan)."""
    o = a.orbit
    return {"exact_loss": float(o.loss_per_T), "exact_xi": float(o.xi), "signature": str(o.sig.canonical()),
            "m": int(o.sig.m), "max_abs_multiplier": a.max_abs_multiplier, "orbit_distance": float(a.distance[-1]),
            "rate": a.rate}


def _polish(prob, r, b: int, m: int, loss: float) -> dict:
    """The exact orbit of trajectory ``b``'s periodic motion (or no fields if Newton does not get there).

    Any signature (:func:`.settle.orbit_of`, damped or not); where Newton does not get there, a motion of
    the paper's class by :func:`plbar.find_response` from the simulated stuck time.
    """
    try:
        a = approach(r, b, orbit_of(prob, r, b, m))
    except (PlbarError, ValueError, np.linalg.LinAlgError):
        return _polish_paper(prob, r, b, m, loss)
    if not abs(a.orbit.loss_per_T - loss) <= 1e-5 * max(loss, 1e-300):
        return _polish_paper(prob, r, b, m, loss)  # Newton went to another orbit: not the motion simulated
    fields = _orbit_fields(a)
    del fields["rate"]                              # on its orbit throughout: no approach to measure (a blank)
    return fields


def _polish_paper(prob, r, b: int, m: int, loss: float) -> dict:
    """A damped periodic motion of the paper's class (m = 1, one impact, a stuck phase) as its exact response."""
    if m != 1 or r.impacts[b].mean() != 1 or r.stuck[b].mean() <= 0:
        return {}
    T = float(r.T[b])
    try:
        o = find_response(prob, T, float(r.stuck[b].mean()))
    except (NoResponseError, PlbarError, ValueError, ArithmeticError):
        return {}
    if not abs(o.dPL - loss) <= 1e-5 * max(loss, 1e-300):
        return {}
    return {"exact_loss": float(o.dPL), "exact_xi": float(o.xi), "signature": "1P"}


def _row(s, r, i: int) -> dict:
    """The simulated columns of trajectory ``i`` (the steady statistics ``s`` of the run ``r``)."""
    row = {c: float(getattr(s, c)[i]) for c in COLUMNS if hasattr(s, c) and c not in ("kind", "m")}
    row.update(kind=KINDS[int(s.kind[i])], m=int(s.m[i]), status=int(r.status[i]), signature="",
               steady=int(s.steady[i]), viscous_per_T=float(s.viscous_per_T[i]))
    return row


def _continuum_rows(case: Case, T, periods: int, record: int, start, progress) -> list[dict]:
    """The rows of the continuum (:mod:`.continuum`): no exact orbit, ``xi_eq`` blank undamped (not defined)."""
    from .continuum import blank_columns, continuum_run

    if start is not None:
        raise InputError("model = 'continuum' starts from rest only (no sweeps: drop --continue)")
    T = np.asarray(T, float)
    r = continuum_run(case, T, periods, record, progress)
    s = steady(r)
    blank = blank_columns(case)
    rows = []
    for i in range(T.size):
        row = _row(s, r, i)
        if r.status[i] != 0:                           # the march stopped (chatter): no accounts to report
            rows.append({k: row[k] for k in ("T", "kind", "m", "status", "signature", "steady")})
            continue
        if case.rayleigh is not None:                  # the damped continuum: Rayleigh's ratio at omega + the impact's
            row["xi_total"] = float(rayleigh_ratio(*case.rayleigh, 2 * np.pi / T[i]) + row["xi_eq"])
        # blanks: never a nan nor an inf (a march stopped by chatter has no accounts: its row is T, kind 'failed'
        # and its status)
        rows.append({k: v for k, v in row.items() if k not in blank and not (isinstance(v, float)
                                                                            and not np.isfinite(v))})
    return rows


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
        Initial states (default: the case's start, :mod:`plbar.app.start`, or at rest against the wall; load
        ``q cos(2 pi t / T)``).
    """
    if case.model == "continuum":                      # the exact bar by characteristics: no exact orbits to polish
        return _continuum_rows(case, T, periods, record, start, progress), None
    prob = case.problem()
    pad = pad or padded(prob)
    T = np.asarray(T, float)
    start = case_start(case, prob, T.size) if start is None else start     # the case's start, or rest
    r = run(pad, T, 0.0, periods, record, start, progress)
    s = steady(r)
    # the exact orbits (plbar.periodic), with rebounds where e > 0; none where a constant load pushes a rigid-body
    # motion (the periodic solvers do not take it: the simulated motion's own statistics stand alone)
    exact = prob.statics.accel is None
    settled = {b: settle(prob, r, b) for b in np.flatnonzero(s.kind == KINDS.index("irregular"))} if exact else {}
    settled = {b: a for b, a in settled.items() if a is not None}
    # the exact orbit of each periodic motion (any restitution: R in the signature for a rebound)
    orbit = {b: a for b in (np.flatnonzero(s.kind == KINDS.index("periodic")) if exact else ())
             if (a := _polish(prob, r, b, int(s.m[b]), float(s.loss_per_T[b])))}
    orbit.update({b: _orbit_fields(a) for b, a in settled.items()})
    # a row names its orbit's period: its statistics are taken over whole orbits of it (not the window's repeat)
    period = [int(orbit[b].get("m", 0)) if b in orbit else 0 for b in range(T.size)]
    if any(p and p != s.m[b] for b, p in enumerate(period)):
        s = steady(r, settled=period)
    models = linear_models(prob)
    rows = []
    for i in range(T.size):
        row = _row(s, r, i)
        row.update(linear_fields(models, float(T[i]), float(s.xi_eq[i])))
        row.update(xi_total=float(prob.system.rayleigh_ratio(2 * np.pi / T[i]) + s.xi_eq[i])
                   if getattr(prob.system, "damped", False) else float(s.xi_eq[i]))
        row.update(orbit.get(i, {}))
        rows.append(row)
    return rows, r.final
