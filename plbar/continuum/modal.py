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

__all__ = ["Modes", "closed_modes", "open_modes", "overlap", "ModalRun", "simulate_modal"]

OPENING, IMPACT = 1, 2


@dataclass(frozen=True)
class Modes:
    """A contact state's first ``K`` modes (mass-normalised), their damping and the values the switches need.

    Attributes
    ----------
    k, norm : ndarray, shape (K,)
        ``phi_j(x) = sin(k_j x) / norm_j``.
    omega, damping : ndarray
        ``omega_j = c k_j`` and ``c_j = alpha + beta omega_j^2``.
    at_s, at_L, slope_L : ndarray
        ``phi_j(s)``, ``phi_j(L)``, ``phi_j'(L)``.
    closed : bool
    """

    k: np.ndarray
    norm: np.ndarray
    omega: np.ndarray
    damping: np.ndarray
    at_s: np.ndarray
    at_L: np.ndarray
    slope_L: np.ndarray
    closed: bool

    def shapes(self, x) -> np.ndarray:
        """``phi_j(x)``, shape (len(x), K)."""
        x = np.atleast_1d(np.asarray(x, float))
        return np.sin(np.outer(x, self.k)) / self.norm


def _modes(bar: ContinuumBar, k: np.ndarray, norm: np.ndarray, rayleigh, closed: bool) -> Modes:
    a, b = rayleigh
    w = bar.c * k
    return Modes(k, norm, w, a + b * w * w, np.sin(k * bar.s) / norm, np.sin(k * bar.L) / norm,
                 k * np.cos(k * bar.L) / norm, closed)


def closed_modes(bar: ContinuumBar, K: int, rayleigh=(0.0, 0.0)) -> Modes:
    """The clamped-clamped bar: ``k_j = j pi / L``, ``norm^2 = rhoA L / 2``."""
    k = np.arange(1, K + 1) * math.pi / bar.L
    return _modes(bar, k, np.full(K, math.sqrt(bar.rhoA * bar.L / 2)), rayleigh, True)


def open_modes(bar: ContinuumBar, K: int, rayleigh=(0.0, 0.0)) -> Modes:
    """The clamped bar with its free end mass: ``cos z = r z sin z`` (``r = m_e / rhoA L``), one root ``z_j`` in
    ``((j - 1) pi, (j - 1/2) pi)``; ``norm^2 = rhoA (L/2 - sin 2kL / 4k) + m_e sin^2 kL``."""
    r = bar.end_mass / (bar.rhoA * bar.L)
    if r == 0:
        z = (np.arange(1, K + 1) - 0.5) * math.pi
    else:
        z = np.array([brentq(lambda z: math.cos(z) - r * z * math.sin(z), (j - 1) * math.pi, (j - 0.5) * math.pi,
                             xtol=1e-15, rtol=1e-15) for j in range(1, K + 1)])
    k = z / bar.L
    n2 = bar.rhoA * (bar.L / 2 - np.sin(2 * z) / (4 * k)) + bar.end_mass * np.sin(z) ** 2
    return _modes(bar, k, np.sqrt(n2), rayleigh, False)


def overlap(bar: ContinuumBar, closed: Modes, opened: Modes) -> np.ndarray:
    """``P[i, j] = int_0^L rhoA phi_i^closed phi_j^open dx`` in closed form, shape (K_closed, K_open)."""
    a, b, L = closed.k[:, None], opened.k[None, :], bar.L
    integral = 0.5 * (np.sin((a - b) * L) / (a - b) - np.sin((a + b) * L) / (a + b))
    return bar.rhoA * integral / np.outer(closed.norm, opened.norm)


def _expint(mu, tau):
    """``int_0^tau exp(mu t) dt`` for complex ``mu`` (arrays), accurate for small ``|mu tau|``."""
    z = mu * tau
    small = np.abs(z) < 1e-3
    zs = np.where(small, z, 0)
    series = tau * (1 + zs / 2 + zs * zs / 6 + zs ** 3 / 24 + zs ** 4 / 120)
    safe = np.where(small, 1.0, mu)
    return np.where(small, series, (np.exp(np.where(small, 0, z)) - 1) / safe)


@dataclass
class _State:
    """One contact state's constants for the run: modes, particular amplitudes, the switch function's parts."""

    modes: Modes
    A: np.ndarray          #: particular amplitudes, q_p = Re(A e^{i theta})
    lam: np.ndarray        #: (2, K) roots lambda+-
    gam2: np.ndarray       #: 2 gamma
    coef_f: np.ndarray     #: (2, K) per-root weight of the switch function (u_L or R) on alpha+-
    amp_f: complex         #: the switch function's harmonic part, Re(amp_f e^{i theta}) (+ correction)
    coef_v: np.ndarray     #: weights for v_L (open) on alpha+-


def _state(bar: ContinuumBar, m: Modes, omega: float, rayleigh) -> _State:
    a, b = rayleigh
    q = bar.q
    cj, wj = m.damping, m.omega
    A = m.at_s * q / (wj * wj - omega * omega + 1j * omega * cj)
    gam = np.sqrt((cj * cj / 4 - wj * wj).astype(complex))
    if np.any(np.abs(gam) < 1e-7 * wj):
        raise InputError("a mode is critically damped to 1e-7; the modal solution's closed form does not apply "
                         "(change the Rayleigh coefficients slightly)")
    lam = np.vstack([-cj / 2 + gam, -cj / 2 - gam])
    static = m.at_s * q / (wj * wj)
    if m.closed:
        # R = -sigma(L) (+ F at s = L); sigma = EA [F G_c'(L) + sum (p_j - phi_j(s) F / w_j^2) phi_j'(L)], p = q + b qdot
        Gc = -bar.s / (bar.EA * bar.L) if not bar.at_end else 0.0
        amp = -bar.EA * (q * Gc + np.sum(((1 + 1j * omega * b) * A - static) * m.slope_L)) + (q if bar.at_end else 0)
        coef = -bar.EA * (1 + b * lam) * m.slope_L
        coef_v = np.zeros_like(lam)
    else:
        Go = bar.s / bar.EA
        amp = q * Go + np.sum((A - static) * m.at_L)
        coef = np.broadcast_to(m.at_L, lam.shape).astype(complex)
        coef_v = lam * m.at_L
    return _State(m, A, lam, 2 * gam, coef, complex(amp), coef_v)


class _Segment:
    """The closed-form motion from ``t0`` in one state: ``q_j = Re(A_j e^{i theta}) + alpha+ e^{l+ tau} + alpha- e^{l- tau}``."""

    __slots__ = ("st", "t0", "theta0", "al", "omega")

    def __init__(self, st: _State, t0: float, q0: np.ndarray, v0: np.ndarray, omega: float, phi: float):
        self.st, self.t0, self.omega = st, t0, omega
        self.theta0 = omega * t0 - phi
        e = np.exp(1j * self.theta0)
        h0 = q0 - (st.A * e).real
        hd0 = v0 - (1j * omega * st.A * e).real
        lp, lm = st.lam
        self.al = np.vstack([(hd0 - lm * h0) / st.gam2, (lp * h0 - hd0) / st.gam2])

    def modal(self, tau: float) -> tuple[np.ndarray, np.ndarray]:
        """``q, qdot`` at ``t0 + tau``."""
        st = self.st
        E = self.al * np.exp(st.lam * tau)
        e = st.A * np.exp(1j * (self.theta0 + self.omega * tau))
        return (e + E.sum(0)).real, (1j * self.omega * e + (st.lam * E).sum(0)).real

    def switch(self, tau) -> tuple[np.ndarray, np.ndarray]:
        """The switch function (``u(L)`` open, ``R`` closed) and its time derivative at ``t0 + tau`` (array)."""
        st = self.st
        tau = np.atleast_1d(np.asarray(tau, float))
        w = self.al * st.coef_f                                  # (2, K)
        harm = st.amp_f * np.exp(1j * (self.theta0 + self.omega * tau))
        # the terms that have decayed below round-off of the largest one by the first time asked are left out
        size = np.abs(w) * np.exp(st.lam.real * tau[0])
        keep = size > 1e-17 * max(size.max(), abs(st.amp_f))
        f, df = harm.real, (1j * self.omega * harm).real
        for r in (0, 1):
            sel = keep[r]
            if sel.any():
                E = np.exp(np.outer(tau, st.lam[r, sel]))
                f += (E @ w[r, sel]).real
                df += (E @ (w[r, sel] * st.lam[r, sel])).real
        return f, df

    def end_velocity(self, tau: float) -> float:
        """``v(L)`` with the quasi-static correction (open state)."""
        st = self.st
        harm = 1j * self.omega * st.amp_f * np.exp(1j * (self.theta0 + self.omega * tau))
        return float((np.sum(self.al * st.coef_v * np.exp(st.lam * tau)) + harm).real)

    def accounts(self, tau: float, phi_s: np.ndarray, q: float) -> tuple[float, float, float]:
        """``int F v(s) dt``, ``sum_j c_j int qdot_j^2 dt`` and ``sum_j int qdot_j^2 dt`` over ``[t0, t0 + tau]``."""
        st = self.st
        e0 = np.exp(1j * self.theta0)
        # qdot_j = sum_m d_m exp(mu_m t'), t' in [0, tau]
        d = np.vstack([0.5j * self.omega * st.A * e0, np.conj(0.5j * self.omega * st.A * e0),
                       self.al[0] * st.lam[0], self.al[1] * st.lam[1]])
        K = st.A.size
        mu = np.vstack([np.full(K, 1j * self.omega), np.full(K, -1j * self.omega), st.lam[0], st.lam[1]])
        sq = np.zeros(K)
        for i in range(4):
            for j in range(4):
                sq += (d[i] * d[j] * _expint(mu[i] + mu[j], tau)).real
        fq = 0.5 * q * e0
        wk = np.zeros(K)
        for fc, fm in ((fq, 1j * self.omega), (np.conj(fq), -1j * self.omega)):
            for i in range(4):
                wk += (fc * d[i] * _expint(fm + mu[i], tau)).real
        return float(np.sum(phi_s * wk)), float(np.sum(st.modes.damping * sq)), float(sq.sum())


def _energy(m: Modes, q, v) -> float:
    return 0.5 * float(np.sum(v * v + (m.omega * q) ** 2))


@dataclass(frozen=True)
class ModalRun:
    """What :func:`simulate_modal` recorded, per forcing period (``P = periods``).

    Attributes
    ----------
    impacts, openings : ndarray of int, shape (P,)
    loss, work, dissipation, transfer, v2 : ndarray, shape (P,)
        Impact loss ``m_e v_L^2 / 2`` (Eq. (14)), work of the load, Rayleigh dissipation, the truncation's energy
        change at the switches, ``int v^T M v dt``.
    energy : ndarray, shape (P + 1,)
        Bar and end-mass energy at the period boundaries.
    events : dict of ndarray
        ``time``, ``kind`` (1 opening, 2 impact), ``v`` (impact velocity), ``loss``.
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
    energy: np.ndarray
    events: dict
    elapsed: float
    _segments: list = field(default_factory=list, repr=False)

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

    def contact(self, t) -> np.ndarray:
        """``u(L)`` at the times ``t`` (within the kept periods; 0 while closed)."""
        t = np.atleast_1d(np.asarray(t, float))
        starts = np.array([s.t0 for s in self._segments])
        if t.size and t.max() > self._kept_until:
            raise InputError(f"u(L) is kept up to t = {self._kept_until:g}; asked for t = {t.max():g}")
        idx = np.searchsorted(starts, t, side="right") - 1
        out = np.zeros(t.size)
        for i in np.unique(idx):
            sg = self._segments[i]
            sel = idx == i
            if not sg.st.modes.closed:
                out[sel] = sg.switch(t[sel] - sg.t0)[0]
        return out

    @property
    def _kept_until(self) -> float:
        return self.__dict__.get("kept_until", 0.0)


def simulate_modal(bar: ContinuumBar, T: float, periods: int = 20, rayleigh=(0.0, 0.0), modes: int = 256,
                   phi: float = 0.0, steps_per_period: int = 400, keep: int = 20, chunk: int = 128,
                   max_events: int = 1000) -> ModalRun:
    """March the bar from rest against the wall under ``q cos(2 pi t / T - phi)`` by modal superposition.

    Parameters
    ----------
    bar : ContinuumBar
    T : float
        Forcing period.
    periods : int
    rayleigh : (float, float)
        ``(alpha, beta)`` of ``C = alpha M + beta K`` (``plbar.rayleigh_from_ratio``).
    modes : int
        Modes ``K`` kept in each contact state.
    phi : float
    steps_per_period : int
        The grid on which switches are looked for (sign changes and local extrema of the switch function).
    keep : int
        Periods whose segments are kept for :meth:`ModalRun.contact`.
    max_events : int
        Largest number of switches in one period (a chattering accumulation is refused).

    Returns
    -------
    ModalRun
    """
    if not (isinstance(periods, (int, np.integer)) and periods >= 1):
        raise InputError(f"periods = {periods!r} must be an integer >= 1")
    if not (isinstance(modes, (int, np.integer)) and modes >= 2):
        raise InputError(f"modes = {modes!r} must be an integer >= 2")
    if not (math.isfinite(T) and T > 0):
        raise InputError(f"forcing period T = {T!r} must be finite and > 0")
    a, b = (float(v) for v in rayleigh)
    if not (a >= 0 and b >= 0):
        raise InputError(f"rayleigh = {rayleigh!r} must be two numbers >= 0")
    t_start = time.perf_counter()
    omega = 2 * math.pi / T
    mc, mo = closed_modes(bar, modes, (a, b)), open_modes(bar, modes, (a, b))
    P = overlap(bar, mc, mo)
    states = {True: _state(bar, mc, omega, (a, b)), False: _state(bar, mo, omega, (a, b))}
    dt = T / steps_per_period
    K = modes
    q0, v0 = np.zeros(K), np.zeros(K)
    closed = True
    seg = _Segment(states[closed], 0.0, q0, v0, omega, phi)
    kept, ev = [seg], {"time": [], "kind": [], "v": [], "loss": []}
    acc = {n: np.zeros(periods) for n in ("loss", "work", "dissipation", "transfer", "v2")}
    counts = {IMPACT: np.zeros(periods, int), OPENING: np.zeros(periods, int)}
    energy = np.zeros(periods + 1)
    t_end = periods * T
    p = 0                                  # current period
    fresh = True                           # the segment starts at a switch (skip tau = 0)

    def book(sg: _Segment, tau: float):
        w, d, v2 = sg.accounts(tau, sg.st.modes.at_s, bar.q)
        acc["work"][p] += w
        acc["dissipation"][p] += d
        acc["v2"][p] += v2

    while True:
        t_bound = min((p + 1) * T, t_end)
        # look for the next switch on the grid up to the period boundary
        n_steps = max(1, int(math.ceil((t_bound - seg.t0) / dt - 1e-9)))
        taus = np.linspace(0.0, t_bound - seg.t0, n_steps + 1)
        hit = None
        for lo in range(0, n_steps, chunk):
            tt = taus[lo:min(lo + chunk, n_steps) + 1]
            f, df = seg.switch(tt)
            bad = (f >= 0) if not closed else (f < 0)
            if fresh and lo == 0:
                bad[0] = False
            i = np.flatnonzero(bad)
            # a graze between samples: the switch function comes back towards its threshold inside a step
            sgn = 1.0 if not closed else -1.0
            turn = np.flatnonzero((sgn * df[:-1] > 0) & (sgn * df[1:] <= 0))
            cand = None
            if i.size:
                cand = (tt[max(i[0] - 1, 0)], tt[i[0]])
            for j in turn:
                if cand is not None and tt[j] >= cand[0]:
                    break
                tm = brentq(lambda x: seg.switch(x)[1][0], tt[j], tt[j + 1], xtol=1e-15)
                if sgn * seg.switch(tm)[0][0] >= 0:
                    cand = (tt[j], tm)
                    break
            if cand is not None:
                hit = cand
                break
        if hit is None:
            # period boundary: book, re-reference
            tau = t_bound - seg.t0
            book(seg, tau)
            q0, v0 = seg.modal(tau)
            energy[p + 1] = _energy(seg.st.modes, q0, v0)
            p += 1
            if p == periods:
                break
            seg = _Segment(states[closed], t_bound, q0, v0, omega, phi)
            fresh = False
            if p < keep:
                kept.append(seg)
            continue
        lo_t, hi_t = hit
        g = lambda x: seg.switch(x)[0][0]
        f_lo = g(lo_t)
        if (f_lo >= 0) == (g(hi_t) >= 0):     # exact zero at the start of a fresh segment
            tau = hi_t
        else:
            tau = brentq(g, lo_t, hi_t, xtol=1e-15, rtol=1e-15)
        book(seg, tau)
        q, v = seg.modal(tau)
        E_before = _energy(seg.st.modes, q, v)
        t_ev = seg.t0 + tau
        if closed:                                           # opening
            q, v = P.T @ q, P.T @ v
            vL, loss, kind = 0.0, 0.0, OPENING
        else:                                                # plastic impact
            vL = seg.end_velocity(tau)
            loss = 0.5 * bar.end_mass * vL * vL
            q, v = P @ q, P @ v
            kind = IMPACT
        closed = not closed
        E_after = _energy(states[closed].modes, q, v)
        acc["loss"][p] += loss
        acc["transfer"][p] += E_before - E_after - loss
        counts[kind][p] += 1
        if counts[kind][p] > max_events:
            raise InputError(f"more than {max_events} switches in period {p} (an accumulation of impacts)")
        for nm, val in (("time", t_ev), ("kind", kind), ("v", vL), ("loss", loss)):
            ev[nm].append(val)
        seg = _Segment(states[closed], t_ev, q, v, omega, phi)
        fresh = True
        if p < keep:
            kept.append(seg)
    run = ModalRun(bar, float(T), float(phi), (a, b), K, int(periods), counts[IMPACT], counts[OPENING],
                   acc["loss"], acc["work"], acc["dissipation"], acc["transfer"], acc["v2"], energy,
                   {k: np.array(v) for k, v in ev.items()}, time.perf_counter() - t_start, kept)
    object.__setattr__(run, "kept_until", min(keep, periods) * T)
    return run
