"""The accounts' integrals, compiled: the work of the load and the space integrals at given times.

Gauss-Legendre (6 points) on intervals cut at every mapped piece end, the fields at the points by
:func:`~.fields.point` (two sines a point).  See :mod:`plbar.continuum.accounts`.
"""

from __future__ import annotations

import math

import numpy as np

from .fields import point
from .jit import cached

__all__ = ["space_into", "work_into"]

_X, _W = np.polynomial.legendre.leggauss(6)


def _space_into(stamp):
    def space_into(pc, kc, ts, kind, out):
        """``out[j] = int_0^L`` of the energy density ``rhoA (w+^2 + w-^2) / 4`` (``kind`` 0) or ``rhoA v^2`` (1) at
        ``ts[j]``, on the intervals cut at the mapped ends of the pieces of the last ``2L/c`` and the load's fronts."""
        if stamp < 0:
            return  # never: the stamp keys the on-disk cache (:mod:`.jit`)
        t0, t1, omega, L, c, Z, s, P = pc.t0, pc.t1, pc.omega, kc.L, kc.c, kc.Z, kc.s, kc.P
        rhoA = Z / c
        n = t0.size
        for j in range(ts.size):
            t = ts[j]
            lo = max(np.searchsorted(t0, t - P) - 1, 0)
            hi = min(np.searchsorted(t0, t, side="right") + 1, n)
            m = hi - lo
            xs = np.empty(4 * m + 6)
            for i in range(m):
                xs[4 * i] = L - c * (t - t0[lo + i])
                xs[4 * i + 1] = L - c * (t0[lo + i] + P - t)
                xs[4 * i + 2] = L - c * (t - t1[lo + i])
                xs[4 * i + 3] = L - c * (t1[lo + i] + P - t)
            xs[4 * m], xs[4 * m + 1], xs[4 * m + 2], xs[4 * m + 3] = s, s - c * t, 2 * L - c * t - s, c * t - s
            xs[4 * m + 4], xs[4 * m + 5] = 0.0, L
            xs = np.sort(xs)
            ct, st = math.cos(omega * t), math.sin(omega * t)
            walk = (lo, hi - 1)
            tot = 0.0
            prev = 0.0
            for e in range(xs.size):
                b = min(xs[e], L)
                if b <= prev:
                    continue
                h = 0.5 * (b - prev)
                mid = 0.5 * (b + prev)
                acc = 0.0
                for g in range(_X.size):
                    x = mid + h * _X[g]
                    wd = omega * (L - x) / c
                    wp, wm, walk = point(pc, kc, x, t, ct, st, math.cos(wd), math.sin(wd), walk)
                    acc += _W[g] * (0.25 * (wp * wp + wm * wm) if kind == 0 else 0.25 * (wp + wm) ** 2)
                tot += h * acc
                prev = b
            out[j] = rhoA * tot

    return space_into


space_into = cached(_space_into)


def _work_into(stamp):
    def work_into(pc, kc, edges, T, out):
        """``out[p] += int F(t) v(s, t) dt`` over the intervals of ``edges`` (period ``p`` of each by its middle)."""
        if stamp < 0:
            return  # never: the stamp keys the on-disk cache (:mod:`.jit`)
        omega, L, c, s, cphi, sphi, q, from_rest = pc.omega, kc.L, kc.c, kc.s, kc.cphi, kc.sphi, kc.q, kc.from_rest
        periods = out.size
        d = (L - s) / c
        cd, sd = math.cos(omega * d), math.sin(omega * d)
        walk = (0, 0)
        for e in range(edges.size - 1):
            a, b = edges[e], edges[e + 1]
            h, mid = 0.5 * (b - a), 0.5 * (a + b)
            p = min(int(math.floor(mid / T)), periods - 1)
            acc = 0.0
            for g in range(_X.size):
                t = mid + h * _X[g]
                ct, st = math.cos(omega * t), math.sin(omega * t)
                wp, wm, walk = point(pc, kc, s, t, ct, st, cd, sd, walk)
                F = 0.0 if from_rest and t < 0 else q * (ct * cphi + st * sphi)
                acc += _W[g] * F * 0.5 * (wp + wm)
            out[p] += h * acc


    return work_into


work_into = cached(_work_into)