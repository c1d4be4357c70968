"""The compiled march (numba): the end's closed-form motion fed by the delay line, and the delay line's record.

One kernel, :func:`march`, does the whole march; its pieces are pure ``@njit(cache=True)`` functions of floats.

* **The end over a piece** ``t in [ta, ta + h]``: the incoming invariant is ``w_in = l0 + l1 tau + C cos(omega t) +
  D sin(omega t)`` (``tau = t - ta``) and the end obeys ``m v' = -Z v + g(t)``, ``g = Z w_in + F_L`` (``F_L`` the load
  if it acts on the end), ``u' = v`` while free; ``u = v = 0`` and the wall force ``r = -g <= 0`` while stuck
  (FORMULATION §3).  Free, ``v = l0p + l1p tau + a cos + b sin + K exp(-lam tau)`` (:func:`free`, a 9-tuple).
* **Events**: opening (``g`` turns negative) and the return to the wall (``u`` reaches 0 from below) are sign
  changes on :data:`SAMPLES` points of the piece, plus the extrema between samples (a dip of ``g`` below zero, a
  return of ``u`` between samples shows as a ``+ -`` change of ``v``), located by Brent's method (the algorithm
  of scipy's ``brentq``, to 1e-15) and, for the dips, golden-section minimisation.
* **The record** ``w_out`` per piece: linear (``a0`` at ``tau0``, ``a1`` at ``tau1``, local times of grid step
  ``k``) plus ``C cos + D sin``, and ``jump``: whether ``w_out`` jumps at the piece's start.  Stuck, ``w_out = -w_in``;
  free, ``w_out = 2 v - w_in`` whose transient ``2 K exp(-lam tau)`` is stored as its L2 projection on linear
  functions scaled to keep ``int w_out^2`` (:func:`stored_line`).
* **The merge**: when a grid step is done, its pieces between jumps (joined at period cuts, load-delay points,
  openings, the delayed pieces' kinks) are merged into one piece per jump-free run (:func:`merge_run`): the
  harmonic part is the run's length-weighted mean, the rest is projected (L2, Gauss-Legendre on every piece) on
  one linear function, scaled so that ``int w_out^2`` over the run is kept exactly.  Jumps (impacts: ``w_out``
  jumps by ``-2 v``; the load's arrival from rest; the jumps carried in by the delay line) stay breakpoints.  So a
  step holds one piece plus one per jump in it, and the delay line still conserves energy to round-off.

The arrays grow by doubling; nothing else is allocated in the loop.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["SAMPLES", "MAX_EVENTS_PER_STEP", "OPENING", "IMPACT", "march"]

#: samples per piece for the sign and extremum scans of the event search
SAMPLES = 8
#: more switches than this in one grid step is taken as chatter and stops the march
MAX_EVENTS_PER_STEP = 50
OPENING, IMPACT = 1, 2

_GX, _GW = np.polynomial.legendre.leggauss(8)
_EPS = float(np.finfo(float).eps)

jit = njit(cache=True, error_model="numpy", nogil=True)


# ----------------------------------------------------------------------------------------------- closed forms
@jit
def _beta(B, Cq, dE):
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
def free(ta, u0, v0, l0, l1, C, D, w, Z, m):
    """The free end from ``(u0, v0)`` at ``ta`` under ``g = Z (l0 + l1 tau) + Z (C cos + D sin)`` (``F_L`` folded
    into ``C, D``): ``(ta, w, l0p, l1p, a, b, K, lam, u0)``; no homogeneous part at ``m = 0``."""
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
    ok, beta = _beta(c0 * B0 + c1 * B1, h * (c0 * c0 + c1 * c1 / 3), dE)
    return lin0 + beta * (c0 - c1), lin0 + lin1 * h + beta * (c0 + c1)


# ----------------------------------------------------------------------------------------------- the record
@jit
def merge_run(hk, t0, t1, a0, a1, C, D, i0, i1, dtk, w):
    """Pieces ``i0 .. i1 - 1`` (a jump-free run of one step, times local to ``dtk = k dt``) as one piece
    ``(a0, a1, C, D)``; ``ok`` False where no energy-keeping piece exists (then they stay as they are)."""
    S0, S1 = t0[i0], t1[i1 - 1]
    H = S1 - S0
    same = True
    Cs = Ds = 0.0
    for i in range(i0, i1):
        Cs += (t1[i] - t0[i]) * C[i]
        Ds += (t1[i] - t0[i]) * D[i]
        same = same and C[i] == C[i0] and D[i] == D[i0]
    if same:
        Cs, Ds = C[i0], D[i0]
    else:
        Cs, Ds = Cs / H, Ds / H
    m0 = m1 = A = B0 = B1 = dE = 0.0
    for i in range(i0, i1):
        h = t1[i] - t0[i]
        sl = (a1[i] - a0[i]) / h
        for j in range(_GX.size):
            tau = 0.5 * h * (_GX[j] + 1)
            wt = 0.5 * h * _GW[j]
            x = 2 * (t0[i] + tau - S0) / H - 1
            t = dtk + t0[i] + tau
            cw, sw = math.cos(w * t), math.sin(w * t)
            base = Cs * cw + Ds * sw
            r = a0[i] + sl * tau + (C[i] - Cs) * cw + (D[i] - Ds) * sw
            m0 += wt * r
            m1 += wt * r * x
            A += wt * base * base
            B0 += wt * base
            B1 += wt * base * x
            dE += wt * r * (2 * base + r)
    c0, c1 = m0 / H, 3 * m1 / H
    B = c0 * B0 + c1 * B1
    Cq = H * (c0 * c0 + c1 * c1 / 3)
    ok, beta = _beta(B, Cq, dE)
    if ok:
        return True, beta * (c0 - c1), beta * (c0 + c1), Cs, Ds
    E, G = A + dE, A + 2 * B + Cq  # the whole projection scaled instead (a run whose field is nearly zero)
    if G > 0 and E >= 0:
        gam = math.sqrt(E / G)
        return True, gam * (c0 - c1), gam * (c0 + c1), gam * Cs, gam * Ds
    return E == 0, 0.0, 0.0, 0.0, 0.0


@jit
def merge_step(hk, t0, t1, a0, a1, C, D, jp, first, count, dtk, w):
    """Merge the jump-free runs of the step's pieces ``first .. count - 1`` in place; the new count."""
    out = first
    i = first
    while i < count:
        j = i + 1
        while j < count and jp[j] == 0:
            j += 1
        ok = j > i + 1
        if ok:
            ok, b0, b1, Cm, Dm = merge_run(hk, t0, t1, a0, a1, C, D, i, j, dtk, w)
        if ok:
            hk[out], t0[out], t1[out], jp[out] = hk[i], t0[i], t1[j - 1], jp[i]
            a0[out], a1[out], C[out], D[out] = b0, b1, Cm, Dm
            out += 1
        else:
            for q in range(i, j):
                hk[out], t0[out], t1[out], a0[out], a1[out] = hk[q], t0[q], t1[q], a0[q], a1[q]
                C[out], D[out], jp[out] = C[q], D[q], jp[q]
                out += 1
        i = j
    return out


@jit
def _force(d, t, omega, phi, q, from_rest):
    """``(C, D)`` of ``F(t - d) = q cos(omega (t - d) - phi)``, 0 before the load starts (rest start)."""
    if from_rest and t < d:
        return 0.0, 0.0
    x = omega * d + phi
    return q * math.cos(x), q * math.sin(x)


@jit
def _forcing(t, at_end, d1, d2, omega, phi, q, Z, from_rest):
    """``(C, D)`` of ``g``'s load part over a piece holding ``t``: ``Fterm / Z`` in ``w_in``, or ``F_L / Z``."""
    if at_end:
        c, s = _force(0.0, t, omega, phi, q, from_rest)
        return c / Z, s / Z
    c1, s1 = _force(d1, t, omega, phi, q, from_rest)
    c2, s2 = _force(d2, t, omega, phi, q, from_rest)
    return (c1 - c2) / Z, (s1 - s2) / Z


@jit
def march(L, c, Z, m, s, q, omega, phi, n, hold, from_rest, su, sv, sstuck, sC, sD, T, periods, merge):
    """The whole march from ``t = 0`` for ``periods`` of ``T`` on the grid ``dt = L / (c n)``.

    ``hold``: 0 none, 1 closed, 2 open.  Returns ``(rec, ev, strobes, amp, status, t_err)``: ``rec`` (8, pieces)
    rows ``k, tau0, tau1, a0, a1, C, D, jump``; ``ev`` (4, events) rows ``time, kind, v, loss``; ``strobes`` (3,
    periods) ``u, v, stuck`` at the period boundaries; ``amp`` (periods + 1) the largest ``-u`` per period;
    ``status`` 0, or 1 for chatter at ``t_err``."""
    dt = L / (c * n)
    nsteps = int(math.ceil(periods * T / dt - 1e-12))
    at_end = s == L
    P = 2 * L / c
    cr, sr = math.cos(omega * P), math.sin(omega * P)
    d1, d2 = (L - s) / c, (L + s) / c
    off = 2 * n
    rec = np.empty((8, 4 * (off + nsteps)))
    first = np.empty(off + nsteps + 1, np.int64)
    for i in range(off):
        rec[0, i], rec[1, i], rec[2, i], rec[3, i], rec[4, i] = i - off, 0.0, dt, 0.0, 0.0
        rec[5, i], rec[6, i], rec[7, i] = sC, sD, 0.0
        first[i] = i
    npc = off
    ev = np.empty((4, 64))
    ne = 0
    strobes = np.zeros((3, periods))
    ns = 0
    amp = np.zeros(periods + 1)
    na = 1
    u, v, stuck = su, sv, sstuck
    amp[0] = -u
    taus, vals = np.empty(SAMPLES + 1), np.empty(SAMPLES + 1)  # the event searches' scratch
    ncut = int(dt / T) + 3
    cutv = np.empty(ncut)
    pts = np.empty(ncut + 2)
    pjump = np.empty(ncut + 2)
    pcut = np.empty(ncut + 2)
    pnext = 1
    for k in range(nsteps):
        tk = k * dt
        nc = 0
        while pnext <= periods and pnext * T <= (k + 1) * dt * (1 + 1e-15):
            cutv[nc] = min(pnext * T - tk, dt)
            nc += 1
            pnext += 1
        # the step's breakpoints: the load's delay points (jumps from rest) and the period cuts, sorted
        npt = 0
        if not at_end:
            for d in (d1, d2):
                if 0 < d - tk < dt:
                    pts[npt], pjump[npt], pcut[npt] = d - tk, 1.0 if from_rest else 0.0, 0.0
                    npt += 1
        for j in range(nc):
            dup = False
            for i in range(npt):
                if pts[i] == cutv[j]:
                    pcut[i] = 1.0
                    dup = True
            if not dup:
                pts[npt], pjump[npt], pcut[npt] = cutv[j], 0.0, 1.0
                npt += 1
        for i in range(1, npt):
            j = i
            while j > 0 and pts[j - 1] > pts[j]:
                pts[j - 1], pts[j] = pts[j], pts[j - 1]
                pjump[j - 1], pjump[j] = pjump[j], pjump[j - 1]
                pcut[j - 1], pcut[j] = pcut[j], pcut[j - 1]
                j -= 1
        first[k + off] = npc
        nev = 0
        pend = 0.0
        for i in range(first[k], first[k + 1]):
            t0, t1, a0, a1 = rec[1, i], rec[2, i], rec[3, i], rec[4, i]
            Cw = rec[5, i] * cr - rec[6, i] * sr
            Dw = rec[5, i] * sr + rec[6, i] * cr
            slope = (a1 - a0) / (t1 - t0)
            pend = max(pend, rec[7, i])
            sa = t0
            ip = 0
            while ip < npt and pts[ip] <= t0:
                ip += 1
            while sa < t1:
                iscut, nxt_jump = False, 0.0
                if ip < npt and pts[ip] < t1:
                    sb = pts[ip]
                    iscut, nxt_jump = pcut[ip] != 0, pjump[ip]
                    ip += 1
                else:
                    sb = t1
                    for j in range(nc):
                        if cutv[j] == t1:
                            iscut = True
                Cf, Df = _forcing(tk + 0.5 * (sa + sb), at_end, d1, d2, omega, phi, q, Z, from_rest)
                l0, l1 = -(a0 + slope * (sa - t0)), -slope
                if at_end:
                    Ci, Di, LC, LD = -Cw, -Dw, Cf, Df
                else:
                    Ci, Di, LC, LD = Cf - Cw, Df - Dw, 0.0, 0.0
                # the end over [sa, sb], switching where the closed form says
                x = sa
                while sb > x:
                    h = sb - x
                    gp = (tk + x, omega, l0, l1, Ci + LC, Di + LD, Z, 0.0, 0.0)
                    if stuck:
                        tau = -1.0 if hold == 1 else opening(gp, h, taus, vals)
                        te = h if tau < 0 else tau
                        xe = sb if tau < 0 else x + te
                        b0, b1, Cs, Ds = -l0, -(l0 + l1 * te), -Ci, -Di
                    else:
                        p = free(tk + x, u, v, l0, l1, Ci + LC, Di + LD, omega, Z, m)
                        tau = -1.0 if hold == 2 else impact(p, h, taus, vals)
                        te = h if tau < 0 else tau
                        xe = sb if tau < 0 else x + te
                        b0, b1 = stored_line(p, te, l0, l1, Ci, Di)
                        Cs, Ds = 2 * p[4] - Ci, 2 * p[5] - Di
                        amp[na - 1] = max(amp[na - 1], -lowest(p, te))
                        u, v = pu(p, te), pv(p, te)
                    if xe > x:
                        if npc >= rec.shape[1]:
                            big = np.empty((8, 2 * rec.shape[1]))
                            big[:, :npc] = rec[:, :npc]
                            rec = big
                        rec[0, npc], rec[1, npc], rec[2, npc], rec[3, npc] = k, x, xe, b0
                        rec[4, npc], rec[5, npc], rec[6, npc], rec[7, npc] = b1, Cs, Ds, pend
                        npc += 1
                        pend = 0.0
                    if tau < 0:
                        break
                    if ne + 2 > ev.shape[1]:
                        big = np.empty((4, 2 * ev.shape[1]))
                        big[:, :ne] = ev[:, :ne]
                        ev = big
                    te_abs = tk + x + tau
                    if stuck:
                        ev[0, ne], ev[1, ne], ev[2, ne], ev[3, ne] = te_abs, OPENING, 0.0, 0.0
                        ne += 1
                        stuck, u, v = False, 0.0, 0.0
                    else:
                        ev[0, ne], ev[1, ne], ev[2, ne], ev[3, ne] = te_abs, IMPACT, v, 0.5 * m * v * v
                        ne += 1
                        u, v = 0.0, 0.0
                        pend = 1.0  # w_out jumps by -2 v
                        stuck = fval(0, gp, 0.0, tau) >= 0
                        if not stuck:
                            ev[0, ne], ev[1, ne], ev[2, ne], ev[3, ne] = te_abs, OPENING, 0.0, 0.0
                            ne += 1
                    l0 = l0 + l1 * tau
                    x += tau
                    nev += 1
                    if nev > MAX_EVENTS_PER_STEP:
                        return rec[:, :npc], ev[:, :ne], strobes, amp, 1, tk
                if iscut and ns < periods:
                    strobes[0, ns], strobes[1, ns], strobes[2, ns] = u, v, 1.0 if stuck else 0.0
                    ns += 1
                    if na <= periods:
                        amp[na] = -u
                        na += 1
                sa = sb
                pend = max(pend, nxt_jump)
        if merge:
            npc = merge_step(rec[0], rec[1], rec[2], rec[3], rec[4], rec[5], rec[6], rec[7], first[k + off], npc,
                             tk, omega)
    first[nsteps + off] = npc
    return rec[:, :npc], ev[:, :ne], strobes, amp, 0, 0.0
