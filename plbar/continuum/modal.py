"""The damped continuum bar by exact modal superposition in each contact state (issue 29).

Rayleigh damping ``C = alpha M + beta K`` of the FE bar tends, under refinement, to a Kelvin-Voigt bar with mass
damping: ``rhoA (u_tt + alpha u_t) = EA (u_x + beta u_xt)_x + F(t) delta_s``, the end mass obeying
``m_e (u_tt + alpha u_t) = -EA (u_x + beta u_xt)(L)`` while free.  Characteristics no longer apply (the stress
``beta EA u_xt`` diffuses every front), but in each contact state the bar is linear, its undamped modes are known in
closed form and they diagonalise the damping (``c_j = alpha + beta omega_j^2``):

* held **closed** (clamped-clamped, the end mass at rest against the wall): ``phi_j = sin(j pi x / L)``;
* held **open** (clamped, end mass free): ``phi_j = sin(k_j x)``, ``cos z = (m_e / rhoA L) z sin z``, ``z = k_j L``,
  normalised with the end mass (``int rhoA phi^2 + m_e phi(L)^2 = 1``).

Each modal coordinate moves in closed form (the harmonic particular solution plus two exponentials), so a state
is exact but for the truncation to ``K`` modes.  The switches follow the simulator's rules: a plastic impact when
``u(L)`` reaches the wall (the end mass stops, the bar's field is kept: ``q_closed = P q_open``, loss
``m_e v_L^2 / 2``), an opening when the wall's reaction ``R = -sigma(L)`` (``+ F`` for a load on the end) turns
tensile (``q_open = P^T q_closed``), ``P`` the overlap of the two bases in ``L2(rhoA)``.  ``u(L)`` and ``sigma(L)``
are summed with the quasi-static correction (the static response to ``F(t)`` in closed form plus the modal
remainder, which decays like ``j^-3``), so the switches converge fast in ``K``.  Events are found on a time grid by
sign changes and local extrema, then by Brent's method on the closed form.

The energy accounts are closed-form integrals of the exponentials: work of the load, Rayleigh dissipation,
``int v^T M v dt`` (for ``xi_omega``), the energy of the bar and end mass.  At each switch the truncation changes
the energy by a small amount beside the impact loss (``transfer``), which tends to 0 with ``K``: it measures the
truncation, and the balance ``work = losses + dissipation + transfer + Delta E`` closes to round-off.

This is the reference of the damped rows of the refinement table (``tests/bench/refinement_vs_continuum.py``);
without damping it converges (slowly, the fronts are kept) to the characteristics of :func:`~.simulate`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..errors import InputError
from .bar import ContinuumBar
from .modes import Segment, closed_modes, energy, open_modes, overlap, state

__all__ = ["ModalRun", "simulate_modal", "OPENING", "IMPACT"]

OPENING, IMPACT = 1, 2


@dataclass(frozen=True)
class ModalRun:
    """What :func:`simulate_modal` recorded, per forcing period (``P = periods``).

    Attributes
    ----------
    impacts, openings : ndarray of int, shape (P,)
    loss, work, dissipation, transfer, v2, psi : ndarray, shape (P,)
        Impact loss ``m_e v_L^2 / 2`` (Eq. (14)), work of the load, Rayleigh dissipation, the truncation's energy
        change at the switches, ``int v^T M v dt`` and ``sum_j omega_j int qdot_j^2 dt`` over the segments of each
        state (Eqs. (20), (22)).
    energy : ndarray, shape (P + 1,)
        Bar and end-mass energy at the period boundaries.
    events : dict of ndarray
        ``time``, ``kind`` (1 opening, 2 impact), ``v`` (impact velocity), ``loss``.
    kept_until : float
        :meth:`contact` answers up to this time.
    """

    bar: ContinuumBar
    T: float
    phi: float
    rayleigh: tuple
    modes: int
    periods: int
    impacts: np.ndarray
    openings: np.ndarray
    loss: np.ndarray
    work: np.ndarray
    dissipation: np.ndarray
    transfer: np.ndarray
    v2: np.ndarray
    psi: np.ndarray
    energy: np.ndarray
    events: dict
    elapsed: float
    kept_until: float
    segments: tuple = field(default=(), repr=False)

    @property
    def omega(self) -> float:
        return 2 * math.pi / self.T

    @property
    def energy_residual(self) -> float:
        """``(work - losses - dissipation - transfer - Delta E) / work`` (round-off: the accounts are exact)."""
        W = float(self.work.sum())
        out = self.loss.sum() + self.dissipation.sum() + self.transfer.sum() + self.energy[-1] - self.energy[0]
        return float((W - out) / W)

    def xi_omega(self, last: int | None = None) -> float:
        """``mean loss / (2 omega mean int v^T M v dt)`` over the ``last`` periods (default all)."""
        n = self.periods if last is None else last
        return float(self.loss[-n:].mean() / (2 * self.omega * self.v2[-n:].mean()))

    def xi_eq(self, last: int | None = None) -> float:
        """``mean loss / (2 mean sum_j omega_j int qdot_j^2 dt)`` over the ``last`` periods (Eq. (22) for any motion:
        finite here, the damping smooths the jump an impact leaves, so the modes' sum converges like ``K^-2``)."""
        n = self.periods if last is None else last
        return float(self.loss[-n:].mean() / (2 * self.psi[-n:].mean()))

    def contact(self, t) -> np.ndarray:
        """``u(L)`` at the times ``t`` (up to :attr:`kept_until`; 0 while closed)."""
        t = np.atleast_1d(np.asarray(t, float))
        if t.size and t.max() > self.kept_until:
            raise InputError(f"u(L) is kept up to t = {self.kept_until:g}; asked for t = {t.max():g}")
        starts = np.array([s.t0 for s in self.segments])
        idx = np.searchsorted(starts, t, side="right") - 1
        out = np.zeros(t.size)
        for i in np.unique(idx):
            sg = self.segments[i]
            if not sg.st.modes.closed:
                out[idx == i] = sg.switch(t[idx == i] - sg.t0)[0]
        return out


class _Books:
    """The per-period accounts and the event list of a run (filled in place)."""

    def __init__(self, periods: int, bar: ContinuumBar, max_events: int):
        self.acc = {n: np.zeros(periods) for n in ("loss", "work", "dissipation", "transfer", "v2", "psi")}
        self.counts = {IMPACT: np.zeros(periods, int), OPENING: np.zeros(periods, int)}
        self.energy = np.zeros(periods + 1)
        self.events = {"time": [], "kind": [], "v": [], "loss": []}
        self.bar, self.max_events = bar, max_events

    def segment(self, sg: Segment, tau: float, p: int):
        w, d, v2, psi = sg.accounts(tau, sg.st.modes.at_s, self.bar.q)
        self.acc["work"][p] += w
        self.acc["dissipation"][p] += d
        self.acc["v2"][p] += v2
        self.acc["psi"][p] += psi

    def event(self, p: int, t: float, kind: int, v: float, loss: float, transfer: float):
        self.acc["loss"][p] += loss
        self.acc["transfer"][p] += transfer
        self.counts[kind][p] += 1
        if self.counts[kind][p] > self.max_events:
            raise InputError(f"more than {self.max_events} switches in period {p} (an accumulation of impacts)")
        for nm, val in (("time", t), ("kind", kind), ("v", v), ("loss", loss)):
            self.events[nm].append(val)


def _bracket(sg: Segment, closed: bool, fresh: bool, span: float, dt: float, chunk: int):
    """``(lo, hi)`` around the first switch of ``sg`` within ``span``, or None: a sign change of the switch
    function on the grid, or a local extremum between grid points that reaches the threshold (a graze)."""
    n = max(1, int(math.ceil(span / dt - 1e-9)))
    taus = np.linspace(0.0, span, n + 1)
    sgn = -1.0 if closed else 1.0                  # closed: R < 0 opens; open: u(L) >= 0 is an impact
    for lo in range(0, n, chunk):
        tt = taus[lo:min(lo + chunk, n) + 1]
        f, df = sg.switch(tt)
        bad = (f < 0) if closed else (f >= 0)
        if fresh and lo == 0:
            bad[0] = False                         # the switch just made
        i = np.flatnonzero(bad)
        cand = (tt[max(i[0] - 1, 0)], tt[i[0]]) if i.size else None
        for j in np.flatnonzero((sgn * df[:-1] > 0) & (sgn * df[1:] <= 0)):
            if cand is not None and tt[j] >= cand[0]:
                break
            d = lambda x: sg.switch(x)[1][0]  # noqa: E731
            if sgn * d(tt[j]) <= 0 or sgn * d(tt[j + 1]) > 0:
                continue                           # the turn was round-off of a zero derivative
            tm = brentq(d, tt[j], tt[j + 1], xtol=1e-15)
            if sgn * sg.switch(tm)[0][0] >= 0:
                cand = (tt[j], tm)
                break
        if cand is not None:
            return cand
    return None


def _locate(sg: Segment, lo: float, hi: float) -> float:
    g = lambda x: sg.switch(x)[0][0]  # noqa: E731
    if (g(lo) >= 0) == (g(hi) >= 0):               # a zero exactly at the start of a fresh segment
        return hi
    return brentq(g, lo, hi, xtol=1e-15, rtol=1e-15)


def _switch(books: _Books, sg: Segment, tau: float, p: int, P: np.ndarray, after) -> tuple:
    """Apply the switch at ``sg.t0 + tau``: the impact (end mass stopped, ``P q``) or the opening (``P^T q``)."""
    q, v = sg.modal(tau)
    E0 = energy(sg.st.modes, q, v)
    if sg.st.modes.closed:
        q, v, vL, loss, kind = P.T @ q, P.T @ v, 0.0, 0.0, OPENING
    else:
        vL = sg.end_velocity(tau)
        loss = 0.5 * books.bar.end_mass * vL * vL
        q, v, kind = P @ q, P @ v, IMPACT
    books.event(p, sg.t0 + tau, kind, vL, loss, E0 - energy(after.modes, q, v) - loss)
    return q, v


def _checked(T, periods, rayleigh, modes) -> tuple[float, float]:
    if not (isinstance(periods, (int, np.integer)) and periods >= 1):
        raise InputError(f"periods = {periods!r} must be an integer >= 1")
    if not (isinstance(modes, (int, np.integer)) and modes >= 2):
        raise InputError(f"modes = {modes!r} must be an integer >= 2")
    if not (math.isfinite(T) and T > 0):
        raise InputError(f"forcing period T = {T!r} must be finite and > 0")
    try:
        a, b = (float(v) for v in rayleigh)
    except (TypeError, ValueError):
        raise InputError(f"rayleigh = {rayleigh!r} must be a pair (alpha, beta)") from None
    if not (a >= 0 and b >= 0 and math.isfinite(a + b)):
        raise InputError(f"rayleigh = {rayleigh!r} must be two finite numbers >= 0")
    return a, b


def simulate_modal(bar: ContinuumBar, T: float, periods: int = 20, rayleigh=(0.0, 0.0), modes: int = 1024,
                   phi: float = 0.0, steps_per_period: int = 400, keep: int = 20, chunk: int = 128,
                   max_events: int = 1000) -> ModalRun:
    """March the bar from rest against the wall under ``q cos(2 pi t / T - phi)`` by modal superposition.

    Parameters
    ----------
    bar : ContinuumBar
    T, periods : float, int
        Forcing period and periods to run.
    rayleigh : (float, float)
        ``(alpha, beta)`` of ``C = alpha M + beta K`` (``plbar.rayleigh_from_ratio``).
    modes : int
        Modes ``K`` kept in each contact state (1,024: the first 20 periods agree with 2,048 to 2e-4 in ``u(L)``).
    phi : float
        Phase of the load.
    steps_per_period : int
        The grid on which switches are looked for (sign changes and local extrema of the switch function).
    keep, chunk : int
        Periods whose segments are kept for :meth:`ModalRun.contact`; grid points evaluated at once.
    max_events : int
        Largest number of switches of one kind in one period (an accumulation is refused).

    Returns
    -------
    ModalRun
    """
    a, b = _checked(T, periods, rayleigh, modes)
    t_start = time.perf_counter()
    omega = 2 * math.pi / T
    mc, mo = closed_modes(bar, modes, (a, b)), open_modes(bar, modes, (a, b))
    P = overlap(bar, mc, mo)
    states = {True: state(bar, mc, omega, (a, b)), False: state(bar, mo, omega, (a, b))}
    books = _Books(periods, bar, max_events)
    closed, fresh, p = True, True, 0
    sg = Segment(states[True], 0.0, np.zeros(modes), np.zeros(modes), omega, phi)
    kept = [sg]
    while True:
        t_bound = (p + 1) * T
        hit = _bracket(sg, closed, fresh, t_bound - sg.t0, T / steps_per_period, chunk)
        tau = t_bound - sg.t0 if hit is None else _locate(sg, *hit)
        books.segment(sg, tau, p)
        if hit is None:                            # a period boundary: re-reference the segment
            q, v = sg.modal(tau)
            p += 1
            books.energy[p] = energy(sg.st.modes, q, v)
            if p == periods:
                break
            fresh = False
        else:
            closed = not closed
            q, v = _switch(books, sg, tau, p, P, states[closed])
            fresh = True
        sg = Segment(states[closed], sg.t0 + tau, q, v, omega, phi)
        if p < keep:
            kept.append(sg)
    ev = {k: np.array(v) for k, v in books.events.items()}
    return ModalRun(bar, float(T), float(phi), (a, b), int(modes), int(periods), books.counts[IMPACT],
                    books.counts[OPENING], *(books.acc[n] for n in ("loss", "work", "dissipation", "transfer", "v2", "psi")),
                    books.energy, ev, time.perf_counter() - t_start, min(keep, periods) * T, tuple(kept))
