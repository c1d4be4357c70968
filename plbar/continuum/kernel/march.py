"""The whole march (compiled): grid step by grid step, the end fed by the delay line it writes.

The record of ``w_out``, ``rec`` (8, pieces): rows ``k, tau0, tau1, a0, a1, C, D, jump`` -- grid step ``k``, local
times, the linear part from ``a0`` (at ``tau0``) to ``a1`` (at ``tau1``), ``C cos(omega t) + D sin(omega t)``, and
whether ``w_out`` jumps at the piece's start.  Stuck, ``w_out = -w_in``; free, ``w_out = 2 v - w_in`` whose
transient is stored by :func:`~.end.stored_line`.  Step ``k`` reads the pieces of step ``k - 2n`` (the delay
``2L/c``), splits them at the load's delay points and the period cuts, marches the end over each part
(:func:`end_over`), and merges its own pieces between jumps (:mod:`.merge`).  The arrays grow by doubling.
The state between calls is a :class:`.records.MarchState`: ``st`` = ``u, v, stuck, pending jump``; ``ix`` =
``pieces, events, strobes, amp entries, switches in this step``.
"""

from __future__ import annotations

import math

import numpy as np

from .end import SAMPLES, free, fval, impact, lowest, opening, pu, pv, stored_line
from .jit import cached, inline, jit
from .merge import merge_step
from .records import Incoming, MarchConstants, MarchScratch, MarchState

__all__ = ["OPENING", "IMPACT", "MAX_EVENTS_PER_STEP", "march"]

OPENING, IMPACT = 1, 2
#: more switches than this in one grid step is taken as chatter and stops the march
MAX_EVENTS_PER_STEP = 50


@jit
def force(d, t, omega, phi, q, from_rest):
    """``(C, D)`` of ``F(t - d) = q cos(omega (t - d) - phi)``, 0 before the load starts (rest start)."""
    if from_rest and t < d:
        return 0.0, 0.0
    x = omega * d + phi
    return q * math.cos(x), q * math.sin(x)


@jit
def forcing(t, at_end, d1, d2, omega, phi, q, Z, from_rest):
    """``(C, D)`` of ``g``'s load part over a piece holding ``t``: ``Fterm / Z`` in ``w_in``, or ``F_L / Z``."""
    if at_end:
        c, s = force(0.0, t, omega, phi, q, from_rest)
        return c / Z, s / Z
    c1, s1 = force(d1, t, omega, phi, q, from_rest)
    c2, s2 = force(d2, t, omega, phi, q, from_rest)
    return (c1 - c2) / Z, (s1 - s2) / Z


@jit
def add_piece(rec, sv, k, x, xe, b0, b1, C, D):
    """Store the piece ``[x, xe]`` of step ``k`` (none if empty; ``sv`` the :class:`.records.MarchState`); the
    record, grown if it was full."""
    if xe <= x:
        return rec
    ix, st = sv.ix, sv.st
    n = ix[0]
    if n >= rec.shape[1]:
        big = np.empty((8, 2 * rec.shape[1]))
        big[:, :n] = rec[:, :n]
        rec = big
    rec[0, n], rec[1, n], rec[2, n], rec[3, n], rec[4, n] = k, x, xe, b0, b1
    rec[5, n], rec[6, n], rec[7, n] = C, D, st[3]
    ix[0] = n + 1
    st[3] = 0.0
    return rec


@jit
def add_event(ev, ix, t, kind, v, loss):
    n = ix[1]
    if n >= ev.shape[1]:
        big = np.empty((4, 2 * ev.shape[1]))
        big[:, :n] = ev[:, :n]
        ev = big
    ev[0, n], ev[1, n], ev[2, n], ev[3, n] = t, kind, v, loss
    ix[1] = n + 1
    return ev


@inline
def end_over(rec, ev, sv, k, x, sb, wi, prm, ws):
    """March the end over ``[x, sb]`` of step ``k`` (local times) under the incoming invariant ``wi``
    (:class:`.records.Incoming`: ``w_in = l0 + l1 tau + C cos + D sin``, and ``LC, LD`` of the load on the end),
    switching where the closed form says; ``(rec, ev, chatter)``."""
    hold, Z, m, omega, taus, vals = prm.hold, prm.Z, prm.m, prm.omega, ws.taus, ws.vals
    ix, st, amp = sv.ix, sv.st, sv.amp
    tk = k * prm.dt
    l0, l1, Ci, Di, LC, LD = wi
    while sb > x:
        h = sb - x
        gp = (tk + x, omega, l0, l1, Ci + LC, Di + LD, Z, 0.0, 0.0)
        if st[2] != 0:
            tau = -1.0 if hold == 1 else opening(gp, h, taus, vals)
            te = h if tau < 0 else tau
            rec = add_piece(rec, sv, k, x, sb if tau < 0 else x + te, -l0, -(l0 + l1 * te), -Ci, -Di)
        else:
            p = free(gp, st[0], st[1], m)
            tau = -1.0 if hold == 2 else impact(p, h, taus, vals)
            te = h if tau < 0 else tau
            b0, b1 = stored_line(p, te, l0, l1, Ci, Di)
            rec = add_piece(rec, sv, k, x, sb if tau < 0 else x + te, b0, b1, 2 * p[4] - Ci, 2 * p[5] - Di)
            amp[ix[3] - 1] = max(amp[ix[3] - 1], -lowest(p, te))
            st[0], st[1] = pu(p, te), pv(p, te)
        if tau < 0:
            return rec, ev, False
        t = tk + x + tau
        if st[2] != 0:
            ev = add_event(ev, ix, t, OPENING, 0.0, 0.0)
            st[0], st[1], st[2] = 0.0, 0.0, 0.0
        else:
            v = st[1]
            ev = add_event(ev, ix, t, IMPACT, v, 0.5 * m * v * v)
            st[0], st[1], st[3] = 0.0, 0.0, 1.0  # w_out jumps by -2 v
            st[2] = 1.0 if fval(0, gp, 0.0, tau) >= 0 else 0.0
            if st[2] == 0:
                ev = add_event(ev, ix, t, OPENING, 0.0, 0.0)
        l0 += l1 * tau
        x += tau
        ix[4] += 1
        if ix[4] > MAX_EVENTS_PER_STEP:
            return rec, ev, True
    return rec, ev, False


@jit
def breakpoints(tk, nc, prm, ws):
    """The breakpoints of the step at ``tk``, sorted into ``ws.pts``: the load's delay points (jumps from rest,
    flagged in ``ws.pjump``) and the period cuts ``ws.cutv[:nc]`` (flagged in ``ws.pcut``); their number."""
    dt, at_end, d1, d2, from_rest = prm.dt, prm.at_end, prm.d1, prm.d2, prm.from_rest
    cutv, pts, pjump, pcut = ws.cutv, ws.pts, ws.pjump, ws.pcut
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
                pcut[i], dup = 1.0, True
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
    return npt


@jit
def strobe(sv):
    """The end at a period boundary, and a new period's amplitude (in the :class:`.records.MarchState` ``sv``)."""
    st, ix, strobes, amp = sv.st, sv.ix, sv.strobes, sv.amp
    if ix[2] < strobes.shape[1]:
        strobes[0, ix[2]], strobes[1, ix[2]], strobes[2, ix[2]] = st[0], st[1], st[2]
        ix[2] += 1
        if ix[3] < amp.size:
            amp[ix[3]] = -st[0]
            ix[3] += 1


@jit
def step(rec, ev, sv, k, nc, prm, ws):
    """Grid step ``k``: the pieces of step ``k - 2n`` (record rows ``sv.first[k] .. sv.first[k + 1]``), rotated by
    the delay and split at the breakpoints (``ws.cutv[:nc]`` the period cuts in it); ``(rec, ev, chatter)``."""
    Z, q, omega, phi, dt, cr, sr, d1, d2 = prm.Z, prm.q, prm.omega, prm.phi, prm.dt, prm.cr, prm.sr, prm.d1, prm.d2
    from_rest, at_end, cutv, pts, pjump, pcut = prm.from_rest, prm.at_end, ws.cutv, ws.pts, ws.pjump, ws.pcut
    ix, st, first = sv.ix, sv.st, sv.first
    tk = k * dt
    npt = breakpoints(tk, nc, prm, ws)
    ix[4] = 0
    st[3] = 0.0
    for i in range(first[k], first[k + 1]):
        t0, t1, a0, a1 = rec[1, i], rec[2, i], rec[3, i], rec[4, i]
        Cw, Dw = rec[5, i] * cr - rec[6, i] * sr, rec[5, i] * sr + rec[6, i] * cr
        slope = (a1 - a0) / (t1 - t0)
        st[3] = max(st[3], rec[7, i])
        sa, ip = t0, 0
        while ip < npt and pts[ip] <= t0:
            ip += 1
        while sa < t1:
            iscut, jump = False, 0.0
            if ip < npt and pts[ip] < t1:
                sb, iscut, jump = pts[ip], pcut[ip] != 0, pjump[ip]
                ip += 1
            else:
                sb = t1
                for j in range(nc):
                    iscut = iscut or cutv[j] == t1
            Cf, Df = forcing(tk + 0.5 * (sa + sb), at_end, d1, d2, omega, phi, q, Z, from_rest)
            Ci, Di, LC, LD = (-Cw, -Dw, Cf, Df) if at_end else (Cf - Cw, Df - Dw, 0.0, 0.0)
            rec, ev, bad = end_over(rec, ev, sv, k, sa, sb, Incoming(-(a0 + slope * (sa - t0)), -slope, Ci, Di, LC,
                                                                     LD), prm, ws)
            if bad:
                return rec, ev, True
            if iscut:
                strobe(sv)
            sa = sb
            st[3] = max(st[3], jump)
    return rec, ev, False


def _march(stamp):
    def march(bar, load, start, T, periods, n, hold, merge, seed):
        """The whole march of ``bar`` under ``load`` from ``start`` at ``t = 0`` (:class:`.records.MarchBar`,
        :class:`.records.MarchLoad`, :class:`.records.MarchStart`) for ``periods`` of ``T`` on the grid
        ``dt = L / (c n)``; ``hold`` 0 none, 1 closed, 2 open; ``seed`` (3, 2n) the delay line's past from a given
        field (``a0, a1, jump`` of each grid step before ``t = 0``; ``seed.shape[1] == 0``: the harmonic past
        ``C cos + D sin`` of ``start``).  Returns ``(rec, ev, strobes, amp, status, t_err)``:
        the record; ``ev`` (4, events) rows ``time, kind, v, loss``; ``strobes`` (3, periods) ``u, v, stuck`` at the
        period boundaries; ``amp`` (periods + 1) the largest ``-u`` per period; ``status`` 0, or 1 for chatter in the
        step at ``t_err``."""
        if stamp < 0:
            raise ValueError("never")  # never: the stamp keys the on-disk cache (:mod:`.jit`)
        L, c, Z, m, s = bar
        q, omega, phi, from_rest = load
        su, sv, sstuck, sC, sD = start
        dt, off = L / (c * n), 2 * n
        nsteps = int(math.ceil(periods * T / dt - 1e-12))
        prm = MarchConstants(L, c, Z, m, s, q, omega, phi, dt, math.cos(omega * 2 * L / c),
                             math.sin(omega * 2 * L / c), (L - s) / c, (L + s) / c, hold, from_rest, s == L)
        rec, first = np.empty((8, 4 * (off + nsteps))), np.empty(off + nsteps + 1, np.int64)
        for i in range(off):
            rec[0, i], rec[1, i], rec[2, i], rec[3, i], rec[4, i] = i - off, 0.0, dt, 0.0, 0.0
            rec[5, i], rec[6, i], rec[7, i] = sC, sD, 0.0
            if seed.shape[1] == off:
                rec[3, i], rec[4, i], rec[7, i] = seed[0, i], seed[1, i], seed[2, i]
            first[i] = i
        ev, strobes, amp = np.empty((4, 64)), np.zeros((3, periods)), np.zeros(periods + 1)
        ix = np.array([off, 0, 0, 1, 0], np.int64)
        st = np.array([su, sv, 1.0 if sstuck else 0.0, 0.0])
        amp[0] = -su
        state = MarchState(ix, st, amp, strobes, first)
        ncut = int(dt / T) + 3
        ws = MarchScratch(np.empty(ncut), np.empty(ncut + 2), np.empty(ncut + 2), np.empty(ncut + 2),
                          np.empty(SAMPLES + 1), np.empty(SAMPLES + 1))
        cutv = ws.cutv
        pnext = 1
        for k in range(nsteps):
            nc = 0
            while pnext <= periods and pnext * T <= (k + 1) * dt * (1 + 1e-15):
                cutv[nc] = min(pnext * T - k * dt, dt)
                nc, pnext = nc + 1, pnext + 1
            first[k + off] = ix[0]
            rec, ev, bad = step(rec, ev, state, k, nc, prm, ws)
            if bad:
                return rec[:, :ix[0]], ev[:, :ix[1]], strobes, amp, 1, k * dt
            if merge:
                ix[0] = merge_step(rec, first[k + off], ix[0], k * dt, omega)
        return rec[:, :ix[0]], ev[:, :ix[1]], strobes, amp, 0, 0.0


    return march


march = cached(_march)