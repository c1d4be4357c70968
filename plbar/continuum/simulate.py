"""Simulate the continuum bar for whole forcing periods and keep the survey's accounts (:class:`ContinuumRun`)."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..util.record import Record, events
from .accounts import bar_energy, strobe, velocity_square, work
from .bar import ContinuumBar
from .fields import Line
from .stepper import IMPACT, OPENING, Field, Start, march

__all__ = ["ContinuumRun", "simulate"]


@dataclass(frozen=True, kw_only=True)
class ContinuumRun(Record):
    """What :func:`simulate` recorded, per forcing period ``p`` (``P = periods``; ``R = record``): a
    :class:`plbar.util.record.Record` of one trajectory.

    Attributes
    ----------
    T, phi : float
    status : ndarray of int, shape (1,)
        0 (a march that cannot go on raises instead).
    events : ndarray of dtype EVENT, shape (E,)
        ``time``, ``kind`` (1 opening, 2 impact), ``v`` (impact velocity), ``loss``; ``traj`` 0.
    impacts, openings : ndarray of int, shape (P,)
    loss, work, amp : ndarray, shape (P,)
        Impact loss (``m_e v^2 / 2``, Eq. (14); 0 at ``m_e = 0``), work of the load, largest ``-u(L)``.
    energy : ndarray, shape (P + 1,)
        Bar (kinetic + strain) plus end-mass kinetic energy at the period boundaries.
    v2 : ndarray, shape (R,)
        ``int int rhoA v^2 dx dt`` over each of the last ``R`` periods (for ``xi_omega``).
    strobe_u, strobe_v : ndarray, shape (R + 1, n + 1)
        ``u, v`` on the grid ``x_j = j L / n`` at the boundaries of the last ``R`` periods.
    end : ndarray, shape (P + 1, 3)
        ``u(L), v(L)`` and stuck (1) / free (0) at every period boundary.
    elapsed : float
        Seconds the march took.
    line : Line
        The stored delay line: the whole solution (:mod:`.fields` evaluates it anywhere, :class:`.ContinuumSeries`).
    """

    bar: ContinuumBar
    periods: int
    record: int
    n: int
    dt: float
    impacts: np.ndarray
    openings: np.ndarray
    loss: np.ndarray
    work: np.ndarray
    amp: np.ndarray
    energy: np.ndarray
    v2: np.ndarray
    strobe_u: np.ndarray
    strobe_v: np.ndarray
    end: np.ndarray
    elapsed: float
    line: Line = field(default=None, repr=False)

    @property
    def omega(self) -> float:
        return 2 * math.pi / self.T

    @property
    def energy_residual(self) -> float:
        """``(work - losses - (E_end - E_0)) / work`` over the whole run (0 for an exact balance)."""
        W = float(self.work.sum())
        return (W - float(self.loss.sum()) - (self.energy[-1] - self.energy[0])) / W

    @property
    def xi_omega(self) -> float:
        """``xi_omega = mean loss per period / (2 omega mean int int rhoA v^2)`` over the recorded periods."""
        R = self.record
        return float(self.loss[-R:].mean() / (2 * self.omega * self.v2.mean()))

    def __repr__(self) -> str:
        return (f"ContinuumRun(T={self.T:g}, periods={self.periods}, n={self.n}, impacts/period="
                f"{self.impacts[-self.record:].mean():.3g}, loss/period={self.loss[-self.record:].mean():.6g})")


def _per_period(ev: np.ndarray, T: float, periods: int, kind: int, what: str | None = None) -> np.ndarray:
    sel = ev["kind"] == kind
    idx = np.minimum((ev["time"][sel] / T).astype(int), periods - 1)
    w = None if what is None else ev[what][sel]
    return np.bincount(idx, w, minlength=periods)[:periods]


def simulate(bar: ContinuumBar, T: float, periods: int = 20, steps_per_L: int = 64, phi: float = 0.0,
             record: int | None = None, hold: str | None = None, start: Start | None = None) -> ContinuumRun:
    """March the bar from rest against the wall (or ``start``) under ``q cos(2 pi t / T - phi)`` for ``periods``.

    Parameters
    ----------
    bar : ContinuumBar
    T : float
        Forcing period.
    periods : int
    steps_per_L : int
        Grid steps ``n`` per travel time ``L / c`` (``dt = L / (c n)``).
    phi : float
    record : int, optional
        The last periods whose ``v2`` and grid states are kept (default ``min(periods, 10)``).
    hold : {None, "closed", "open"}
        Forbid opening (clamped-clamped) or impacts (free end with its mass) - the linear checks.
    start : Start or Field, optional
        A harmonic state (:class:`Start`), or a given field of displacement and velocity on the grid
        (:class:`Field`: ``steps_per_L + 1`` values each); default the rest against the wall.

    Returns
    -------
    ContinuumRun
    """
    if not (isinstance(periods, (int, np.integer)) and periods >= 1):
        raise InputError(f"periods = {periods!r} must be an integer >= 1")
    if not (isinstance(steps_per_L, (int, np.integer)) and steps_per_L >= 2):
        raise InputError(f"steps_per_L = {steps_per_L!r} must be an integer >= 2")
    if not (math.isfinite(T) and T > 0):
        raise InputError(f"forcing period T = {T!r} must be finite and > 0")
    record = min(periods, 10) if record is None else int(record)
    if not 1 <= record <= periods:
        raise InputError(f"record = {record} must lie in [1, periods = {periods}]")
    t0 = time.perf_counter()
    mc = march(bar, T, periods, steps_per_L, phi, hold, start)
    h = mc.line
    ln = Line(h["t0"], h["t1"], h["a0"], h["a1"], h["C"], h["D"], mc.omega, phi, bar.q, bar.L, bar.c, bar.Z,
              bar.s, not isinstance(start, Start))      # from rest, or a field: the load starts at t = 0
    keep = mc.events["time"] <= periods * T
    ev = events(*(mc.events[k][keep] for k in ("time", "kind", "loss")), v=mc.events["v"][keep])
    st = Start(float(start.u[-1]), float(start.v[-1]), start.u[-1] == 0.0) if isinstance(start, Field) else \
        start or Start()
    end = np.concatenate([[(st.u, st.v, float(st.stuck))], mc.strobes[:periods]])
    bounds = T * np.arange(periods + 1)
    energy = bar_energy(ln, bounds) + 0.5 * bar.end_mass * end[:, 1] ** 2
    grid = [strobe(ln, t, steps_per_L) for t in bounds[periods - record:]]
    impacts, openings = (_per_period(ev, T, periods, kd).astype(int) for kd in (IMPACT, OPENING))
    return ContinuumRun(T=float(T), phi=float(phi), status=np.zeros(1, int), events=ev, bar=bar,
                        periods=int(periods), record=record, n=int(steps_per_L), dt=mc.dt, impacts=impacts,
                        openings=openings, loss=_per_period(ev, T, periods, IMPACT, "loss"), work=work(ln, T, periods),
                        amp=np.array(mc.amp[:periods]), energy=energy,
                        v2=velocity_square(ln, T, periods - record, periods, steps_per_L),
                        strobe_u=np.array([g[0] for g in grid]), strobe_v=np.array([g[1] for g in grid]), end=end,
                        elapsed=time.perf_counter() - t0, line=ln)
