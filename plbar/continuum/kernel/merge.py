"""The merge of a grid step's pieces between jumps (compiled).

When a grid step is done, its pieces between jumps (joined at period cuts, load-delay points, openings, the
delayed pieces' kinks) are merged into one piece per jump-free run (:func:`merge_run`): the harmonic part is the
run's length-weighted mean (the pieces' own where they agree), the rest is projected (L2, Gauss-Legendre on
every piece) on one linear function, scaled (:func:`~.end.energy_scale`) so that ``int w_out^2`` over the run is
kept: the delay line conserves energy to round-off.  Jumps (impacts: ``w_out`` jumps by ``-2 v``; the load's
arrival from rest; the jumps carried in by the delay line) stay breakpoints.
"""

from __future__ import annotations

import math

import numpy as np

from .end import energy_scale
from .jit import jit
from .records import Pieces

__all__ = ["merge_run", "merge_step"]

_GX, _GW = np.polynomial.legendre.leggauss(8)


@jit
def merge_run(pc, i0, i1, dtk):
    """Pieces ``i0 .. i1 - 1`` of ``pc`` (:class:`.records.Pieces`: a jump-free run of one step, times local to
    ``dtk = k dt``) as one piece ``(a0, a1, C, D)``; ``ok`` False where no energy-keeping piece exists (then they
    stay as they are)."""
    t0, t1, a0, a1, C, D, w = pc
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
    ok, beta = energy_scale(B, Cq, dE)
    if ok:
        return True, beta * (c0 - c1), beta * (c0 + c1), Cs, Ds
    E, G = A + dE, A + 2 * B + Cq  # the whole projection scaled instead (a run whose field is nearly zero)
    if G > 0 and E >= 0:
        gam = math.sqrt(E / G)
        return True, gam * (c0 - c1), gam * (c0 + c1), gam * Cs, gam * Ds
    return E == 0, 0.0, 0.0, 0.0, 0.0


@jit
def merge_step(rec, first, count, dtk, omega):
    """Merge the jump-free runs of the step's pieces ``first .. count - 1`` of the march's record ``rec`` (rows
    ``k, tau0, tau1, a0, a1, C, D, jump``, :mod:`.march`) in place; the new count."""
    hk, jp = rec[0], rec[7]
    pc = Pieces(rec[1], rec[2], rec[3], rec[4], rec[5], rec[6], omega)
    t0, t1, a0, a1, C, D = pc.t0, pc.t1, pc.a0, pc.a1, pc.C, pc.D
    out = first
    i = first
    while i < count:
        j = i + 1
        while j < count and jp[j] == 0:
            j += 1
        ok = j > i + 1
        if ok:
            ok, b0, b1, Cm, Dm = merge_run(pc, i, j, dtk)
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


