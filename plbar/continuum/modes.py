"""One contact state of the damped continuum bar in exact modes (:mod:`.modal`): the modes, their overlap, the
closed-form motion of a segment between switches and its energy accounts (pure functions and small value types).

Closed (clamped-clamped): ``phi_j = sin(j pi x / L)``.  Open (clamped, free end mass ``m_e``):
``phi_j = sin(k_j x)``, ``cos z = (m_e / rhoA L) z sin z``, ``z = k_j L``.  Both mass-normalised (the open state with
the end mass), both diagonalise ``C = alpha M + beta K`` (``c_j = alpha + beta omega_j^2``).  A modal coordinate
is the harmonic particular solution ``Re(A_j e^{i theta})`` plus two exponentials ``e^{lambda+- tau}``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .bar import ContinuumBar

__all__ = ["Modes", "closed_modes", "open_modes", "overlap", "expint", "State", "state", "Segment", "energy"]


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
    from scipy.optimize import brentq  # on use: importing scipy.optimize takes 0.13 s

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


def expint(mu, tau):
    """``int_0^tau exp(mu t) dt`` for complex ``mu`` (arrays), accurate for small ``|mu tau|``."""
    z = mu * tau
    small = np.abs(z) < 1e-3
    zs = np.where(small, z, 0)
    series = tau * (1 + zs / 2 + zs * zs / 6 + zs ** 3 / 24 + zs ** 4 / 120)
    safe = np.where(small, 1.0, mu)
    return np.where(small, series, (np.exp(np.where(small, 0, z)) - 1) / safe)


@dataclass(frozen=True)
class State:
    """One contact state's constants for the run: modes, particular amplitudes, the switch function's parts."""

    bar: ContinuumBar
    modes: Modes
    A: np.ndarray          #: particular amplitudes, q_p = Re(A e^{i theta})
    lam: np.ndarray        #: (2, K) roots lambda+-
    gam2: np.ndarray       #: 2 gamma
    coef_f: np.ndarray     #: (2, K) per-root weight of the switch function (u_L or R) on alpha+-
    amp_f: complex         #: the switch function's harmonic part, Re(amp_f e^{i theta}) (+ correction)
    coef_v: np.ndarray     #: weights for v_L (open) on alpha+-


def state(bar: ContinuumBar, m: Modes, omega: float, rayleigh) -> State:
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
        # R = -sigma(L) (+ F at s = L); sigma = EA [F G_c'(L) + sum (p_j - phi_j(s) F / w_j^2) phi_j'(L)],
        # p = q + b qdot
        Gc = -bar.s / (bar.EA * bar.L) if not bar.at_end else 0.0
        amp = -bar.EA * (q * Gc + np.sum(((1 + 1j * omega * b) * A - static) * m.slope_L)) + (q if bar.at_end else 0)
        coef = -bar.EA * (1 + b * lam) * m.slope_L
        coef_v = np.zeros_like(lam)
    else:
        Go = bar.s / bar.EA
        amp = q * Go + np.sum((A - static) * m.at_L)
        coef = np.broadcast_to(m.at_L, lam.shape).astype(complex)
        coef_v = lam * m.at_L
    return State(bar, m, A, lam, 2 * gam, coef, complex(amp), coef_v)


class Segment:
    """The closed-form motion from ``t0`` in one state:
    ``q_j = Re(A_j e^{i theta}) + alpha+ e^{l+ tau} + alpha- e^{l- tau}``."""

    __slots__ = ("st", "t0", "theta0", "al", "omega")

    def __init__(self, st: State, t0: float, q0: np.ndarray, v0: np.ndarray, omega: float, phi: float):
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

    def fields(self, tau: float, x) -> tuple[np.ndarray, np.ndarray]:
        """``u(x), v(x)`` at ``t0 + tau``: the static response to ``F(t)`` (clamped-free, minus its end's linear
        part when closed) plus the modal remainder, as the switches sum it."""
        m, bar = self.st.modes, self.st.bar
        x = np.atleast_1d(np.asarray(x, float))
        q, v = self.modal(tau)
        th = self.theta0 + self.omega * tau
        F, dF = bar.q * math.cos(th), -bar.q * self.omega * math.sin(th)
        G = np.minimum(x, bar.s) / bar.EA - (x * bar.s / (bar.EA * bar.L) if m.closed else 0.0)
        Phi, stat = m.shapes(x), m.at_s / m.omega ** 2
        return F * G + Phi @ (q - stat * F), dF * G + Phi @ (v - stat * dF)

    def end_velocity(self, tau: float) -> float:
        """``v(L)`` with the quasi-static correction (open state)."""
        st = self.st
        harm = 1j * self.omega * st.amp_f * np.exp(1j * (self.theta0 + self.omega * tau))
        return float((np.sum(self.al * st.coef_v * np.exp(st.lam * tau)) + harm).real)

    def accounts(self, tau: float, phi_s: np.ndarray, q: float) -> tuple[float, float, float, float]:
        """``int F v(s) dt``, ``sum_j c_j int qdot_j^2 dt``, ``sum_j int qdot_j^2 dt`` and
        ``sum_j omega_j int qdot_j^2 dt`` (Eq. (22)'s denominator, Eq. (20)) over ``[t0, t0 + tau]``."""
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
                sq += (d[i] * d[j] * expint(mu[i] + mu[j], tau)).real
        fq = 0.5 * q * e0
        wk = np.zeros(K)
        for fc, fm in ((fq, 1j * self.omega), (np.conj(fq), -1j * self.omega)):
            for i in range(4):
                wk += (fc * d[i] * expint(fm + mu[i], tau)).real
        m = st.modes
        return float(np.sum(phi_s * wk)), float(np.sum(m.damping * sq)), float(sq.sum()), float(np.sum(m.omega * sq))


def energy(m: Modes, q, v) -> float:
    return 0.5 * float(np.sum(v * v + (m.omega * q) ** 2))
