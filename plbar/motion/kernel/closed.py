"""Closed-form flow of one modal oscillator, compiled (the kernel's scalar form of :mod:`plbar.response`).

Each mode obeys ``eta'' + 2 zeta w eta' + w^2 eta = f cos(W t - phi) + g`` (Eq. (1) in modal
form; ``zeta = 0`` undamped; ``g`` a constant load's acceleration, on a rigid-body mode only, where
``zeta = 0`` too: it adds ``g u^2 / 2`` and ``g u``, and 0 changes no double).  Over a segment that starts
at ``ts`` with ``eta0, v0`` its state at ``ts + u`` is the free flow plus the Duhamel kernels ``C, S, C'`` (Appendix 1,
Eqs. (26)-(27)), written as in :func:`plbar.response.flow.kernels`: undamped in the
factorised ``sinc`` form that stays exact at and near resonance ``W = w``; damped with
the divided differences of :mod:`plbar.response.damped` (exact through critical damping).

These are the formulas of the batched numpy functions of :mod:`plbar.response` (which the
periodic solver uses), one mode at a time; the tests hold the two to round-off.  The
undamped kernels take their sines and cosines from the half angles ``w u / 2`` and
``W u / 2`` (two calls a mode instead of six; ``sin((w - W) u / 2)`` directly where it is
small, so the ``sinc`` keeps its relative accuracy).  ``c0, s0`` are ``cos W ts, sin W ts``
(once per segment), ``cphi, sphi`` those of the forcing phase: a :class:`.data.Forcing` ``ld``; a mode is a
:class:`.data.Mode`, its state at the segment's start a :class:`.data.ModeState`, the forcing's half angle at a
point a :class:`.data.Half`.
"""

from __future__ import annotations

import cmath
from math import cos, cosh, exp, sin, sinh, sqrt

from .data import Half
from .jit import jit

__all__ = [
    "add",
    "damped_flow",
    "damped_free",
    "damped_kernels",
    "flow",
    "half",
    "kernels",
    "matvec",
    "mode_flow",
    "phi1",
    "roots",
    "sinc",
    "sinw",
]

SERIES = 20   #: terms of the phi_1 and kernel series (|x| < 1: error below 1e-19)
DIRECT = 0.7  #: below this |(w - W) u / 2| its sine is taken directly (the angle difference would cancel)


@jit
def sinc(x):
    """``sin(x) / x`` with the value 1 at 0."""
    return sin(x) / x if x != 0.0 else 1.0


@jit
def sinw(si, w, u):
    """``sin(w u) / w`` from ``si = sin(w u)``: ``u`` at ``w = 0`` (a rigid-body mode, whose free flow is
    ``eta0 + v0 u``; every other closed form here holds at ``w = 0`` as it is)."""
    return si / w if w != 0.0 else u


@jit
def half(W, u):
    """The :class:`.data.Half` at ``u``: ``cos, sin`` of ``W u / 2`` and ``sin W u``, the forcing's share of
    :func:`kernels` (once per point)."""
    c, s = cos(0.5 * W * u), sin(0.5 * W * u)
    return Half(c, s, 2.0 * s * c)


@jit
def kernels(w, W, u, hf):
    """Undamped Duhamel kernels ``C, S, C'`` at ``u`` and ``cos w u, sin w u`` (:func:`plbar.response.kernels`).

    ``hf`` from :func:`half`.  ``C = sin(s) snc / (w + W)``, ``S = (sin(w u) / w - cos(s) snc) / (w + W)``,
    ``C' = (w cos(s) snc + sin(W u)) / (w + W)`` with ``s = (w + W) u / 2``, ``snc = u sinc((w - W) u / 2)``.
    """
    a = 0.5 * w * u
    return kernels_at(w, W, u, cos(a), sin(a), hf)


@jit
def kernels_at(w, W, u, ca, sa, hf):
    """:func:`kernels` from ``ca, sa = cos, sin(w u / 2)`` as well (rotated from sample to sample by a caller)."""
    cW, sW, sWu = hf
    dl = 0.5 * (w - W) * u
    sdl = sin(dl) if abs(dl) < DIRECT else sa * cW - ca * sW
    snc = u * (sdl / dl if dl != 0.0 else 1.0)
    wp = w + W
    csn = (ca * cW - sa * sW) * snc
    si = 2.0 * sa * ca
    return (sa * cW + ca * sW) * snc / wp, (sinw(si, w, u) - csn) / wp, (w * csn + sWu) / wp, 1.0 - 2.0 * sa * sa, si


@jit
def flow(mode, ld, u, z, hf):
    """``eta, eta'`` of the undamped ``mode`` at ``u`` into a segment of forcing ``ld`` from ``z``
    (:func:`plbar.response.segment`)."""
    a = 0.5 * mode.w * u
    return flow_at(mode, ld, u, z, cos(a), sin(a), hf)


@jit
def flow_at(mode, ld, u, z, ca, sa, hf):
    """:func:`flow` from ``ca, sa = cos, sin(w u / 2)`` as well."""
    w, f, W, c0, s0, cphi, sphi, eta0, v0 = mode.w, mode.f, ld.W, ld.c0, ld.s0, ld.cphi, ld.sphi, z.eta, z.v
    C, S, Cp, co, si = kernels_at(w, W, u, ca, sa, hf)
    ec, es = f * (c0 * C - s0 * S), f * (s0 * C + c0 * S)
    vc, vs = f * (c0 * Cp - s0 * W * C), f * (s0 * Cp + c0 * W * C)
    return (co * eta0 + sinw(si, w, u) * v0 + ec * cphi + es * sphi + 0.5 * mode.g * u * u,
            -w * si * eta0 + co * v0 + vc * cphi + vs * sphi + mode.g * u)


@jit
def phi1(x):
    """``(exp(x) - 1) / x`` for complex ``x`` (1 at 0): a series for ``|x| < 1``, the quotient otherwise."""
    if abs(x) < 1.0:
        s = 1.0 + 0j
        for k in range(SERIES + 1, 1, -1):
            s = 1.0 + s * x / k
        return s
    return (cmath.exp(x) - 1.0) / x


@jit
def roots(w, zeta):
    """``(y, z, a, d)`` of :func:`plbar.response.damped.roots`: the roots, ``y`` nearest the imaginary axis."""
    a = zeta * w
    d = w * w * (1.0 - zeta) * (1.0 + zeta)
    q = sqrt(abs(d))
    r2 = a + q
    r1 = w * w / r2 if r2 > 0 else 0.0
    if d > 0:
        return complex(-a, q), complex(-a, -q), a, d
    return complex(-r1, 0.0), complex(-r2, 0.0), a, d


@jit
def damped_free(w, zeta, u):
    """``ss = e[l1, l2]``, ``p11, p22`` (the free flow's stable forms) and the roots (``_cs`` of :mod:`.damped`)."""
    y, z, a, d = roots(w, zeta)
    q = sqrt(abs(d))
    x = q * u
    ea = exp(-a * u)
    if d > 0:
        cc, ss = ea * cos(x), ea * u * sinc(x)
        return ss, cc + a * ss, cc - a * ss, y, z
    if x < 1.0:                          # critical neighbourhood
        cc = ea * cosh(x)
        ss = ea * u * (sinh(x) / x if x > 0 else 1.0)
        return ss, cc + a * ss, cc - a * ss, y, z
    r1, r2, k2 = -y.real, -z.real, 2.0 * q     # over-damped, k u >= 1: two real exponentials
    e1, e2 = exp(-r1 * u), exp(-r2 * u)
    return (e1 - e2) / k2, (r2 * e1 - r1 * e2) / k2, (r2 * e2 - r1 * e1) / k2, y, z


@jit
def _kernel_series(p, y, z, u):
    """``e[p, y, z]`` of ``exp(. u)`` by its Taylor series (``max(|p|, |y|, |z|) u < 1/2``)."""
    A, Bk, Ck = 1.0 + 0j, 1.0 + 0j, 1.0 + 0j
    term = u * u / 2.0
    out = term * Ck
    for k in range(1, SERIES + 1):
        A = A * p
        Bk = y * Bk + A
        Ck = z * Ck + Bk
        term = term * u / (k + 2)
        out = out + term * Ck
    return out


@jit
def damped_kernels(w, W, u, zeta):
    """Damped Duhamel kernels ``C, S, C'`` and the free flow ``p11, ss, p22``
    (:func:`plbar.response.damped.kernels`)."""
    ss, p11, p22, y, z = damped_free(w, zeta, u)
    p = complex(0.0, W)
    if max(max(W, abs(y)), abs(z)) * u < 0.5:
        K = _kernel_series(p, y, z, u)
    else:
        x = (p - y) * u
        if abs(x) < 1.0:
            dpy = u * cmath.exp(y * u) * phi1(x)
        else:
            dpy = (cmath.exp(p * u) - cmath.exp(y * u)) / (p - y)
        K = (dpy - ss) / (p - z)
    return K.real, K.imag, ss - W * K.imag, p11, ss, p22


@jit
def damped_flow(mode, ld, u, z):
    """``eta, eta'`` of a damped ``mode`` at ``u`` into a segment of forcing ``ld`` from ``z``
    (:func:`plbar.response.segment` with ``zeta``)."""
    w, f, W, c0, s0, cphi, sphi, eta0, v0 = mode.w, mode.f, ld.W, ld.c0, ld.s0, ld.cphi, ld.sphi, z.eta, z.v
    C, S, Cp, p11, ss, p22 = damped_kernels(w, W, u, mode.zeta)
    ec, es = f * (c0 * C - s0 * S), f * (s0 * C + c0 * S)
    vc, vs = f * (c0 * Cp - s0 * W * C), f * (s0 * Cp + c0 * W * C)
    return (p11 * eta0 + ss * v0 + ec * cphi + es * sphi + 0.5 * mode.g * u * u,
            -w * w * ss * eta0 + p22 * v0 + vc * cphi + vs * sphi + mode.g * u)


@jit
def mode_flow(mode, ld, u, z, hf, damping):
    """:func:`damped_flow` where ``damping`` is given (``mode.zeta`` used), else :func:`flow` (``hf`` from
    :func:`half`; compiled only if used)."""
    if damping is None:
        return flow(mode, ld, u, z, hf)
    return damped_flow(mode, ld, u, z)


@jit
def matvec(A, x, out):
    """``out = A x`` (a plain loop: no BLAS threads under the kernel's own; the switch maps of the simulator and of
    the chain)."""
    for i in range(A.shape[0]):
        acc = 0.0
        for j in range(A.shape[1]):
            acc += A[i, j] * x[j]
        out[i] = acc


@jit
def add(x, a):
    """``x[:a.size] += a`` (a switch's offset, a gap's static equilibria, in the simulator and the chain: zeros
    without a gap, which change no double)."""
    for i in range(a.size):
        x[i] += a[i]
