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

from ..errors import InputError
from ..util.options import collect
from ..util.record import Record, events
from .bar import ContinuumBar
from .modes import Segment, closed_modes, energy, open_modes, overlap, state

__all__ = ["ModalRun", "ModalOptions", "simulate_modal", "OPENING", "IMPACT"]

OPENING, IMPACT = 1, 2


@dataclass(frozen=True, kw_only=True)
class ModalRun(Record):
    """What :func:`simulate_modal` recorded, per forcing period (``P = periods``): a
    :class:`plbar.util.record.Record` of one trajectory.

    Attributes
    ----------
    T, phi : float
    status : ndarray of int, shape (1,)
        0 (an accumulation of switches raises instead).
    events : ndarray of dtype EVENT, shape (E,)
        ``time``, ``kind`` (1 opening, 2 impact), ``v`` (impact velocity), ``loss``; ``traj`` 0.
    impacts, openings : ndarray of int, shape (P,)
    loss, work, dissipation, transfer, v2, psi : ndarray, shape (P,)
        Impact loss ``m_e v_L^2 / 2`` (Eq. (14)), work of the load, Rayleigh dissipation, the truncation's energy
        change at the switches, ``int v^T M v dt`` and ``sum_j omega_j int qdot_j^2 dt`` over the segments of each
        state (Eqs. (20), (22)).
    energy : ndarray, shape (P + 1,)
        Bar and end-mass energy at the period boundaries.
    amp : ndarray, shape (P,)
        Largest ``-u(L)`` per period.
    end : ndarray, shape (P + 1, 3)
        ``u(L), v(L)`` and stuck (1) / free (0) at every period boundary.
    strobe_u, strobe_v : ndarray, shape (R + 1, n + 1)
        ``u, v`` on the grid ``x_j = j L / n`` at the boundaries of the last ``R = record`` periods.
    record : int
        The last periods that :attr:`xi_eq`, :attr:`xi_omega` and the grid states cover.
    kept_until : float
        :meth:`contact` answers up to this time.
    """

    bar: ContinuumBar
    rayleigh: tuple
    modes: int
    periods: int
    record: int
    impacts: np.ndarray
    openings: np.ndarray
    loss: np.ndarray
    work: np.ndarray
    dissipation: np.ndarray
    transfer: np.ndarray
    v2: np.ndarray
    psi: np.ndarray
    energy: np.ndarray
    amp: np.ndarray
    end: np.ndarray
    strobe_u: np.ndarray
    strobe_v: np.ndarray
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

    @property
    def xi_omega(self) -> float:
        """``mean loss / (2 omega mean int v^T M v dt)`` over the recorded periods."""
        R = self.record
        return float(self.loss[-R:].mean() / (2 * self.omega * self.v2[-R:].mean()))

    @property
    def xi_eq(self) -> float:
        """``mean loss / (2 mean sum_j omega_j int qdot_j^2 dt)`` over the recorded periods (Eq. (22) for any motion:
        finite here, the damping smooths the jump an impact leaves, so the modes' sum converges like ``K^-2``)."""
        R = self.record
        return float(self.loss[-R:].mean() / (2 * self.psi[-R:].mean()))

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

    def __init__(self, periods: int, bar: ContinuumBar, max_events: int, record: int, grid: int):
        self.acc = {n: np.zeros(periods) for n in ("loss", "work", "dissipation", "transfer", "v2", "psi")}
        self.counts = {IMPACT: np.zeros(periods, int), OPENING: np.zeros(periods, int)}
        self.energy, self.amp = np.zeros(periods + 1), np.zeros(periods)
        self.end = np.zeros((periods + 1, 3))
        self.end[0, 2] = 1.0
        if not 1 <= record <= periods:
            raise InputError(f"record = {record} must lie in [1, periods = {periods}]")
        self.grid, self.first = np.linspace(0.0, bar.L, int(grid) + 1), periods - record
        self.strobes = [(np.zeros(self.grid.size),) * 2] if record == periods else []
        self.events = {"time": [], "kind": [], "v": [], "loss": []}
        self.bar, self.max_events = bar, max_events

    def boundary(self, sg: Segment, tau: float, p: int):
        """The state at the end of period ``p - 1``: energy, the end, the grid state if recorded."""
        q, v = sg.modal(tau)
        self.energy[p] = energy(sg.st.modes, q, v)
        if not sg.st.modes.closed:
            self.end[p] = sg.switch(tau)[0][0], sg.end_velocity(tau), 0.0
        else:
            self.end[p, 2] = 1.0
        if p >= self.first:
            self.strobes.append(sg.fields(tau, self.grid))
        return q, v

    def result(self, T, phi, rayleigh, modes, elapsed, kept_until, kept) -> ModalRun:
        ev = events(*(np.array(self.events[k]) for k in ("time", "kind", "loss")), v=np.array(self.events["v"]))
        acc = {n: self.acc[n] for n in ("loss", "work", "dissipation", "transfer", "v2", "psi")}
        return ModalRun(T=float(T), phi=float(phi), status=np.zeros(1, int), events=ev, bar=self.bar,
                        rayleigh=rayleigh, modes=int(modes), periods=self.amp.size, record=self.amp.size - self.first,
                        impacts=self.counts[IMPACT], openings=self.counts[OPENING], **acc, energy=self.energy,
                        amp=self.amp, end=self.end, strobe_u=np.array([u for u, _ in self.strobes]),
                        strobe_v=np.array([v for _, v in self.strobes]), elapsed=elapsed, kept_until=kept_until,
                        segments=kept)

    def segment(self, sg: Segment, tau: float, p: int, low: list, dt: float):
        """Book a segment ``[0, tau]`` in period ``p``: its integrals, and its end's excursion if free."""
        if not sg.st.modes.closed:
            self.amp[p] = max(self.amp[p], _lowest(sg, low, tau, dt))
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


def _bracket(sg: Segment, closed: bool, fresh: bool, span: float, dt: float, chunk: int, low: list):
    """``(lo, hi)`` around the first switch of ``sg`` within ``span``, or None: a sign change of the switch
    function on the grid, or a local extremum between grid points that reaches the threshold (a graze).
    ``low`` gets the lowest grid sample ``[f, tau]`` of the switch function on the way (the end's amplitude)."""
    from scipy.optimize import brentq  # on use: importing scipy.optimize takes 0.13 s

    n = max(1, int(math.ceil(span / dt - 1e-9)))
    taus = np.linspace(0.0, span, n + 1)
    sgn = -1.0 if closed else 1.0                  # closed: R < 0 opens; open: u(L) >= 0 is an impact
    for lo in range(0, n, chunk):
        tt = taus[lo:min(lo + chunk, n) + 1]
        f, df = sg.switch(tt)
        k = int(np.argmin(f))
        if f[k] < low[0]:
            low[:] = [float(f[k]), float(tt[k])]
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
            tm = brentq(d, tt[j], tt[j + 1], xtol=1e-14, maxiter=500)
            if sgn * sg.switch(tm)[0][0] >= 0:
                cand = (tt[j], tm)
                break
        if cand is not None:
            return cand
    return None


def _lowest(sg: Segment, low: list, tau: float, dt: float) -> float:
    """The end's largest excursion ``-u(L)`` in an open segment ``[0, tau]``, refined from the lowest grid sample
    to the turning point of ``u(L)`` (Brent's method on ``v(L)``)."""
    from scipy.optimize import brentq  # on use: importing scipy.optimize takes 0.13 s

    f0, t0 = low
    if not np.isfinite(f0):
        return 0.0
    a, b = max(t0 - dt, 0.0), min(t0 + dt, tau)
    d = lambda x: sg.switch(x)[1][0]  # noqa: E731
    if b > a and d(a) < 0 < d(b):
        t0 = brentq(d, a, b, xtol=1e-14)
        f0 = min(f0, sg.switch(t0)[0][0])
    return max(-f0, 0.0)


def _locate(sg: Segment, lo: float, hi: float) -> float:
    from scipy.optimize import brentq  # on use: importing scipy.optimize takes 0.13 s

    g = lambda x: sg.switch(x)[0][0]  # noqa: E731
    if (g(lo) >= 0) == (g(hi) >= 0):               # a zero exactly at the start of a fresh segment
        return hi
    try:
        return brentq(g, lo, hi, xtol=1e-14, rtol=1e-15, maxiter=200)
    except RuntimeError:                           # round-off noise near the root: halve the bracket instead
        glo = g(lo) >= 0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if not lo < mid < hi:
                break
            lo, hi = (mid, hi) if (g(mid) >= 0) == glo else (lo, mid)
        return hi


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


@dataclass(frozen=True)
class ModalOptions:
    """How :func:`simulate_modal` looks for the switches and what it keeps (its keyword options).

    Attributes
    ----------
    steps_per_period, chunk : int
        The grid on which switches are looked for (sign changes and local extrema of the switch function), and
        how many of its points are evaluated at once.
    max_events : int
        Largest number of switches of one kind in one period (an accumulation is refused).
    keep : int
        Periods whose segments :meth:`ModalRun.contact` keeps.
    record, grid : int
        The last periods whose boundary states are kept (default ``min(periods, 10)``), on ``grid`` steps of the bar.
    """

    steps_per_period: int = 400
    keep: int = 20
    chunk: int = 128
    max_events: int = 1000
    record: int | None = None
    grid: int = 32


def simulate_modal(bar: ContinuumBar, T: float, periods: int = 20, rayleigh=(0.0, 0.0), modes: int = 1024,
                   phi: float = 0.0, **options) -> ModalRun:
    """March the bar from rest against the wall under ``q cos(2 pi t / T - phi)`` by modal superposition.

    Parameters
    ----------
    bar : ContinuumBar
    T, periods, phi : float, int, float
        Forcing period, periods to run, phase of the load.
    rayleigh : (float, float)
        ``(alpha, beta)`` of ``C = alpha M + beta K`` (``plbar.rayleigh_from_ratio``).
    modes : int
        Modes ``K`` kept in each contact state (1,024: the first 20 periods agree with 2,048 to 2e-4 in ``u(L)``).

    Other Parameters
    ----------------
    steps_per_period, keep, chunk, max_events, record, grid
        The keyword options (:class:`ModalOptions`): the search for the switches, and what the run keeps.

    Returns
    -------
    ModalRun
    """
    opts = collect(ModalOptions, options, "simulate_modal")
    steps_per_period, keep, chunk, record = opts.steps_per_period, opts.keep, opts.chunk, opts.record
    a, b = _checked(T, periods, rayleigh, modes)
    t_start = time.perf_counter()
    omega = 2 * math.pi / T
    mc, mo = closed_modes(bar, modes, (a, b)), open_modes(bar, modes, (a, b))
    P = overlap(bar, mc, mo)
    states = {True: state(bar, mc, omega, (a, b)), False: state(bar, mo, omega, (a, b))}
    books = _Books(periods, bar, opts.max_events, min(periods, 10) if record is None else int(record), opts.grid)
    closed, fresh, p, dt = True, True, 0, T / steps_per_period
    sg = Segment(states[True], 0.0, np.zeros(modes), np.zeros(modes), omega, phi)
    kept = [sg]
    while True:
        t_bound, low = (p + 1) * T, [np.inf, 0.0]
        hit = _bracket(sg, closed, fresh, t_bound - sg.t0, dt, chunk, low)
        tau = t_bound - sg.t0 if hit is None else _locate(sg, *hit)
        books.segment(sg, tau, p, low, dt)
        if hit is None:                            # a period boundary: re-reference the segment
            p += 1
            q, v = books.boundary(sg, tau, p)
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
    return books.result(T, phi, (a, b), modes, time.perf_counter() - t_start, min(keep, periods) * T, tuple(kept))
