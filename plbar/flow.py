"""Closed-form flow of forced undamped modal oscillators (pure functions).

Each modal coordinate obeys ``eta'' + w^2 eta = f cos(W t - phi)`` (Eq. (1) in
modal form).  Over a segment that starts at ``t_s`` with ``eta0, v0`` the exact
solution is written with the Duhamel kernels

``C(tau) = (cos W tau - cos w tau) / (w^2 - W^2)``,
``S(tau) = (w sin W tau - W sin w tau) / (w (w^2 - W^2))``,

evaluated in a factorised ``sinc`` form that stays exact at and near
resonance ``W = w`` (the limit ``tau sin(w tau) / (2 w)``), so no term ever
divides by ``w - W`` (FORMULATION §2).  This is Appendix 1 rearranged: the
free-vibration amplitudes ``a, b`` of Eqs. (26)-(27) are ``eta0`` and ``v0/w``
after subtracting the particular solution, here folded into ``C`` and ``S``.

All functions broadcast over leading axes.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["kernels", "forced_coeffs", "segment", "psi", "psi_closed_form", "psi_quadrature", "sinc"]


def sinc(x):
    """``sin(x) / x`` with the value 1 at 0."""
    x = np.asarray(x, float)
    small = np.abs(x) < 1e-4
    xs = np.where(small, 1.0, x)
    return np.where(small, 1.0 - x * x / 6.0, np.sin(xs) / xs)


def kernels(w, W, tau):
    """Duhamel kernels ``C, S, C'`` at ``tau`` (``S' = W C``).

    Parameters
    ----------
    w : array_like
        Natural circular frequency of the mode(s), > 0.
    W : array_like
        Forcing circular frequency, > 0.
    tau : array_like
        Time since the segment start.

    Returns
    -------
    C, S, Cp : ndarray
        Broadcast shapes of the inputs.
    """
    sig = 0.5 * (w + W) * tau
    snc = tau * sinc(0.5 * (w - W) * tau)
    cs = np.cos(sig)
    C = np.sin(sig) / (w + W) * snc
    S = (np.sin(w * tau) / w - cs * snc) / (w + W)
    Cp = (w * cs * snc + np.sin(W * tau)) / (w + W)
    return C, S, Cp


def forced_coeffs(w, f, W, ts, tau):
    """Forced part of a segment, split into its ``cos(phi)`` and ``sin(phi)`` parts.

    The forced response at ``ts + tau`` from rest is
    ``eta_F = eta_c cos(phi) + eta_s sin(phi)`` and likewise for the velocity.

    Returns
    -------
    eta_c, eta_s, v_c, v_s : ndarray
    """
    C, S, Cp = kernels(w, W, tau)
    c0, s0 = np.cos(W * ts), np.sin(W * ts)
    return (f * (c0 * C - s0 * S), f * (s0 * C + c0 * S),
            f * (c0 * Cp - s0 * W * C), f * (s0 * Cp + c0 * W * C))


def segment(w, f, W, ts, tau, eta0, v0, cphi, sphi):
    """Exact modal displacement and velocity at ``ts + tau``.

    ``cphi, sphi`` are ``cos(phi), sin(phi)`` of the forcing phase.
    """
    co, si = np.cos(w * tau), np.sin(w * tau)
    ec, es, vc, vs = forced_coeffs(w, f, W, ts, tau)
    eta = co * eta0 + si / w * v0 + ec * cphi + es * sphi
    v = -w * si * eta0 + co * v0 + vc * cphi + vs * sphi
    return eta, v


def _icc(a, b, t):
    return 0.5 * t * (sinc((a - b) * t) + sinc((a + b) * t))


def _iss(a, b, t):
    return 0.5 * t * (sinc((a - b) * t) - sinc((a + b) * t))


def _omc(x, t):
    """``(1 - cos(x t)) / x``, exact at ``x = 0``."""
    return 0.5 * x * t * t * sinc(0.5 * x * t) ** 2


def _ics(a, b, t):
    """``int_0^t cos(a u) sin(b u) du``."""
    return 0.5 * (_omc(a + b, t) - _omc(a - b, t))


def psi_closed_form(w, f, W, ts, tau, eta0, v0, cphi, sphi):
    """Closed-form ``Psi = int_0^tau etadot^2`` (Eq. (20), Appendix 2).

    The velocity is written as ``A cos w u + B sin w u + Cc cos W u + Cs sin W u``
    (Eqs. (15)-(17)) and the products are integrated exactly (Eqs. (28)-(33),
    with the ``W/w`` factor of Appendix 1 restored, FORMULATION §2).

    Returns
    -------
    psi : ndarray
    cancel : ndarray
        Cancellation factor ``(|A|+|B|+|Cc|+|Cs|)^2 tau / psi``; large near
        resonance, where :func:`psi` switches to quadrature.
    """
    th_c = np.cos(W * ts) * cphi + np.sin(W * ts) * sphi     # cos(W ts - phi)
    th_s = np.sin(W * ts) * cphi - np.cos(W * ts) * sphi     # sin(W ts - phi)
    d = w * w - W * W
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        g = np.where(d != 0, f / np.where(d != 0, d, 1.0), np.inf)
        A = v0 + g * W * th_s
        B = -w * eta0 + g * w * th_c
        Cc = -g * W * th_s
        Cs = -g * W * th_c
        psi = (A * A * _icc(w, w, tau) + B * B * _iss(w, w, tau) + Cc * Cc * _icc(W, W, tau)
               + Cs * Cs * _iss(W, W, tau) + 2 * A * B * _ics(w, w, tau) + 2 * A * Cc * _icc(w, W, tau)
               + 2 * A * Cs * _ics(w, W, tau) + 2 * B * Cc * _ics(W, w, tau) + 2 * B * Cs * _iss(w, W, tau)
               + 2 * Cc * Cs * _ics(W, W, tau))
        scale = (np.abs(A) + np.abs(B) + np.abs(Cc) + np.abs(Cs)) ** 2 * tau
        cancel = np.where(psi > 0, scale / psi, np.inf)
    return psi, cancel


@lru_cache(maxsize=64)
def gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1] (cached)."""
    x, w = np.polynomial.legendre.leggauss(int(n))
    x.setflags(write=False)
    w.setflags(write=False)
    return x, w


def psi_quadrature(w, f, W, ts, tau, eta0, v0, cphi, sphi, n=None):
    """``int_0^tau etadot^2`` by Gauss-Legendre on the exact velocity.

    The integrand is a trigonometric polynomial of frequency at most
    ``2 max(w, W)``; ``n`` nodes are chosen so the rule is exact to round-off.
    """
    w, f, W, ts, tau, eta0, v0, cphi, sphi = np.broadcast_arrays(w, f, W, ts, tau, eta0, v0, cphi, sphi)
    if n is None:
        k = float(np.max(2 * np.maximum(w, W) * tau)) if w.size else 0.0
        n = int(np.ceil(0.6 * k)) + 40
        n = 20 * int(np.ceil(n / 20))
    x, wt = gauss(n)
    u = 0.5 * tau[..., None] * (x + 1)
    _, v = segment(w[..., None], f[..., None], W[..., None], ts[..., None], u,
                   eta0[..., None], v0[..., None], cphi[..., None], sphi[..., None])
    return 0.5 * tau * np.sum(wt * v * v, axis=-1)


CANCEL_LIMIT = 1e4


def psi(w, f, W, ts, tau, eta0, v0, cphi, sphi):
    """``Psi`` of Eq. (20): closed form, or quadrature where it would cancel.

    Returns
    -------
    psi : ndarray
    closed : ndarray of bool
        True where the closed form was used (False near resonance).
    """
    p, cancel = psi_closed_form(w, f, W, ts, tau, eta0, v0, cphi, sphi)
    bad = ~(cancel < CANCEL_LIMIT)
    if np.any(bad):
        b = np.broadcast_arrays(w, f, W, ts, tau, eta0, v0, cphi, sphi)
        q = psi_quadrature(*[a[bad] for a in b])
        p = np.array(p, copy=True)
        p[bad] = q
    return p, ~bad
