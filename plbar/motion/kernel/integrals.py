"""Integrals of one mode over a piece, compiled: ``Psi = int eta'^2`` (Eq. (20)) and the work of the load.

The closed forms of :mod:`plbar.response` one mode at a time: ``Psi`` in the grouped
``sinc`` form of :func:`plbar.response.flow.psi_closed_form` (Eqs. (28)-(33), Appendix 2)
and the work in that of :func:`plbar.response.power.work_closed_form`; damped modes as
sums of exponentials (:mod:`plbar.response.damped`).  Where a closed form cancels
(cancellation factor at least :data:`plbar.response.flow.CANCEL_LIMIT`: near resonance,
near critical damping) Gauss-Legendre quadrature of the exact velocity takes over,
composite with at most 100 nodes a piece, exact to round-off (the bound of
:func:`plbar.response.flow.psi_quadrature`).  The work is independent of the energies,
so the energy budget of a simulation is a check, not an identity.  A rigid-body mode under a constant
acceleration ``g`` (:class:`.data.Mode`; its velocity gains ``g u``) takes the quadrature: its velocity is
exact in it, a polynomial and sinusoids that the rule integrates to round-off.  A mode is a :class:`.data.Mode`, the
forcing a :class:`.data.Forcing`, the state at the piece's start a :class:`.data.ModeState`, the forcing's half
angle over the piece a :class:`.data.Half` (:func:`.closed.half` of its length).
"""

from __future__ import annotations

from math import ceil, cos, inf, isfinite, sin

import numpy as np

from ...response.flow import CANCEL_LIMIT, gauss
from .closed import DIRECT, half, mode_flow, phi1, roots
from .jit import jit

__all__ = ["GL_W", "GL_X", "psi", "work"]


def _rules():
    """Gauss-Legendre nodes and weights for 40, 60, 80 and 100 points, padded to rows of 100."""
    x, wt = np.zeros((4, 100)), np.zeros((4, 100))
    for i, n in enumerate((40, 60, 80, 100)):
        x[i, :n], wt[i, :n] = gauss(n)
    return x, wt


GL_X, GL_W = _rules()


@jit
def _sines(w, W, u, cb, sb):
    """``sin`` of ``w u, 2 w u, W u, 2 W u, p, 2 p, q, 2 q`` (``p, q = (w +- W) u / 2``) from ``cos, sin(w u / 2)`` and
    ``cb, sb = cos, sin(W u / 2)``; ``sin q`` directly where it is small (the difference would cancel)."""
    a = 0.5 * w * u
    ca, sa = cos(a), sin(a)
    q = a - 0.5 * W * u
    sp, cp = sa * cb + ca * sb, ca * cb - sa * sb
    sq = sin(q) if abs(q) < DIRECT else sa * cb - ca * sb
    cq = ca * cb + sa * sb
    sw, cw = 2.0 * sa * ca, 1.0 - 2.0 * sa * sa
    sW, cW = 2.0 * sb * cb, 1.0 - 2.0 * sb * sb
    return sw, 2.0 * sw * cw, sW, 2.0 * sW * cW, sp, 2.0 * sp * cp, sq, 2.0 * sq * cq


@jit
def _sc(s, x):
    """``s / x`` (a sinc from its sine), 1 at ``x = 0``."""
    return s / x if x != 0.0 else 1.0


@jit
def _theta(ld):
    """``cos, sin(W ts - phi)``."""
    return ld.c0 * ld.cphi + ld.s0 * ld.sphi, ld.s0 * ld.cphi - ld.c0 * ld.sphi


@jit
def _decompose(mode, W, thc, ths, z):
    """``A, B, Cc, Cs`` of the undamped velocity ``A cos wu + B sin wu + Cc cos Wu + Cs sin Wu`` (Eqs. (15)-(17));
    ``thc, ths = cos, sin(W ts - phi)``."""
    w, f, eta0, v0 = mode.w, mode.f, z.eta, z.v
    d = (w + W) * (w - W)
    g = f / d if d != 0 else inf
    Cc = -g * W * ths
    Cs = -g * W * thc
    return v0 - Cc, g * w * thc - w * eta0, Cc, Cs


@jit
def _psi_undamped(mode, ld, u, z, hf):
    """Closed-form ``Psi`` of an undamped mode and its cancellation factor (:func:`plbar.response.psi_closed_form`)."""
    w, W, cb, sb = mode.w, ld.W, hf.cW, hf.sW
    thc, ths = _theta(ld)
    A, B, Cc, Cs = _decompose(mode, W, thc, ths, z)
    wp, wm = w + W, w - W
    ht = 0.5 * u
    wt, Wt, pt, mt = w * u, W * u, wp * ht, wm * ht
    sw1, sw2, sW1, sW2, sp1, sp2, sm1, sm2 = _sines(w, W, u, cb, sb)
    s2w, s2W, sm, sp = _sc(sw2, 2 * wt), _sc(sW2, 2 * Wt), _sc(sm2, 2 * mt), _sc(sp2, 2 * pt)
    s1w, s1W, sph, smh = _sc(sw1, wt), _sc(sW1, Wt), _sc(sp1, pt), _sc(sm1, mt)
    AA, BB, CC, SS = A * A, B * B, Cc * Cc, Cs * Cs
    ACc, BCs, ACs, BCc = A * Cc, B * Cs, A * Cs, B * Cc
    p = (ht * ((AA + BB + CC + SS) + (AA - BB) * s2w + (CC - SS) * s2W + 2 * (ACc + BCs) * sm
               + 2 * (ACc - BCs) * sp)
         + u * u * (A * B * w * s1w * s1w + Cc * Cs * W * s1W * s1W + 0.5 * ((ACs + BCc) * wp * sph * sph
                                                                           + (BCc - ACs) * wm * smh * smh)))
    scale = (abs(A) + abs(B) + abs(Cc) + abs(Cs)) ** 2 * u
    return p, (scale / p if p > 0 else inf)


@jit
def _work_undamped(mode, ld, u, z, hf):
    """Closed-form work of the load on an undamped mode and its cancellation factor (:mod:`plbar.response.power`)."""
    w, f, W, cb, sb, eta0, v0 = mode.w, mode.f, ld.W, hf.cW, hf.sW, z.eta, z.v
    thc, ths = _theta(ld)
    A, B, Cc, Cs = _decompose(mode, W, thc, ths, z)
    wp, wm = w + W, w - W
    _, _, sW1, sW2, sp1, sp2, sm1, sm2 = _sines(w, W, u, cb, sb)
    cm, cp = u * _sc(sm2, wm * u), u * _sc(sp2, wp * u)
    hp, hm = 0.5 * wp * u * u * _sc(sp1, 0.5 * wp * u) ** 2, 0.5 * wm * u * u * _sc(sm1, 0.5 * wm * u) ** 2
    c2 = u * _sc(sW2, 2 * W * u)
    sW = _sc(sW1, W * u)
    scW = 0.5 * W * u * u * sW * sW
    cos_v = A * 0.5 * (cm + cp) + B * 0.5 * (hp + hm) + Cc * 0.5 * (u + c2) + Cs * scW
    sin_v = A * 0.5 * (hp - hm) + B * 0.5 * (cm - cp) + Cc * scW + Cs * 0.5 * (u - c2)
    work = f * (thc * cos_v - ths * sin_v)
    scale = (w * w * eta0 * eta0 + v0 * v0) ** 0.5 + abs(f) * u
    num = abs(A) + abs(B) + abs(Cc) + abs(Cs)
    cancel = num / scale if scale > 0 else (inf if num > 0 else 0.0)
    return work, (cancel if isfinite(work) else inf)


@jit
def _terms(mode, ld, st):
    """The damped velocity ``A1 e^{yu} + A2 e^{zu} + B e^{iWu} + cc`` from the state ``st``:
    ``(y, z, A1, A2, B, th, singular)``."""
    w, f, W, c0, s0, cphi, sphi, eta0, v0 = mode.w, mode.f, ld.W, ld.c0, ld.s0, ld.cphi, ld.sphi, st.eta, st.v
    y, z, a, _ = roots(w, mode.zeta)
    den = complex(w * w - W * W, 2.0 * a * W)
    sing = den == 0 or y == z
    H = 1.0 / den if not sing else 1.0 + 0j
    th = complex(c0, s0) * complex(cphi, -sphi)          # e^{i (W ts - phi)}
    P = f * H * th
    B = 0.5j * W * P
    h0 = eta0 - P.real
    hv0 = v0 - 2.0 * B.real
    hd0 = -w * w * h0 - 2.0 * a * hv0
    dl = y - z if not sing else 1.0 + 0j
    return y, z, (hd0 - z * hv0) / dl, (y * hv0 - hd0) / dl, B, th, sing


@jit
def _F(m, u):
    """``int_0^u e^{m s} ds``."""
    return u * phi1(m * u)


@jit
def _psi_damped(mode, ld, u, st):
    """Closed-form ``Psi`` of a damped mode and its cancellation factor
    (:func:`plbar.response.damped.psi_closed_form`)."""
    y, z, A1, A2, B, _, sing = _terms(mode, ld, st)
    if sing:
        return 0.0, inf
    iW = complex(0.0, ld.W)
    Bc = B.conjugate()
    t = (A1 * A1 * _F(2 * y, u), 2 * A1 * A2 * _F(y + z, u), A2 * A2 * _F(2 * z, u), 2 * A1 * B * _F(y + iW, u),
         2 * A1 * Bc * _F(y - iW, u), 2 * A2 * B * _F(z + iW, u), 2 * A2 * Bc * _F(z - iW, u),
         complex(2 * (B * B * _F(2 * iW, u)).real, 0.0), complex(2 * (B * Bc).real * u, 0.0))
    p, size = 0.0, 0.0
    for x in t:
        p += x.real
        size += abs(x)
    return p, (size / p if p > 0 else inf)


@jit
def _work_damped(mode, ld, u, st):
    """Closed-form work of the load on a damped mode, and its cancellation factor (:mod:`plbar.response.damped`)."""
    y, z, A1, A2, B, th, sing = _terms(mode, ld, st)
    if sing:
        return 0.0, inf
    w, f, eta0, v0 = mode.w, mode.f, st.eta, st.v
    iW = complex(0.0, ld.W)
    thc, Bc = th.conjugate(), B.conjugate()
    t = (th * A1 * _F(y + iW, u), th * A2 * _F(z + iW, u), th * B * _F(2 * iW, u), th * Bc * u,
         thc * A1 * _F(y - iW, u), thc * A2 * _F(z - iW, u), thc * B * u, thc * Bc * _F(-2 * iW, u))
    s, size = 0.0, 0.0
    for x in t:
        s += x.real
        size += abs(x)
    work, size = 0.5 * f * s, 0.5 * abs(f) * size
    scale = abs(f) * (abs(v0) + abs(w * eta0) + abs(f) * u) * u
    return work, (size / scale if scale > 0 else (inf if size > 0 else 0.0))


@jit
def _rule(k):
    """Pieces ``p`` and the row of the ``n``-point rule for an integrand of total phase ``k`` (<= 100 nodes a piece)."""
    p = max(1, int(ceil(k / 100.0)))
    n = 20 * int(ceil((ceil(0.6 * k / p) + 40) / 20))
    return p, n, n // 20 - 2


@jit
def _quadrature(mode, ld, u, z, damping, k, of_work):
    """Composite Gauss-Legendre of ``eta'^2`` (or of the load's power) over ``[0, u]`` for total phase ``k``."""
    f, W, c0, s0, cphi, sphi = mode.f, ld.W, ld.c0, ld.s0, ld.cphi, ld.sphi
    p, n, row = _rule(k)
    h = u / p
    acc = 0.0
    for i in range(p):
        for j in range(n):
            s = h * (i + 0.5 * (GL_X[row, j] + 1.0))
            _, v = mode_flow(mode, ld, s, z, half(W, s), damping)
            if of_work:      # cos(W (ts + s) - phi)
                cw, sw = cos(W * s), sin(W * s)
                v = v * f * (cphi * (c0 * cw - s0 * sw) + sphi * (s0 * cw + c0 * sw))
            else:
                v = v * v
            acc += GL_W[row, j] * v
    return 0.5 * h * acc


@jit
def _rate(w, zeta):
    """The fastest rate of a mode, ``max |lambda|`` (``w`` undamped; the fast root if over-damped)."""
    y, z, _, _ = roots(w, zeta)
    return max(abs(y), abs(z))


@jit
def psi(mode, ld, u, z, damping, hf):
    """``Psi = int_0^u eta'^2`` of ``mode`` over a piece of length ``u`` from ``z`` (Eq. (20)): closed form, or
    quadrature where it cancels.

    ``hf = half(W, u)`` (once per piece)."""
    if mode.g == 0.0:
        if damping is not None:
            p, cancel = _psi_damped(mode, ld, u, z)
        else:
            p, cancel = _psi_undamped(mode, ld, u, z, hf)
        if cancel < CANCEL_LIMIT:
            return p
    return _quadrature(mode, ld, u, z, damping, 2 * max(_rate(mode.w, mode.zeta), ld.W) * u, False)


@jit
def work(mode, ld, u, z, damping, hf):
    """Work of the load on ``mode`` over a piece: closed form, or quadrature where it cancels (arguments as for
    :func:`psi`)."""
    if mode.g == 0.0:
        if damping is not None:
            p, cancel = _work_damped(mode, ld, u, z)
        else:
            p, cancel = _work_undamped(mode, ld, u, z, hf)
        if cancel < CANCEL_LIMIT:
            return p
    W = ld.W
    return _quadrature(mode, ld, u, z, damping, 2 * (max(_rate(mode.w, mode.zeta), W) + W) * u, True)
