"""The end ``x = L`` over one piece of a step, in closed form (pure functions).

On a piece ``t in [ta, ta + h]`` the incoming invariant is ``w_in = l0 + l1 tau + C cos(omega t) + D sin(omega t)``
(``tau = t - ta``) and the end obeys ``m v' = -Z v + g(t)``, ``g = Z w_in + F_L`` (``F_L`` the load if it acts on
the end), ``u' = v`` while free; ``u = v = 0`` and the wall force ``r = -g <= 0`` while stuck (FORMULATION §3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

__all__ = ["Piece", "free", "opening", "impact", "lowest", "stored_line", "SAMPLES"]

#: samples per piece for the sign and extremum scans of the event search
SAMPLES = 8


@dataclass(frozen=True)
class Piece:
    """The closed-form free motion on a piece: ``v = l0p + l1p tau + a cos + b sin + K exp(-lam tau)``."""

    ta: float
    w: float
    l0p: float
    l1p: float
    a: float
    b: float
    K: float
    lam: float
    u0: float

    def v(self, tau):
        t = self.ta + tau
        e = self.K * np.exp(-self.lam * tau) if self.lam else 0.0
        return self.l0p + self.l1p * tau + self.a * np.cos(self.w * t) + self.b * np.sin(self.w * t) + e

    def u(self, tau):
        t, ta, w = self.ta + tau, self.ta, self.w
        e = -self.K * np.expm1(-self.lam * tau) / self.lam if self.lam else 0.0
        half = 2 * np.sin(0.5 * w * tau) / w  # sin wt - sin wta = half w cos(w (t + ta) / 2), no cancellation
        mid = 0.5 * w * (t + ta)
        return (self.u0 + self.l0p * tau + 0.5 * self.l1p * tau ** 2 + half * (self.a * np.cos(mid)
                + self.b * np.sin(mid)) + e)

    def tol(self, h: float) -> float:
        """Round-off of ``u`` on a piece of length ``h`` (its terms' size times a few ulps)."""
        return 64 * np.finfo(float).eps * (abs(self.u0) + (abs(self.l0p) + abs(self.K)) * h + abs(self.l1p) * h * h
                                           + (abs(self.a) + abs(self.b)) * min(h, 2 / self.w))


def free(ta, u0, v0, l0, l1, C, D, w, Z, m) -> Piece:
    """The free end from ``(u0, v0)`` at ``ta`` under ``g = Z (l0 + l1 tau) + Z (C cos + D sin)`` (``F_L`` folded into
    ``C, D``): particular linear and harmonic parts plus the homogeneous ``K exp(-Z tau / m)`` (none at ``m = 0``)."""
    p0, p1 = Z * l0, Z * l1
    l0p, l1p = p0 / Z - p1 * m / Z ** 2, p1 / Z
    A, B = Z * C, Z * D
    det = Z * Z + (m * w) ** 2
    a, b = (Z * A - m * w * B) / det, (Z * B + m * w * A) / det
    if m == 0:
        return Piece(ta, w, l0p, l1p, a, b, 0.0, 0.0, u0)
    K = v0 - l0p - a * math.cos(w * ta) - b * math.sin(w * ta)
    return Piece(ta, w, l0p, l1p, a, b, K, Z / m, u0)


def opening(g, h: float):
    """First time in ``[0, h]`` at which the stuck end's compression ``g(tau)`` turns to tension (None if never).

    Samples ``g`` at :data:`SAMPLES` points and at the minimum between them (where the samples turn up), so a
    dip below zero between samples is not missed."""
    taus = np.linspace(0.0, h, SAMPLES + 1)
    vals = g(taus)
    if vals[0] < 0:
        return 0.0
    neg = np.flatnonzero(vals < 0)
    first = None if neg.size == 0 else int(neg[0])
    d = np.diff(vals)
    for i in np.flatnonzero((d[:-1] < 0) & (d[1:] > 0)):
        if first is not None and i + 1 >= first:
            break
        tm = _argmin(g, taus[i], taus[i + 2])
        if g(tm) < 0:
            return brentq(g, taus[i], tm, xtol=1e-15, rtol=1e-15)
    if first is None:
        return None
    return brentq(g, taus[first - 1], taus[first], xtol=1e-15, rtol=1e-15)


def _argmin(f, lo, hi):
    from scipy.optimize import minimize_scalar

    return float(minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-14}).x)


def impact(p: Piece, h: float, start: float = 0.0):
    """First time in ``(start, h]`` at which the free end ``u(tau) <= 0`` returns to the wall (None if never).

    A sign change of ``u`` is bracketed on the samples; a return between samples shows as a maximum of ``u``
    (a ``+ -`` sign change of ``v``), located by root finding on ``v`` and tested."""
    tol = p.tol(h)
    f = lambda t: tol - p.u(t)  # noqa: E731 -- > 0 while free; a return is u reaching the wall within round-off
    taus = np.linspace(start, h, SAMPLES + 1)[1:]
    vals = f(taus)
    neg = np.flatnonzero(vals < 0)
    stop = int(neg[0]) if neg.size else taus.size
    vs = p.v(np.concatenate([[start], taus[:stop]]))
    for i in np.flatnonzero((vs[:-1] > 0) & (vs[1:] <= 0)):
        lo = start if i == 0 else taus[i - 1]
        tm = brentq(p.v, lo, taus[i], xtol=1e-15, rtol=1e-15)
        if f(tm) < 0:
            return brentq(f, lo, tm, xtol=1e-15, rtol=1e-15) if f(lo) >= 0 else tm
    if neg.size == 0:
        return None
    i = int(neg[0])
    lo = start if i == 0 else taus[i - 1]
    if i == 0 and f(lo) <= 0:
        # leaving the wall from rest (u = v = 0): the end first moves away if u dips below 0 before the sample
        lo = _argmin(p.u, start, taus[0])
        if f(lo) <= 0:
            return float(start)
    return brentq(f, lo, taus[i], xtol=1e-15, rtol=1e-15) if f(lo) >= 0 else float(lo)


def lowest(p: Piece, h: float) -> float:
    """Smallest ``u`` of the free end on ``[0, h]`` (samples, and the minima where ``v`` turns from - to +)."""
    taus = np.linspace(0.0, h, SAMPLES + 1)
    us, vs = p.u(taus), p.v(taus)
    low = float(us.min())
    for i in np.flatnonzero((vs[:-1] < 0) & (vs[1:] > 0)):
        low = min(low, float(p.u(brentq(p.v, taus[i], taus[i + 1], xtol=1e-15))))
    return low


_GX, _GW = np.polynomial.legendre.leggauss(8)


def stored_line(p: Piece, h: float, l0: float, l1: float, C: float, D: float) -> tuple[float, float]:
    """The linear part ``(a0, a1)`` stored for ``w_out = 2 v - w_in`` over a free piece ``[0, h]``.

    ``w_out`` is linear + harmonic except the end mass's transient ``2 K exp(-lam tau)``.  That is stored as its
    L2 projection on linear functions, scaled by ``beta = 1 + O(h^4)`` so that ``int w_out^2`` (the energy the
    wave carries, ``Z / 4`` times it) is kept exactly: the delay line then conserves energy to round-off and
    the solution stays second order."""
    lin0, lin1 = 2 * p.l0p - l0, 2 * p.l1p - l1
    if not p.lam or p.K == 0.0 or h <= 0:
        return lin0, lin0 + lin1 * h
    tau = 0.5 * h * (_GX + 1)
    wt = 0.5 * h * _GW
    t = p.ta + tau
    base = lin0 + lin1 * tau + (2 * p.a - C) * np.cos(p.w * t) + (2 * p.b - D) * np.sin(p.w * t)
    r = 2 * p.K * np.exp(-p.lam * tau)
    c0, c1 = wt @ r / h, 3 * (wt @ (r * _GX)) / h
    pr = c0 + c1 * _GX
    A, B, Cq, E = wt @ base ** 2, wt @ (base * pr), wt @ pr ** 2, wt @ (base + r) ** 2
    disc = B * B - Cq * (A - E)
    beta = (-B + math.copysign(math.sqrt(disc), B + Cq)) / Cq if disc >= 0 and Cq > 0 else 1.0
    return lin0 + beta * (c0 - c1), lin0 + lin1 * h + beta * (c0 + c1)
