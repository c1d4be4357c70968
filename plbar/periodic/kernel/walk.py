"""The segment chain walked in compiled code: residuals, their exact Jacobian, the segments' end states.

The formulas of :mod:`plbar.periodic.chain` (its module docstring) one mode at a time.  Every
modal flow is :func:`plbar.motion.kernel.closed.mode_flow` (undamped, or damped where
``md.damping`` is given): the end state from the segment's start state; for the Jacobian also
the free flow's 2 x 2 block of each mode (unit initial states, no load) and the forced
part's derivative in the phase (zero initial state, ``(cos, sin)`` of the phase replaced by
``(-sin phi, cos phi)``), all linear in those arguments.

The model is a :class:`plbar.periodic.packed.ChainModel` ``md``: a state's table ``md.tab1``,
``md.tab2`` (``tab[W | LOAD | C | ZETA | CV, j]``) holds its frequencies, modal loads, the
weights of its margin (``-r_eta`` in state I, ``-gap_row`` in state II), its damping ratios and
the damper's share of the reaction (zero where there is none); ``md.E, md.G, md.B`` are the switch
maps (opening, impact, rebound), ``md.rq1 = -r_q``.  What a walk fills is a
:class:`plbar.periodic.packed.Walk`; the signature is a :class:`plbar.periodic.packed.Pairs` ``sig``.
A pair's kind ``dwell[i]`` is 1 (a stuck phase of positive dwell, then the free phase), 0 (zero dwell: the
opening at once) or 2 (a rebound: the free phase at once); the impact that ends a pair is a rebound (``B``)
when the next pair is of kind 2, else the plastic impact (``G``).
"""

from __future__ import annotations

from math import cos, pi, sin

import numpy as np

from ...motion.kernel.closed import add, half, matvec, mode_flow
from ...motion.kernel.data import Forcing, Mode, ModeState, Segment
from ..packed import CV, LOAD, ZETA, C, W, Jet, Walk
from .stamp import cached, jit

__all__ = ["chain", "segments", "copy", "relative", "start_size", "walk_space"]


@jit
def _flow(tab, damping, ld, tau, z, z1):
    """``z1``: the state at the end of a segment of ``tau`` and forcing ``ld`` from ``z``."""
    m = tab.shape[1]
    hf = half(ld.W, tau)
    for j in range(m):
        z1[j], z1[m + j] = mode_flow(Mode(tab[W, j], tab[LOAD, j], tab[ZETA, j], 0.0), ld, tau,
                                     ModeState(z[j], z[m + j]), hf, damping)


@jit
def _flow_jac(tab, damping, seg, tau, src, dst, tcol, dcol):
    """:func:`_flow` over the segment ``seg`` (a :class:`plbar.motion.kernel.data.Segment`) and its derivative:
    ``dst`` (a :class:`plbar.periodic.packed.Jet`) from ``src``: the free flow (unit initial states, no load), the
    phase (the forced part at ``(-sin phi, cos phi)``), a later start (``-Om d/dphi`` of the forced part) and the
    segment's own duration (column ``dcol``: the vector field at the end)."""
    z, D, z1, Dn = src.z, src.D, dst.z, dst.D
    m, nX = tab.shape[1], D.shape[1]
    ld = seg.ld
    Om, cphi, sphi = ld.W, ld.cphi, ld.sphi
    free = Forcing(Om, ld.c0, ld.s0, 0.0, 0.0)          # no load
    phase = Forcing(Om, ld.c0, ld.s0, -sphi, cphi)      # d/dphi of the forced part
    hf = half(Om, tau)
    load = cos(Om * (seg.ts + tau) - seg.phi)
    for j in range(m):
        w, f, zeta = tab[W, j], tab[LOAD, j], tab[ZETA, j]
        mode = Mode(w, f, zeta, 0.0)
        e, v = mode_flow(mode, ld, tau, ModeState(z[j], z[m + j]), hf, damping)
        p11, p21 = mode_flow(mode, free, tau, ModeState(1.0, 0.0), hf, damping)
        p12, p22 = mode_flow(mode, free, tau, ModeState(0.0, 1.0), hf, damping)
        de, dv = mode_flow(mode, phase, tau, ModeState(0.0, 0.0), hf, damping)
        z1[j], z1[m + j] = e, v
        for k in range(nX):
            a, b = D[j, k], D[m + j, k]
            Dn[j, k] = p11 * a + p12 * b - Om * de * tcol[k]
            Dn[m + j, k] = p21 * a + p22 * b - Om * dv * tcol[k]
        Dn[j, nX - 1] += de
        Dn[m + j, nX - 1] += dv
        Dn[j, dcol] += v
        Dn[m + j, dcol] += f * load - w * w * e - 2.0 * zeta * w * v


@jit
def _margin(tab, rq, g0, Om, t, phi, z):
    """``(g, size)``: the state's margin ``c . eta + cv . eta' + rq cos(Om t - phi) + g0`` (``-R`` in I, ``-x_c``
    in II; ``g0`` a gap's constant) and the size of its terms."""
    m = tab.shape[1]
    g, size = g0, abs(g0)
    for j in range(m):
        g += tab[C, j] * z[j] + tab[CV, j] * z[m + j]
        size += abs(tab[C, j]) * abs(z[j]) + abs(tab[CV, j]) * abs(z[m + j])
    return g + rq * cos(Om * t - phi), size + abs(rq)


@jit
def _gradient(tab, rq, Om, t, phi, D, tcol, row):
    """The gradient of :func:`_margin` in ``X`` into ``row`` (``D = dz/dX``, ``tcol = dt/dX``)."""
    m, nX = tab.shape[1], D.shape[1]
    rs = rq * sin(Om * t - phi)
    for k in range(nX):
        s = -rs * Om * tcol[k]
        for j in range(m):
            s += tab[C, j] * D[j, k] + tab[CV, j] * D[m + j, k]
        row[k] = s
    row[nX - 1] += rs


@jit
def _switch_rows(M, D, Dn):
    """``Dn = M D`` (the switch map on every column of the derivative)."""
    for i in range(M.shape[0]):
        for k in range(D.shape[1]):
            s = 0.0
            for j in range(M.shape[1]):
                s += M[i, j] * D[j, k]
            Dn[i, k] = s


@jit
def _switch(md, s, rebound, z, z1, D, D1, jac):
    """The switch at the end of a segment of state ``s + 1`` (opening; impact, or a ``rebound``): ``z1`` from
    ``z``, plus a gap's static equilibria (zeros without one); with ``jac`` its derivative ``D1`` from ``D``."""
    M = md.E if s == 0 else (md.B if rebound else md.G)
    matvec(M, z, z1)
    if not rebound:
        add(z1, md.offE if s == 0 else md.offG)
    if jac:
        _switch_rows(M, D, D1)


@jit
def copy(src, dst):
    """``dst[:] = src`` (1-d, as a loop: less code than numpy's assignment)."""
    for i in range(src.size):
        dst[i] = src[i]


@jit
def segments(dwell):
    """Segments of a chain: one per free phase and one per positive dwell."""
    n = 0
    for d in dwell:
        n += 2 if d == 1 else 1
    return n


@jit
def start_size(md, dwell):
    """The start state's size: state I, or state II when the first pair begins with a rebound."""
    return 2 * (md.tab2 if dwell[0] == 2 else md.tab1).shape[1]


@jit
def walk_space(md, dwell, F, J):
    """A :class:`plbar.periodic.packed.Walk` of residuals ``F`` and Jacobian ``J`` (empty: none) for a walk of
    ``dwell`` whose other arrays the caller does not keep."""
    k, n = segments(dwell), 2 * max(md.tab1.shape[1], md.tab2.shape[1])
    return Walk(F, J, np.empty((k, 2)), np.empty((k, 2, n)), np.empty(dwell.size),
                np.empty(F.size - start_size(md, dwell) - 1), np.empty(dwell.size))


@jit
def relative(F, scale, X, nz, T):
    """Largest relative residual: each switching residual by the size of its terms, the sum by ``T``, the
    periodicity by the largest state component."""
    q = scale.size
    zs = 1e-300
    for i in range(nz):
        zs = max(zs, abs(X[i]))
    r = abs(F[q]) / T
    for i in range(q):
        r = max(r, abs(F[i]) / max(scale[i], 1e-300))
    for i in range(nz):
        r = max(r, abs(F[q + 1 + i]) / zs)
    return r


@jit
def _close(X, nz, m, T, end, out, jac):
    """The last rows of ``out`` (a :class:`plbar.periodic.packed.Walk`): ``sum tau = m T`` and the periodicity
    ``z(m T) = z0`` at the state ``end`` (a :class:`plbar.periodic.packed.Jet`; with ``jac`` their Jacobian rows)."""
    q, z, D, F, J = X.size - nz - 1, end.z, end.D, out.F, out.J
    total = 0.0
    for i in range(q):
        total += X[nz + i]
    F[q] = total - m * T
    for i in range(nz):
        F[q + 1 + i] = z[i] - X[i]
    if jac:
        for k in range(X.size):
            J[q, k] = 1.0 if nz <= k < nz + q else 0.0
            for i in range(nz):
                J[q + 1 + i, k] = D[i, k] - (1.0 if i == k else 0.0)


def _chain(stamp):
    def chain(md, sig, T, X, out):
        """Residuals ``out.F`` (and, unless ``out.J`` is empty, the Jacobian ``out.J``) of the chain of ``sig.dwell``
        over ``sig.m`` periods at ``T``; returns the largest relative residual (:func:`relative`).

        Also fills (:class:`plbar.periodic.packed.Walk`) the segments' start times and lengths ``times[i]``, their
        states ``zs[i, 0 | 1]`` (start, end; padded; segment ``i`` is the one of duration ``X[nz + i]``), the
        margins after impacts followed by a zero dwell ``zero``, the size of the terms of every switching residual
        ``scale`` and the contact velocity before every impact ``vimp``.  The state and its derivative live in two
        buffers each (``a``: the current one).
        """
        tab1, tab2, rq1, damping, dwell = md.tab1, md.tab2, md.rq1, md.damping, sig.dwell
        F, J, times, zs, zero, scale, vimp = out.F, out.J, out.times, out.zs, out.zero, out.scale, out.vimp
        nz, nX, k = start_size(md, dwell), X.size, dwell.size
        n, jac = 2 * max(tab1.shape[1], tab2.shape[1]), J.size > 0 and stamp >= 0   # (the stamp keys the cache)
        Om, phi = 2.0 * pi / T, X[nX - 1]
        cphi, sphi = cos(phi), sin(phi)
        Z, tcol = np.zeros((2, n)), np.zeros(nX)
        DD = np.zeros((2, n, nX) if jac else (2, 1, 1))
        for i in range(nz):
            Z[0, i] = X[i]
            if jac:
                DD[0, i, i] = 1.0
        t, col, nzero, a = 0.0, 0, 0, 0
        for i in range(k):
            for s in range(2):
                if s == 0 and dwell[i] == 2:          # a rebound: the free phase at once
                    continue
                tab, rq, g0 = tab1 if s == 0 else tab2, rq1 if s == 0 else 0.0, md.g0[s]
                if s == 0 and dwell[i] == 0:          # just after the impact: the reaction must pull (< 0)
                    zero[nzero] = _margin(tab1, rq1, g0, Om, t, phi, Z[a])[0]
                    nzero += 1
                else:
                    tau = X[nz + col]
                    ld = Forcing(Om, cos(Om * t), sin(Om * t), cphi, sphi)
                    if jac:
                        _flow_jac(tab, damping, Segment(ld, t, phi), tau, Jet(Z[a], DD[a]), Jet(Z[1 - a], DD[1 - a]),
                                  tcol, nz + col)
                        tcol[nz + col] = 1.0
                        _gradient(tab, rq, Om, t + tau, phi, DD[1 - a], tcol, J[col])
                    else:
                        _flow(tab, damping, ld, tau, Z[a], Z[1 - a])
                    F[col], scale[col] = _margin(tab, rq, g0, Om, t + tau, phi, Z[1 - a])
                    times[col, 0], times[col, 1] = t, tau
                    copy(Z[a], zs[col, 0])
                    copy(Z[1 - a], zs[col, 1])
                    if s == 1:                        # the contact velocity: the margin -x_c's rate, negated
                        vimp[i] = 0.0
                        for j in range(tab2.shape[1]):
                            vimp[i] -= tab2[C, j] * Z[1 - a, tab2.shape[1] + j]
                    a, t, col = 1 - a, t + tau, col + 1
                _switch(md, s, dwell[(i + 1) % k] == 2, Z[a], Z[1 - a], DD[a], DD[1 - a], jac)
                a = 1 - a
        _close(X, nz, sig.m, T, Jet(Z[a], DD[a]), out, jac)
        return relative(F, scale, X, nz, T)

    return chain


chain = cached(_chain)   #: the entry point (:func:`_chain`)
