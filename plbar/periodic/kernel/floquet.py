"""The monodromy of an evaluated chain in compiled code: flows and saltation matrices (FORMULATION §7).

The product of :mod:`plbar.periodic.floquet` (its docstring says what each factor is) over the segments
:func:`.walk.chain` recorded (``times``, ``zs``): the free flow of every segment (its 2 x 2 block per mode
is :func:`plbar.motion.kernel.closed.mode_flow` with unit initial states and no load), the saltation of
every opening after a positive dwell (``E + (f_II(E z) - E f_I(z)) dh^T / hdot``) and of every impact
(``R + (f^+ - R f_II) e^T / v_c``, ``R = G``, or ``E G`` where a zero dwell follows, or the rebound map ``B``
of Newton's law where a rebound follows, ``f^+`` then the state II field: the saltation of a Newton impact).
"""

from __future__ import annotations

from math import cos, sin

import numpy as np

from ...motion.kernel.closed import half, matvec, mode_flow
from ...motion.kernel.data import Forcing, Mode, ModeState
from ..packed import CV, LOAD, ZETA, C, W
from .stamp import cached, jit

__all__ = ["monodromy"]


@jit
def _field(tab, Om, t, phi, z, out):
    """``out = dz/dt = (eta', f cos(Om t - phi) - w^2 eta - 2 zeta w eta')`` (Eq. (1) in modal form)."""
    m = tab.shape[1]
    load = cos(Om * t - phi)
    for j in range(m):
        w = tab[W, j]
        out[j] = z[m + j]
        out[m + j] = tab[LOAD, j] * load - w * w * z[j] - 2.0 * tab[ZETA, j] * w * z[m + j]


@jit
def _free(tab, damping, Om, tau, P, Pn):
    """``Pn = Phi(tau) P``: the free flow of every mode (its 2 x 2 block) on the rows of ``P``."""
    m = tab.shape[1]
    hf = half(Om, tau)
    free = Forcing(Om, 1.0, 0.0, 0.0, 0.0)      # no load
    for j in range(m):
        mode = Mode(tab[W, j], tab[LOAD, j], tab[ZETA, j], 0.0)
        p11, p21 = mode_flow(mode, free, tau, ModeState(1.0, 0.0), hf, damping)
        p12, p22 = mode_flow(mode, free, tau, ModeState(0.0, 1.0), hf, damping)
        for k in range(P.shape[1]):
            a, b = P[j, k], P[m + j, k]
            Pn[j, k], Pn[m + j, k] = p11 * a + p12 * b, p21 * a + p22 * b


@jit
def _salt(M, u, v, s, P, Pn):
    """``Pn = (M + u v^T / s) P`` (a saltation matrix; ``M`` the switch's map)."""
    vP = np.zeros(P.shape[1])
    for j in range(M.shape[1]):
        for k in range(P.shape[1]):
            vP[k] += v[j] * P[j, k]
    for i in range(M.shape[0]):
        for k in range(P.shape[1]):
            acc = u[i] * vP[k] / s
            for j in range(M.shape[1]):
                acc += M[i, j] * P[j, k]
            Pn[i, k] = acc


@jit
def _jump(tab_a, Mp, tab_b, Om, t, phi, z, fa, jump):
    """The field of ``tab_a`` at ``z`` into ``fa``, and into ``jump`` the field's jump across the switch map
    ``Mp`` to the field of ``tab_b``: ``f_b(Mp z) - Mp f_a(z)`` (the saltation's numerator)."""
    n = Mp.shape[0]
    mz, fb = np.empty(n), np.empty(n)
    _field(tab_a, Om, t, phi, z, fa)
    matvec(Mp, z, mz)
    _field(tab_b, Om, t, phi, mz, fb)
    matvec(Mp, fa, jump)
    for i in range(n):
        jump[i] = fb[i] - jump[i]


@jit
def _opening(md, Om, t, phi, z, P, Pn):
    """The saltation of the opening at ``t`` from the state I ``z`` (``h = -R``, its gradient ``(c, cv)``)."""
    tab1, E, rq1 = md.tab1, md.E, md.rq1
    m1 = tab1.shape[1]
    fI, jump, dh = np.empty(2 * m1), np.empty(E.shape[0]), np.empty(2 * m1)
    _jump(tab1, E, md.tab2, Om, t, phi, z, fI, jump)
    hdot = -rq1 * Om * sin(Om * t - phi)
    for j in range(m1):
        dh[j], dh[m1 + j] = tab1[C, j], tab1[CV, j]
        hdot += dh[j] * fI[j] + dh[m1 + j] * fI[m1 + j]
    _salt(E, jump, dh, hdot, P, Pn)


@jit
def _impact(tabp, R, tab2, Om, t, phi, z, P, Pn):
    """The saltation of the impact at ``t`` from the state II ``z`` (``h = x_c``, reset ``R``, then the field of
    ``tabp``)."""
    m2 = tab2.shape[1]
    fII, jump, e = np.empty(2 * m2), np.empty(R.shape[0]), np.zeros(2 * m2)
    _jump(tab2, R, tabp, Om, t, phi, z, fII, jump)
    vc = 0.0
    for j in range(m2):
        e[j] = -tab2[C, j]                 # the gap row (the state II margin is -x_c)
        vc += e[j] * z[m2 + j]
    _salt(R, jump, e, vc, P, Pn)


def _monodromy(stamp):
    def monodromy(md, dwell, T, phi, times, zs, M):
        """``M``: the Jacobian of the ``m``-period map of the chain of ``dwell`` whose segments are ``times``,
        ``zs``."""
        tab1, tab2, E, G, B, damping = md.tab1, md.tab2, md.E, md.G, md.B, md.damping
        n0, mm = M.shape[0], 2 * max(tab1.shape[1], tab2.shape[1])
        EG = np.zeros((E.shape[0], G.shape[1]))
        for i in range(E.shape[0]):
            for j in range(G.shape[1]):
                for r in range(G.shape[0]):
                    EG[i, j] += E[i, r] * G[r, j]
        P, Pn = np.zeros((mm, n0)), np.zeros((mm, n0))
        for i in range(n0 if stamp >= 0 else 0):      # (the stamp keys the on-disk cache)
            P[i, i] = 1.0
        Om, col, k = 2.0 * np.pi / T, 0, dwell.size
        for i in range(k):
            for s in range(2 if dwell[i] == 1 else 1):
                stuck = s == 0 and dwell[i] == 1
                t = times[col, 0] + times[col, 1]
                _free(tab1 if stuck else tab2, damping, Om, times[col, 1], P, Pn)
                if stuck:
                    _opening(md, Om, t, phi, zs[col, 1], Pn, P)
                elif dwell[(i + 1) % k] == 1:
                    _impact(tab1, G, tab2, Om, t, phi, zs[col, 1], Pn, P)
                elif dwell[(i + 1) % k] == 2:      # a rebound: Newton's law, the free phase goes on
                    _impact(tab2, B, tab2, Om, t, phi, zs[col, 1], Pn, P)
                else:                             # zero dwell next: impact and opening at once
                    _impact(tab2, EG, tab2, Om, t, phi, zs[col, 1], Pn, P)
                col += 1
        for i in range(n0):
            for j in range(n0):
                M[i, j] = P[i, j]

    return monodromy


monodromy = cached(_monodromy)   #: the entry point (:func:`_monodromy`)
