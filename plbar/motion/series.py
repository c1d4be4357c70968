"""A simulated motion as a time series: the recorded window of one trajectory, at any times (issue 28).

The compiled simulator keeps, over its recorded window, the state at every
period boundary and every event (time, kind, loss).  Between events the flow
is exact, so the motion at any time of the window follows from them: start
from the state at the boundary of its period, carry it by the closed-form
modal flows (:func:`plbar.response.segment`, another implementation than the
kernel's) through the period's events, switching at each (opening: the
state I modes seen by state II, ``P12``; impact: ``P21`` for positions,
``Q21`` for velocities, the contact DOF stopped, Eq. (10); a rebound with a
coefficient of restitution: Newton's law along the contact DOF, the gap still open).  Each period
restarts from the kernel's own boundary state, so the series is exact at the
boundaries and an irregular motion's sensitivity cannot carry round-off from
one period to the next; :meth:`MotionSeries.boundary_mismatch` measures how
well the flows carry each boundary state to the next (round-off).

:class:`MotionSeries` answers what :func:`plbar.io.motion_data` asks (the
physical states, the contact reaction and the energies at given times).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..model import Problem
from ..response import segment
from .model import STUCK
from .run import Run

__all__ = ["MotionSeries", "SNAP"]

SNAP = 1e-9   #: an event within ``SNAP * T`` after a boundary belongs to the period before it (the boundary state)


class MotionSeries:
    """Trajectory ``b`` of a :class:`Run` over the last ``periods`` periods of its recorded window.

    Parameters
    ----------
    prob : Problem
        The problem the run simulated (its system and load).
    r : Run
        A run that recorded at least ``periods`` periods (``run(..., record=...)``).
    b : int
        The trajectory.
    periods : int, optional
        The last ``periods`` recorded periods (default: all of them).

    Attributes
    ----------
    T, phi : float
        Forcing period and phase (load ``q cos(2 pi t / T - phi)``).
    t0, span : float
        Absolute start time of the window and its length ``periods T``.
    events : dict of ndarray
        ``time`` (absolute), ``kind`` (1 opening, 2 impact, 3 rebound, 4 the impact that ends a chattering
        sequence, recorded at its accumulation point), ``loss`` of the window's events.
    """

    def __init__(self, prob: Problem, r: Run, b: int, periods: int | None = None):
        R = int(r.record)
        P = R if periods is None else periods
        if isinstance(P, bool) or int(P) != P or not 1 <= P <= R:
            raise InputError(f"periods = {periods!r} must be an integer in [1, {R}] (the run recorded {R} periods)")
        P = int(P)
        self.prob, self.b, self.periods = prob, int(b), P
        self.T, self.phi = float(r.T[b]), float(r.phi[b])
        k0 = R - P
        self.t0 = (r.periods - R + k0) * self.T
        self.span = P * self.T
        self._x = np.asarray(r.strobe_x[b, k0:], float)
        self._v = np.asarray(r.strobe_v[b, k0:], float)
        self._s = np.asarray(r.strobe_state[b, k0:], int)
        after = r.events["time"] > self.t0 + SNAP * self.T if self.t0 > 0 else r.events["time"] >= 0.0
        sel = (r.events["traj"] == b) & after        # the run's start is before its events at t = 0 (see _carry)
        self.events = {k: np.asarray(r.events[k][sel]) for k in ("time", "kind", "loss")}

    # -- modal <-> physical ------------------------------------------------------------------------------------
    def _modal(self, k: int):
        """The boundary state ``k`` in the modal coordinates of its state: ``(state 1|2, eta, etadot)``."""
        sy = self.prob.system
        M = np.asarray(sy.M, float)
        x, v = self._x[k], self._v[k]
        if self._s[k] == STUCK:
            Mr = M[:-1, :-1]
            return 1, sy.V1.T @ (Mr @ x[:-1]), sy.V1.T @ (Mr @ v[:-1])
        return 2, sy.V2.T @ (M @ x), sy.V2.T @ (M @ v)

    def _flow(self, s: int, ts: float, tau: float, e, v):
        sy, prob = self.prob.system, self.prob
        damped = bool(getattr(sy, "damped", False))
        w, f, zeta = (sy.w1, prob.f1, sy.zeta1 if damped else None) if s == 1 else \
            (sy.w2, prob.f2, sy.zeta2 if damped else None)
        return segment(w, np.asarray(f, float), 2 * np.pi / self.T, ts, tau, e, v, np.cos(self.phi),
                       np.sin(self.phi), zeta=zeta)

    def _switch(self, s: int, kind: int, e, v):
        sy = self.prob.system
        if kind == 1:
            if s != 1:
                raise InputError("an opening of the gap recorded while it is open: not this run's events")
            return 2, sy.P12 @ e, sy.P12 @ v
        if s != 2:
            raise InputError("an impact recorded in contact: not this run's events")
        if kind == 3:                      # a rebound: Newton's law along the contact DOF, the gap stays open
            g = np.asarray(sy.gap_row, float)
            return 2, e, v - (1.0 + float(self.prob.restitution)) * (g @ v) / (g @ g) * g
        return 1, sy.P21 @ e, sy.Q21 @ v

    def _stick_time(self, t: float, te: float, e, v) -> float:
        """The time of the impact that ends a chattering sequence, recorded at ``te``: the simulator records it at
        the accumulation point of the rebounds it stands for, ``2 e v_c / (a (1 - e))`` after the impact, where
        it switched (:func:`plbar.motion.kernel.loop.rebound`).  The last return of the gap to zero in the free
        flight ``[t, te]`` (from the state ``e, v`` at ``t``)."""
        g = np.asarray(self.prob.system.gap_row, float)
        xc = lambda u: float(g @ self._flow(2, t, u - t, e, v)[0])   # noqa: E731
        grid = np.linspace(t, te, 65)[1:]
        vals = np.array([xc(u) for u in grid])
        if not vals[-1] > 0:
            return te
        neg = np.flatnonzero(vals <= 0)
        if not neg.size:
            return te
        from scipy.optimize import brentq

        return float(brentq(xc, grid[neg[-1]], grid[neg[-1] + 1], xtol=1e-15 * max(abs(te), 1.0), rtol=1e-15))

    def _carry(self, k: int, t_end: float):
        """The modal state at ``t_end`` (in period ``k``), carried from boundary ``k`` through the events up to it."""
        s, e, v = self._modal(k)
        t = self.t0 + k * self.T
        ev = self.events
        # a boundary state is recorded after the events at it, but the run's start is its initial state: an event
        # at t = 0 (a contact that opens at once: P2's wall reaction is round-off there) is still to come
        lo = np.searchsorted(ev["time"], t + SNAP * self.T, side="right") if t > 0 else 0
        hi = np.searchsorted(ev["time"], t_end, side="right")
        for i in range(lo, hi):
            te, kind = float(ev["time"][i]), int(ev["kind"][i])
            if kind == 4:                  # the end of a chattering sequence: switched before it was recorded
                te = self._stick_time(t, te, e, v)
            e, v = self._flow(s, t, te - t, e, v)
            s, e, v = self._switch(s, kind, e, v)
            t = te
        e, v = self._flow(s, t, t_end - t, e, v)
        return s, e, v

    def _physical(self, s, e, v):
        sy = self.prob.system
        if s == 1:
            return sy.embed(sy.V1 @ e), sy.embed(sy.V1 @ v)
        return sy.V2 @ e, sy.V2 @ v

    # -- what the export asks ---------------------------------------------------------------------------------
    def _period(self, t: float) -> int:
        k = int(np.floor((t - self.t0) / self.T + 1e-12))
        return min(max(k, 0), self.periods - 1) if t < self.t0 + self.span else self.periods - 1

    def modal(self, times):
        """Per absolute time in the window: ``(state 1|2, eta, etadot, t)``."""
        out = []
        for t in np.asarray(times, float).ravel():
            if not self.t0 - 1e-12 * self.span <= t <= self.t0 + self.span * (1 + 1e-12):
                raise InputError(f"t = {t:.12g} is outside the window [{self.t0:.12g}, {self.t0 + self.span:.12g}]")
            out.append((*self._carry(self._period(t), float(t)), float(t)))
        return out

    def response(self, times):
        """Physical ``x, v`` (K, n) and state (K,) (1 in contact, 2 gap open) at absolute ``times``."""
        xs, vs, st = [], [], []
        for s, e, v, _ in self.modal(times):
            x, u = self._physical(s, e, v)
            xs.append(x)
            vs.append(u)
            st.append(s)
        return np.array(xs), np.array(vs), np.array(st)

    def reaction(self, times):
        """``-R`` in state I at ``times`` (0 in state II), as :meth:`plbar.periodic.OrbitSeries.reaction_at`."""
        sy, prob = self.prob.system, self.prob
        W = 2 * np.pi / self.T
        rv = np.asarray(sy.r_v, float) if getattr(sy, "damped", False) else np.zeros(sy.w1.size)
        return np.array([-(sy.r_eta @ e + rv @ v + prob.r_q * np.cos(W * t - self.phi)) if s == 1 else 0.0
                         for s, e, v, t in self.modal(times)])

    def energies(self, times):
        """Kinetic and potential energy (Eqs. (12)-(13)) at ``times``; each (K,)."""
        sy = self.prob.system
        ek, ep = [], []
        for s, e, v, _ in self.modal(times):
            w = sy.w1 if s == 1 else sy.w2
            ek.append(0.5 * float(v @ v))
            ep.append(0.5 * float(np.sum((w * e) ** 2)))
        return np.array(ek), np.array(ep)

    def boundary_mismatch(self) -> float:
        """Largest distance between a boundary state carried over its period by the flows and the kernel's next
        boundary state, relative to the largest state of the window (round-off: the two integrations agree)."""
        scale = max(float(np.abs(np.c_[self._x, self._v]).max()), 1e-300)
        worst = 0.0
        for k in range(self.periods):
            s, e, v = self._carry(k, self.t0 + (k + 1) * self.T)
            x, u = self._physical(s, e, v)
            worst = max(worst, float(np.abs(np.r_[x - self._x[k + 1], u - self._v[k + 1]]).max()) / scale)
        return worst

    @property
    def stuck_time(self) -> float:
        """Time in contact over the window (from the events and the boundary states)."""
        total, t = 0.0, self.t0
        s = 1 if self._s[0] == STUCK else 2
        for te, ke in zip(self.events["time"], self.events["kind"]):
            if te > self.t0 + self.span:
                break
            if s == 1:
                total += te - t
            s, t = (2 if ke == 1 else 1), te
        if s == 1:
            total += self.t0 + self.span - t
        return total
