"""The fields of the bar rebuilt from the delay line (d'Alembert), as pure array functions.

With ``d = (L - x) / c`` and ``P = 2L/c``: ``w-(x, t) = w_out(t - d) + [x < s] F(t - (s - x)/c) / Z`` and
``w+(x, t) = w_in(t + d) - [x < s] F(t + (s - x)/c) / Z``, ``w_in(t) = -w_out(t - P) + Fterm(t) / Z``;
``v = (w+ + w-) / 2``, ``c u_x = (w- - w+) / 2``, energy density ``rhoA (w+^2 + w-^2) / 4``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = ["Line", "w_out", "load", "w_in", "invariants"]


@dataclass(frozen=True)
class Line:
    """The stored delay line and what evaluating it needs (arrays from :meth:`History.arrays`)."""

    t0: np.ndarray
    t1: np.ndarray
    a0: np.ndarray
    a1: np.ndarray
    C: np.ndarray
    D: np.ndarray
    omega: float
    phi: float
    q: float
    L: float
    c: float
    Z: float
    s: float
    from_rest: bool


_jit = njit(cache=True, error_model="numpy", nogil=True)
#: helpers inlined where called: a call passing arrays would cost reference counting on every point
_inline = njit(cache=True, error_model="numpy", nogil=True, inline="always")


@_inline
def _find(t0, x, i):
    """The piece holding ``x`` (the last ``t0 <= x``, 0 before the first), walked from piece ``i`` (sorted
    queries cost O(pieces + queries)) or by bisection where the query is far from it."""
    n = t0.size
    if x >= t0[i]:
        for _ in range(32):
            if i + 1 < n and t0[i + 1] <= x:
                i += 1
            else:
                return i
    elif i > 0:
        for _ in range(32):
            i -= 1
            if t0[i] <= x or i == 0:
                return i
    return max(np.searchsorted(t0, x, side="right") - 1, 0)


@_inline
def _wo(t0, t1, a0, a1, C, D, omega, x, i):
    """``w_out(x)`` on piece ``i``."""
    f = (x - t0[i]) / (t1[i] - t0[i])
    return a0[i] + (a1[i] - a0[i]) * f + C[i] * math.cos(omega * x) + D[i] * math.sin(omega * x)


@_jit
def _w_out(t0, t1, a0, a1, C, D, omega, t, out):
    """``out = w_out(t)`` for the flat ``t``."""
    i = 0
    for j in range(t.size):
        i = _find(t0, t[j], i)
        out[j] = _wo(t0, t1, a0, a1, C, D, omega, t[j], i)


@_inline
def _load(t, omega, phi, q, from_rest):
    return 0.0 if from_rest and t < 0 else q * math.cos(omega * t - phi)


@_jit
def _invariants(t0, t1, a0, a1, C, D, omega, phi, q, L, c, Z, s, from_rest, x, t, wp, wm):
    """``wp, wm = w+, w-`` at the flat points ``x``, times ``t`` (see :func:`invariants`)."""
    i = k = 0
    P = 2 * L / c
    for j in range(x.size):
        d = (L - x[j]) / c
        i = _find(t0, t[j] - d, i)
        wm[j] = _wo(t0, t1, a0, a1, C, D, omega, t[j] - d, i)
        ti = t[j] + d
        k = _find(t0, ti - P, k)
        w = _wo(t0, t1, a0, a1, C, D, omega, ti - P, k)
        if s < L:
            w -= (_load(ti - (L - s) / c, omega, phi, q, from_rest) - _load(ti - (L + s) / c, omega, phi, q,
                                                                             from_rest)) / Z
        wp[j] = -w
        if s < L and x[j] < s:
            e = (s - x[j]) / c
            wm[j] += _load(t[j] - e, omega, phi, q, from_rest) / Z
            wp[j] -= _load(t[j] + e, omega, phi, q, from_rest) / Z


@_inline
def _lw(t0, t1, a0, a1, i, x):
    """The linear part of ``w_out`` on piece ``i`` at ``x``."""
    return a0[i] + (a1[i] - a0[i]) * ((x - t0[i]) / (t1[i] - t0[i]))


@_inline
def _F(tau, cw, sw, cphi, sphi, q, from_rest):
    """``F(tau) = q cos(omega tau - phi)`` from ``cw, sw = cos, sin(omega tau)`` (0 before 0 from rest)."""
    return 0.0 if from_rest and tau < 0 else q * (cw * cphi + sw * sphi)


@_inline
def point(t0, t1, a0, a1, C, D, x, t, ct, st, cd, sd, i, k, L, c, Z, s, P, cP, sP, c1, s1, c2, s2, cphi, sphi, q,
          from_rest):
    """``(w+, w-)`` at ``(x, t)`` given ``ct, st = cos, sin(omega t)`` and ``cd, sd`` of ``omega d``, ``d = (L-x)/c``:
    every other harmonic by rotation (``cP, sP`` of ``omega P``; ``c1, s1``, ``c2, s2`` of ``omega (L -+ s)/c``), two
    sines per point at most.  ``i, k``: the pieces last found for ``w-`` and ``w+`` (walks), returned updated after
    ``(w+, w-)``."""
    d = (L - x) / c
    tm, tp = t - d, t + d - P
    cm, sm = ct * cd + st * sd, st * cd - ct * sd            # omega (t - d)
    cq, sq = ct * cd - st * sd, st * cd + ct * sd            # omega (t + d)
    cpp, spp = cq * cP + sq * sP, sq * cP - cq * sP          # omega (t + d - P)
    i = _find(t0, tm, i)
    k = _find(t0, tp, k)
    wm = _lw(t0, t1, a0, a1, i, tm) + C[i] * cm + D[i] * sm
    wp = -(_lw(t0, t1, a0, a1, k, tp) + C[k] * cpp + D[k] * spp)
    if s < L:
        # F(t + d - (L - s)/c) = F(t + e), e = (s - x)/c, and F(t + d - (L + s)/c)
        ca, sa = cq * c1 + sq * s1, sq * c1 - cq * s1
        cb, sb = cq * c2 + sq * s2, sq * c2 - cq * s2
        Fa = _F(t + d - (L - s) / c, ca, sa, cphi, sphi, q, from_rest)
        wp += (Fa - _F(t + d - (L + s) / c, cb, sb, cphi, sphi, q, from_rest)) / Z
        if x < s:
            # F(t - e) = F(t - d + (L - s)/c)
            ce, se = cm * c1 - sm * s1, sm * c1 + cm * s1
            wm += _F(t - d + (L - s) / c, ce, se, cphi, sphi, q, from_rest) / Z
            wp -= Fa / Z
    return wp, wm, i, k


def w_out(ln: Line, t):
    """``w_out(t)``, right-continuous at the jumps; shape of ``t``."""
    t = np.asarray(t, float)
    flat = np.ascontiguousarray(t).ravel()
    out = np.empty_like(flat)
    _w_out(ln.t0, ln.t1, ln.a0, ln.a1, ln.C, ln.D, ln.omega, flat, out)
    return out.reshape(t.shape)


def load(ln: Line, t):
    """The load ``F(t) = q cos(omega t - phi)`` (0 before ``t = 0`` from rest)."""
    t = np.asarray(t, float)
    F = ln.q * np.cos(ln.omega * t - ln.phi)
    return np.where(t >= 0, F, 0.0) if ln.from_rest else F


def w_in(ln: Line, t):
    """``w_in(t)`` at the end: the reflected ``-w_out(t - 2L/c)`` plus the load crossed twice."""
    t = np.asarray(t, float)
    out = -w_out(ln, t - 2 * ln.L / ln.c)
    if ln.s < ln.L:
        out = out + (load(ln, t - (ln.L - ln.s) / ln.c) - load(ln, t - (ln.L + ln.s) / ln.c)) / ln.Z
    return out


def invariants(ln: Line, x, t):
    """``(w+, w-)`` at points ``x`` and times ``t`` (broadcast), taking right limits at ``x = s``."""
    x, t = np.broadcast_arrays(np.asarray(x, float), np.asarray(t, float))
    xf, tf = np.ascontiguousarray(x).ravel(), np.ascontiguousarray(t).ravel()
    wp, wm = np.empty_like(xf), np.empty_like(xf)
    _invariants(ln.t0, ln.t1, ln.a0, ln.a1, ln.C, ln.D, ln.omega, ln.phi, ln.q, ln.L, ln.c, ln.Z, ln.s, ln.from_rest,
                xf, tf, wp, wm)
    return wp.reshape(x.shape), wm.reshape(x.shape)
