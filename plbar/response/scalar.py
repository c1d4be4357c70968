"""One periodic orbit in plain Python floats (small systems; the fast path of :mod:`plbar.response`).

For a handful of modes, numpy's per-call overhead dominates the arithmetic:
the same closed forms as :mod:`plbar.flow` (Duhamel kernels in sinc form,
Eqs. (15)-(17); ``Psi`` of Eq. (20) in the grouped form of
:func:`plbar.flow.psi_closed_form`) evaluated mode by mode with :mod:`math`
are several times faster for one orbit.  The batched numpy functions
(:mod:`plbar.orbit`, :mod:`plbar.energy`) are the reference they are tested
against.
"""

from __future__ import annotations

from math import atan2, cos, fmod, pi, sin
from operator import mul

from .flow import CANCEL_LIMIT

__all__ = ["Small", "orbit", "CANCEL_LIMIT"]



def _sinc(x: float) -> float:
    return sin(x) / x if x != 0.0 else 1.0


def _kern(w: float, W: float, t: float):
    """Duhamel kernels ``C, S, C'`` (as :func:`plbar.flow.kernels`) and ``cos w t, sin w t``."""
    wp = w + W
    ht = 0.5 * t
    snc = t * _sinc((w - W) * ht)
    sig = wp * ht
    csn = cos(sig) * snc
    co, si = cos(w * t), sin(w * t)
    so = si / w if w != 0.0 else t                   # sin(w t) / w, t for a rigid-body mode
    return sin(sig) * snc / wp, (so - csn) / wp, (w * csn + sin(W * t)) / wp, co, si, so


def _psi(w: float, f: float, W: float, thc: float, ths: float, t: float, eta0: float, v0: float):
    """``int_0^t etadot^2`` of one mode (``thc, ths = cos, sin(W ts - phi)``) and its cancellation factor."""
    wp, wm = w + W, w - W
    d = wp * wm
    if d == 0.0:
        return 0.0, float("inf")
    g = f / d
    Cc = -g * W * ths
    Cs = -g * W * thc
    A = v0 - Cc
    B = g * w * thc - w * eta0
    ht = 0.5 * t
    pt, mt, wt, Wt = wp * ht, wm * ht, w * t, W * t
    # sinc(x) = sin(x) / x (1 at 0), inline: the arguments below are 0 only for mt (at resonance)
    s1w, s1W, sph = sin(wt) / wt, sin(Wt) / Wt, sin(pt) / pt
    smh = sin(mt) / mt if mt != 0.0 else 1.0
    s2w, s2W, s2p = sin(2 * wt) / (2 * wt), sin(2 * Wt) / (2 * Wt), sin(2 * pt) / (2 * pt)
    s2m = sin(2 * mt) / (2 * mt) if mt != 0.0 else 1.0
    AA, BB, CC, SS = A * A, B * B, Cc * Cc, Cs * Cs
    ACc, BCs, ACs, BCc = A * Cc, B * Cs, A * Cs, B * Cc
    p = (ht * ((AA + BB + CC + SS) + (AA - BB) * s2w + (CC - SS) * s2W
               + 2 * (ACc + BCs) * s2m + 2 * (ACc - BCs) * s2p)
         + t * t * (A * B * w * s1w * s1w + Cc * Cs * W * s1W * s1W
                    + 0.5 * ((ACs + BCc) * wp * sph * sph + (BCc - ACs) * wm * smh * smh)))
    scale = (abs(A) + abs(B) + abs(Cc) + abs(Cs)) ** 2 * t
    return p, (scale / p if p > 0 else float("inf"))


def _mv(M, x):
    return [sum(map(mul, row, x)) for row in M]


class Small:
    """A problem's modal data as Python lists."""

    def __init__(self, prob):
        s = prob.system
        self.m1 = s.w1.size
        self.w1, self.w2 = s.w1.tolist(), s.w2.tolist()
        self.f1, self.f2 = [float(v) for v in prob.f1], [float(v) for v in prob.f2]
        self.P12, self.P21, self.Q21 = s.P12.tolist(), s.P21.tolist(), s.Q21.tolist()
        self.r_eta, self.gap_row, self.r_q = s.r_eta.tolist(), s.gap_row.tolist(), float(prob.r_q)
        self.nr = sum(v * v for v in self.r_eta) ** 0.5
        self.ng = max(abs(v) for v in self.gap_row)
        self.S = None if s.truncated else float(s.impact_mass)     # Delta_PL = S v_c^2 / 2 with all modes


def _state_I(k: Small, W: float, T1: float, c: float, sn: float, eta0, v0):
    """Modal state I at ``T1`` from ``t = 0`` (the segment flow of :func:`plbar.response.flow.segment`)."""
    e, v = [], []
    for j in range(k.m1):
        w, f = k.w1[j], k.f1[j]
        C, S, Cp, co, si, so = _kern(w, W, T1)
        e.append(co * eta0[j] + so * v0[j] + f * (C * c + S * sn))
        v.append(-w * si * eta0[j] + co * v0[j] + f * (Cp * c + W * C * sn))
    return e, v


def _state_II(k: Small, W: float, T1: float, T2: float, c: float, sn: float, es, vs):
    """Modal state II at ``T^-`` from ``t = T1`` (phase-shifted forcing)."""
    c0, s0 = cos(W * T1), sin(W * T1)
    eT, vT = [], []
    for j in range(len(k.w2)):
        w, f = k.w2[j], k.f2[j]
        C, S, Cp, co, si, so = _kern(w, W, T2)
        ec, es_ = c0 * C - s0 * S, s0 * C + c0 * S
        vc, vs_ = c0 * Cp - s0 * W * C, s0 * Cp + c0 * W * C
        eT.append(co * es[j] + so * vs[j] + f * (ec * c + es_ * sn))
        vT.append(-w * si * es[j] + co * vs[j] + f * (vc * c + vs_ * sn))
    return eT, vT


def _psi_sum(k: Small, W: float, phi: float, T1: float, T2: float, eta0, v0, es, vs):
    """``sum_j Psi_j w_j`` over both segments (Eq. (21)) and the largest cancellation factor."""
    den, cancel = 0.0, 0.0
    for ws, fs, eta, vel, ts, t in ((k.w1, k.f1, eta0, v0, 0.0, T1), (k.w2, k.f2, es, vs, T1, T2)):
        thc, ths = cos(W * ts - phi), sin(W * ts - phi)
        for j in range(len(ws)):
            p, cf = _psi(ws[j], fs[j], W, thc, ths, t, eta[j], vel[j])
            den += p * ws[j]
            cancel = max(cancel, cf)
    return den, cancel


def orbit(k: Small, T: float, T1: float, a, Z):
    """The orbit at a zero of ``D``: phase, states, residuals, periodicity, ``Delta_PL`` and ``Psi`` sums.

    Parameters
    ----------
    k : Small
    T, T1 : float
    a : (a1, b1, a2, b2)
        Residual coefficients at ``T1`` (FORMULATION §4).
    Z : list of [cos part, sin part]
        Periodic initial state of state I (``2 m1`` rows).

    Returns
    -------
    dict
        ``phi, eta0, v0, eta_s, v_s, r1, r2, sc1, sc2, per, v_imp, dPL, den, cancel``
        (``den = sum_j Psi_j w_j`` over both states, ``cancel`` the largest
        cancellation factor of the closed form).
    """
    a1, b1, a2, b2 = a
    phi = atan2(-a1, b1) if a1 * a1 + b1 * b1 >= a2 * a2 + b2 * b2 else atan2(-a2, b2)
    T2, W = T - T1, 2 * pi / T
    c, sn = cos(phi), sin(phi)
    z = [zc * c + zs * sn for zc, zs in Z]
    e, v = _state_I(k, W, T1, c, sn, z[:k.m1], z[k.m1:])
    es, vs = _mv(k.P12, e), _mv(k.P12, v)
    eT, vT = _state_II(k, W, T1, T2, c, sn, es, vs)
    v_imp = sum(g * x for g, x in zip(k.gap_row, vT))
    if v_imp <= 0:                      # the other root phi + pi: the negated response
        phi, v_imp = phi + pi, -v_imp
        z, e, es, vs, eT, vT = ([-x for x in lst] for lst in (z, e, es, vs, eT, vT))
    phi = fmod(phi, 2 * pi)
    phi = phi + 2 * pi if phi < 0 else phi
    eta0, v0 = z[:k.m1], z[k.m1:]
    r1 = -(sum(r * x for r, x in zip(k.r_eta, e)) + k.r_q * cos(W * T1 - phi))
    r2 = sum(g * x for g, x in zip(k.gap_row, eT))
    sc1 = k.nr * max(max(map(abs, e)), max(map(abs, eta0))) + abs(k.r_q)
    sc2 = k.ng * max(max(map(abs, eT)), max(map(abs, es)))
    ep, vp = _mv(k.P21, eT), _mv(k.Q21, vT)
    zmax = max(map(abs, z))
    per = max(abs(x - y) for x, y in zip(ep + vp, z)) / (zmax if zmax > 0 else 1e-300)
    dPL = 0.5 * k.S * v_imp * v_imp if k.S is not None else \
        0.5 * sum(x * x for x in vT) - 0.5 * sum(x * x for x in vp)
    den, cancel = _psi_sum(k, W, phi, T1, T2, eta0, v0, es, vs)
    return dict(phi=phi, eta0=eta0, v0=v0, eta_s=es, v_s=vs, r1=r1, r2=r2, sc1=sc1, sc2=sc2, per=per,
                v_imp=v_imp, dPL=dPL, den=den, cancel=cancel)
