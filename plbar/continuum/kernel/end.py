"""The end ``x = L`` over one piece of a step, in closed form, and its events (compiled).

On a piece ``t in [ta, ta + h]`` the incoming invariant is ``w_in = l0 + l1 tau + C cos(omega t) + D sin(omega t)``
(``tau = t - ta``) and the end obeys ``m v' = -Z v + g(t)``, ``g = Z w_in + F_L`` (``F_L`` the load if it acts on
the end), ``u' = v`` while free; ``u = v = 0`` and the wall force ``r = -g <= 0`` while stuck (FORMULATION §3).
Free, ``v = l0p + l1p tau + a cos + b sin + K exp(-lam tau)``: the 9-tuple ``(ta, w, l0p, l1p, a, b, K, lam, u0)``
of :func:`free`.  Opening (``g`` turns negative) and the return to the wall (``u`` reaches 0 from below) are sign
changes on :data:`SAMPLES` points of the piece, plus the extrema between samples (a dip of ``g`` below zero; a
return of ``u`` between samples shows as a ``+ -`` change of ``v``), located by :func:`brentq` (scipy's algorithm,
to 1e-15) and, for the dips, golden-section minimisation (:func:`argmin`).
"""

from __future__ import annotations

import math

import numpy as np

from .jit import jit

__all__ = ["SAMPLES", "free", "pu", "pv", "ptol", "fval", "brentq", "argmin", "opening", "impact", "lowest",
           "stored_line", "energy_scale"]

#: samples per piece for the sign and extremum scans of the event search
SAMPLES = 8

_GX, _GW = np.polynomial.legendre.leggauss(8)
_EPS = float(np.finfo(float).eps)


@jit
def energy_scale(B, Cq, dE):
    """The root nearest 1 of ``Cq beta^2 + 2 B beta = dE`` (``int (base + beta pr)^2 = int (base + r)^2`` with
    ``B = int base pr``, ``Cq = int pr^2``, ``dE = int r (2 base + r)``), without cancellation; ``ok`` False if
    none is real."""
    disc = B * B + Cq * dE
    if not (disc >= 0 and Cq > 0):
        return False, 1.0
    qq = -(B + math.copysign(math.sqrt(disc), B))
    r1 = qq / Cq
    r2 = -dE / qq if qq != 0 else r1
    return True, r1 if abs(r1 - 1) < abs(r2 - 1) else r2


@jit
def free(gp, u0, v0, m):
    """The free end of mass ``m`` from ``(u0, v0)`` at ``ta`` under the compression of ``gp = (ta, w, l0, l1, C, D,
    Z, 0, 0)`` (:func:`fval` 0), ``g = Z (l0 + l1 tau) + Z (C cos + D sin)`` (``F_L`` folded into ``C, D``):
    ``(ta, w, l0p, l1p, a, b, K, lam, u0)``; no homogeneous part at ``m = 0``."""
    ta, w, l0, l1, C, D, Z = gp[0], gp[1], gp[2], gp[3], gp[4], gp[5], gp[6]
    p0, p1 = Z * l0, Z * l1
    l0p, l1p = p0 / Z - p1 * m / Z ** 2, p1 / Z
    A, B = Z * C, Z * D
    det = Z * Z + (m * w) ** 2
    a, b = (Z * A - m * w * B) / det, (Z * B + m * w * A) / det
    if m == 0:
        return (ta, w, l0p, l1p, a, b, 0.0, 0.0, u0)
    K = v0 - l0p - a * math.cos(w * ta) - b * math.sin(w * ta)
    return (ta, w, l0p, l1p, a, b, K, Z / m, u0)


@jit
def pv(p, tau):
    ta, w, l0p, l1p, a, b, K, lam, u0 = p
    t = ta + tau
    e = K * math.exp(-lam * tau) if lam != 0 else 0.0
    return l0p + l1p * tau + a * math.cos(w * t) + b * math.sin(w * t) + e


@jit
def pu(p, tau):
    ta, w, l0p, l1p, a, b, K, lam, u0 = p
    t = ta + tau
    e = -K * math.expm1(-lam * tau) / lam if lam != 0 else 0.0
    half = 2 * math.sin(0.5 * w * tau) / w  # sin wt - sin wta = half w cos(w (t + ta) / 2), no cancellation
    mid = 0.5 * w * (t + ta)
    return u0 + l0p * tau + 0.5 * l1p * tau ** 2 + half * (a * math.cos(mid) + b * math.sin(mid)) + e


@jit
def ptol(p, h):
    """Round-off of ``u`` on a piece of length ``h`` (its terms' size times a few ulps)."""
    ta, w, l0p, l1p, a, b, K, lam, u0 = p
    return 64 * _EPS * (abs(u0) + (abs(l0p) + abs(K)) * h + abs(l1p) * h * h + (abs(a) + abs(b)) * min(h, 2 / w))


# the functions the searches work on: 0 the compression g (p = (ta, w, l0, l1, Ct, Dt, Z, 0, 0)), 1 v, 2 tol - u, 3 u
@jit
def fval(kind, p, x, tau):
    if kind == 0:
        ta, w, l0, l1, Ct, Dt, Z = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
        return Z * (l0 + l1 * tau + Ct * math.cos(w * (ta + tau)) + Dt * math.sin(w * (ta + tau)))
    if kind == 1:
        return pv(p, tau)
    if kind == 2:
        return x - pu(p, tau)
    return pu(p, tau)


@jit
def brentq(kind, p, x, xa, xb, xtol, rtol):
    """A root of ``fval(kind, p, x, .)`` in ``[xa, xb]`` (a sign change): scipy's ``brentq`` (Brent 1973)."""
    xpre, xcur = xa, xb
    xblk = fblk = spre = scur = 0.0
    fpre, fcur = fval(kind, p, x, xpre), fval(kind, p, x, xcur)
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    for _ in range(200):
        if fpre != 0 and fcur != 0 and ((fpre < 0) != (fcur < 0)):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = 0.5 * (xtol + rtol * abs(xcur))
        sbis = 0.5 * (xblk - xcur)
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre, scur = sbis, sbis
        else:
            spre, scur = sbis, sbis
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = fval(kind, p, x, xcur)
    return xcur


@jit
def argmin(kind, p, x, lo, hi):
    """The minimum of ``fval(kind, p, x, .)`` on ``[lo, hi]`` by golden sections to 1e-14 (one dip between
    samples; the searches test its value)."""
    r = 0.5 * (3.0 - math.sqrt(5.0))
    a, b = lo, hi
    c, d = a + r * (b - a), b - r * (b - a)
    fc, fd = fval(kind, p, x, c), fval(kind, p, x, d)
    while b - a > 1e-14:
        if fc <= fd:
            b, d, fd = d, c, fc
            c = a + r * (b - a)
            fc = fval(kind, p, x, c)
        else:
            a, c, fc = c, d, fd
            d = b - r * (b - a)
            fd = fval(kind, p, x, d)
    return 0.5 * (a + b)


@jit
def opening(gp, h, taus, vals):
    """First time in ``[0, h]`` at which the stuck end's compression ``g`` turns to tension (-1 if never): samples
    and the minimum between them where the samples turn up, so a dip below zero between samples is not missed."""
    S = SAMPLES
    for i in range(S + 1):
        taus[i] = i * (h / S) if i < S else h
        vals[i] = fval(0, gp, 0.0, taus[i])
    if vals[0] < 0:
        return 0.0
    first = -1
    for i in range(S + 1):
        if vals[i] < 0:
            first = i
            break
    for i in range(S - 1):
        if vals[i + 1] - vals[i] < 0 and vals[i + 2] - vals[i + 1] > 0:
            if first >= 0 and i + 1 >= first:
                break
            tm = argmin(0, gp, 0.0, taus[i], taus[i + 2])
            if fval(0, gp, 0.0, tm) < 0:
                return brentq(0, gp, 0.0, taus[i], tm, 1e-15, 1e-15)
    if first < 0:
        return -1.0
    return brentq(0, gp, 0.0, taus[first - 1], taus[first], 1e-15, 1e-15)


@jit
def impact(p, h, taus, vals):
    """First time in ``(0, h]`` at which the free end ``u <= 0`` returns to the wall (-1 if never).  A sign change
    of ``u`` on the samples, or a return between samples: a maximum of ``u`` (``v`` from + to -) located and tested."""
    S = SAMPLES
    tol = ptol(p, h)
    first = -1
    for i in range(S):
        taus[i] = (i + 1) * (h / S) if i < S - 1 else h
        vals[i] = tol - pu(p, taus[i])
        if first < 0 and vals[i] < 0:
            first = i
    stop = first if first >= 0 else S
    vprev = pv(p, 0.0)
    for i in range(stop):
        vnext = pv(p, taus[i])
        if vprev > 0 and vnext <= 0:
            lo = 0.0 if i == 0 else taus[i - 1]
            tm = brentq(1, p, tol, lo, taus[i], 1e-15, 1e-15)
            if tol - pu(p, tm) < 0:
                return brentq(2, p, tol, lo, tm, 1e-15, 1e-15) if tol - pu(p, lo) >= 0 else tm
        vprev = vnext
    if first < 0:
        return -1.0
    i = first
    lo = 0.0 if i == 0 else taus[i - 1]
    if i == 0 and tol - pu(p, lo) <= 0:
        # leaving the wall from rest (u = v = 0): the end first moves away if u dips below 0 before the sample
        lo = argmin(3, p, tol, 0.0, taus[0])
        if tol - pu(p, lo) <= 0:
            return 0.0
    return brentq(2, p, tol, lo, taus[i], 1e-15, 1e-15) if tol - pu(p, lo) >= 0 else lo


@jit
def lowest(p, h):
    """Smallest ``u`` of the free end on ``[0, h]`` (samples, and the minima where ``v`` turns from - to +)."""
    S = SAMPLES
    low = pu(p, 0.0)
    vprev = pv(p, 0.0)
    tprev = 0.0
    for i in range(1, S + 1):
        t = i * (h / S) if i < S else h
        low = min(low, pu(p, t))
        vn = pv(p, t)
        if vprev < 0 and vn > 0:
            low = min(low, pu(p, brentq(1, p, 0.0, tprev, t, 1e-15, 4 * _EPS)))
        vprev, tprev = vn, t
    return low


@jit
def stored_line(p, h, l0, l1, C, D):
    """The linear part ``(a0, a1)`` stored for ``w_out = 2 v - w_in`` over a free piece ``[0, h]``: the transient
    ``2 K exp(-lam tau)`` as its L2 projection on linear functions, scaled by ``beta = 1 + O(h^4)`` so that
    ``int w_out^2`` (the energy the wave carries, ``Z / 4`` times it) is kept exactly."""
    ta, w, l0p, l1p, a, b, K, lam, u0 = p
    lin0, lin1 = 2 * l0p - l0, 2 * l1p - l1
    if lam == 0 or K == 0.0 or h <= 0:
        return lin0, lin0 + lin1 * h
    s0 = s1 = B0 = B1 = dE = 0.0
    for j in range(_GX.size):
        tau = 0.5 * h * (_GX[j] + 1)
        wt = 0.5 * h * _GW[j]
        t = ta + tau
        base = lin0 + lin1 * tau + (2 * a - C) * math.cos(w * t) + (2 * b - D) * math.sin(w * t)
        r = 2 * K * math.exp(-lam * tau)
        s0 += wt * r
        s1 += wt * r * _GX[j]
        B0 += wt * base
        B1 += wt * base * _GX[j]
        dE += wt * r * (2 * base + r)
    c0, c1 = s0 / h, 3 * s1 / h
    ok, beta = energy_scale(c0 * B0 + c1 * B1, h * (c0 * c0 + c1 * c1 / 3), dE)
    return lin0 + beta * (c0 - c1), lin0 + lin1 * h + beta * (c0 + c1)


