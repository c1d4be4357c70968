"""The fields from the delay line at points, compiled: the piece holding a time, ``w_out``, ``(w+, w-)``.

See :mod:`plbar.continuum.fields` for the formulas (d'Alembert with the clamp's reflection and the load crossed).
"""

from __future__ import annotations

import math

import numpy as np

from .jit import cached, inline

__all__ = ["find", "wo", "w_out_into", "load_at", "invariants_into", "lin", "force_at", "point"]




@inline
def find(t0, x, i):
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


@inline
def wo(t0, t1, a0, a1, C, D, omega, x, i):
    """``w_out(x)`` on piece ``i``."""
    f = (x - t0[i]) / (t1[i] - t0[i])
    return a0[i] + (a1[i] - a0[i]) * f + C[i] * math.cos(omega * x) + D[i] * math.sin(omega * x)


def _w_out_into(stamp):
    def w_out_into(pc, t, out):
        """``out = w_out(t)`` for the flat ``t`` (:class:`.records.Pieces` ``pc``)."""
        if stamp < 0:
            return  # never: the stamp keys the on-disk cache (:mod:`.jit`)
        t0, t1, a0, a1, C, D, omega = pc
        i = 0
        for j in range(t.size):
            i = find(t0, t[j], i)
            out[j] = wo(t0, t1, a0, a1, C, D, omega, t[j], i)

    return w_out_into


w_out_into = cached(_w_out_into)


@inline
def load_at(t, omega, phi, q, from_rest):
    return 0.0 if from_rest and t < 0 else q * math.cos(omega * t - phi)


def _invariants_into(stamp):
    def invariants_into(pc, kc, x, t, wp, wm):
        """``wp, wm = w+, w-`` at the flat points ``x``, times ``t`` (see :func:`invariants`; the line ``pc``, its
        :class:`.records.Constants` ``kc``)."""
        if stamp < 0:
            return  # never: the stamp keys the on-disk cache (:mod:`.jit`)
        t0, t1, a0, a1, C, D, omega = pc
        L, c, Z, s, P, phi, q, from_rest = kc.L, kc.c, kc.Z, kc.s, kc.P, kc.phi, kc.q, kc.from_rest
        i = k = 0
        for j in range(x.size):
            d = (L - x[j]) / c
            i = find(t0, t[j] - d, i)
            wm[j] = wo(t0, t1, a0, a1, C, D, omega, t[j] - d, i)
            ti = t[j] + d
            k = find(t0, ti - P, k)
            w = wo(t0, t1, a0, a1, C, D, omega, ti - P, k)
            if s < L:
                w -= (load_at(ti - (L - s) / c, omega, phi, q, from_rest) - load_at(ti - (L + s) / c, omega, phi, q,
                                                                                 from_rest)) / Z
            wp[j] = -w
            if s < L and x[j] < s:
                e = (s - x[j]) / c
                wm[j] += load_at(t[j] - e, omega, phi, q, from_rest) / Z
                wp[j] -= load_at(t[j] + e, omega, phi, q, from_rest) / Z

    return invariants_into


invariants_into = cached(_invariants_into)


@inline
def lin(t0, t1, a0, a1, i, x):
    """The linear part of ``w_out`` on piece ``i`` at ``x``."""
    return a0[i] + (a1[i] - a0[i]) * ((x - t0[i]) / (t1[i] - t0[i]))


@inline
def force_at(tau, cw, sw, cphi, sphi, q, from_rest):
    """``F(tau) = q cos(omega tau - phi)`` from ``cw, sw = cos, sin(omega tau)`` (0 before 0 from rest)."""
    return 0.0 if from_rest and tau < 0 else q * (cw * cphi + sw * sphi)


@inline
def point(pc, kc, x, t, ct, st, cd, sd, walk):
    """``(w+, w-)`` of the line ``pc`` at ``(x, t)`` given ``ct, st = cos, sin(omega t)`` and ``cd, sd`` of
    ``omega d``, ``d = (L-x)/c``: every other harmonic by rotation (:class:`.records.Constants` ``kc``: ``cP, sP``
    of ``omega P``; ``c1, s1``, ``c2, s2`` of ``omega (L -+ s)/c``), two sines per point at most.  ``walk = (i,
    k)``: the pieces last found for ``w-`` and ``w+``, returned updated after ``(w+, w-)``."""
    t0, t1, a0, a1, C, D = pc.t0, pc.t1, pc.a0, pc.a1, pc.C, pc.D
    i, k = walk
    L, c, Z, s, P, cP, sP, c1, s1, c2, s2, phi, cphi, sphi, q, from_rest = kc
    d = (L - x) / c
    tm, tp = t - d, t + d - P
    cm, sm = ct * cd + st * sd, st * cd - ct * sd            # omega (t - d)
    cq, sq = ct * cd - st * sd, st * cd + ct * sd            # omega (t + d)
    cpp, spp = cq * cP + sq * sP, sq * cP - cq * sP          # omega (t + d - P)
    i = find(t0, tm, i)
    k = find(t0, tp, k)
    wm = lin(t0, t1, a0, a1, i, tm) + C[i] * cm + D[i] * sm
    wp = -(lin(t0, t1, a0, a1, k, tp) + C[k] * cpp + D[k] * spp)
    if s < L:
        # F(t + d - (L - s)/c) = F(t + e), e = (s - x)/c, and F(t + d - (L + s)/c)
        ca, sa = cq * c1 + sq * s1, sq * c1 - cq * s1
        cb, sb = cq * c2 + sq * s2, sq * c2 - cq * s2
        Fa = force_at(t + d - (L - s) / c, ca, sa, cphi, sphi, q, from_rest)
        wp += (Fa - force_at(t + d - (L + s) / c, cb, sb, cphi, sphi, q, from_rest)) / Z
        if x < s:
            # F(t - e) = F(t - d + (L - s)/c)
            ce, se = cm * c1 - sm * s1, sm * c1 + cm * s1
            wm += force_at(t - d + (L - s) / c, ce, se, cphi, sphi, q, from_rest) / Z
            wp -= Fa / Z
    return wp, wm, (i, k)
