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

``Psi`` (:func:`psi` and its closed form and quadrature) takes the modes and the forcing as two records,
:class:`~.records.Modes` ``(w, f, zeta)`` and :class:`~.records.Forcing` ``(W, cos phi, sin phi)``.

**Damping** (FORMULATION §8).  Every function takes an optional per-mode damping
ratio ``zeta`` (broadcast like ``w``; ``Modes.zeta``): with it each mode is the damped oscillator
``eta'' + 2 zeta w eta' + w^2 eta = f cos(W t - phi)``, in closed form for the
under-, critically and over-damped modes alike (:mod:`plbar.response.damped`).
``zeta=None`` (the default) is the undamped code path, unchanged bit for bit;
``zeta = 0`` gives the same numbers to round-off.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from . import damped as _damped
from .records import Forcing, Modes, broadcast

__all__ = ["sin_over", "free_flow", "flow_matrix", "kernels", "forced_coeffs", "segment", "psi", "psi_closed_form",
           "psi_quadrature", "sinc", "gauss", "CANCEL_LIMIT"]


def sinc(x):
    """``sin(x) / x`` with the value 1 at 0.

    ``sin`` is correctly rounded near 0 (``sin(x) = x`` in floating point for
    ``|x| < 1e-8``), so the quotient is accurate to round-off for every ``x != 0``.
    """
    x = np.asarray(x, float)
    return np.divide(np.sin(x), x, out=np.ones_like(x), where=x != 0)


def sin_over(w, tau, si=None):
    """``sin(w tau) / w``, and its limit ``tau`` where ``w = 0`` (a rigid-body mode of a free body or a cracked bar's
    floating part: its free flow is ``eta0 + v0 tau``, FORMULATION §9).

    ``si`` is ``sin(w tau)`` if the caller has it.  Where every ``w`` is non-zero it is ``si / w`` itself (the same
    bits as before rigid modes were taken).
    """
    si = np.sin(w * tau) if si is None else si
    w = np.asarray(w, float)
    if np.all(w != 0.0):
        return si / w
    shape = np.broadcast(w, tau, si).shape
    out = np.array(np.broadcast_to(tau, shape), float)
    return np.divide(si, w, out=out, where=np.broadcast_to(w != 0.0, shape))


def free_flow(w, tau, zeta=None):
    """The free modal flow over ``tau``: ``[[cos w tau, sin w tau / w], [-w sin w tau, cos w tau]]``.

    The homogeneous part of Appendix 1 (Eqs. (26)-(27) without the load),
    used by the one-period map, the orbits and the Floquet monodromy alike.

    Returns
    -------
    co, si_w, mwsi, si : ndarray
        ``cos w tau``, ``sin w tau / w``, ``-w sin w tau`` (the matrix entries,
        row by row, with ``co`` on the diagonal) and ``sin w tau`` (for the
        Duhamel kernels of :func:`kernels`).
    p11, p12, p21, p22 : ndarray
        With ``zeta``: the four entries of the damped flow matrix
        ``exp(tau [[0, 1], [-w^2, -2 zeta w]])`` row by row (the diagonal entries
        differ under damping).  :func:`flow_matrix` returns the four entries in
        both cases.
    """
    if zeta is not None:
        return _damped.flow_matrix(w, zeta, tau)
    wt = w * tau
    co, si = np.cos(wt), np.sin(wt)
    return co, sin_over(w, tau, si), -w * si, si


def flow_matrix(w, tau, zeta=None):
    """The entries ``p11, p12, p21, p22`` of the free modal flow over ``tau``, damped or not.

    ``eta(tau) = p11 eta0 + p12 v0`` and ``eta'(tau) = p21 eta0 + p22 v0``.
    """
    if zeta is not None:
        return _damped.flow_matrix(w, zeta, tau)
    co, si_w, mwsi, _ = free_flow(w, tau)
    return co, si_w, mwsi, co


def kernels(w, W, tau, swt=None, zeta=None):
    """Duhamel kernels ``C, S, C'`` at ``tau`` (``S' = W C``).

    Parameters
    ----------
    w : array_like
        Natural circular frequency of the mode(s), >= 0 (0: a rigid-body mode).
    W : array_like
        Forcing circular frequency, > 0.
    tau : array_like
        Time since the segment start.
    swt : array_like, optional
        ``sin(w tau)`` if the caller has it already (undamped only).
    zeta : array_like, optional
        Damping ratio of the mode(s): the kernels of the damped oscillator
        (:func:`plbar.response.damped.kernels`; ``S' = W C`` still holds).

    Returns
    -------
    C, S, Cp : ndarray
        Broadcast shapes of the inputs.
    """
    if zeta is not None:
        return _damped.kernels(w, W, tau, zeta)
    wp = w + W
    ht = 0.5 * tau
    snc = tau * sinc((w - W) * ht)
    sig = wp * ht
    csn = np.cos(sig) * snc
    C = np.sin(sig) * snc / wp
    S = (sin_over(w, tau, swt) - csn) / wp
    Cp = (w * csn + np.sin(W * tau)) / wp
    return C, S, Cp


def forced_coeffs(w, f, W, ts, tau, zeta=None):
    """Forced part of a segment, split into its ``cos(phi)`` and ``sin(phi)`` parts.

    The forced response at ``ts + tau`` from rest is
    ``eta_F = eta_c cos(phi) + eta_s sin(phi)`` and likewise for the velocity
    (damped modes with ``zeta``).

    Returns
    -------
    eta_c, eta_s, v_c, v_s : ndarray
    """
    C, S, Cp = kernels(w, W, tau, zeta=zeta)
    c0, s0 = np.cos(W * ts), np.sin(W * ts)
    return (f * (c0 * C - s0 * S), f * (s0 * C + c0 * S),
            f * (c0 * Cp - s0 * W * C), f * (s0 * Cp + c0 * W * C))


def segment(w, f, W, ts, tau, eta0, v0, cphi, sphi, zeta=None, accel=None):
    """Exact modal displacement and velocity at ``ts + tau``.

    ``cphi, sphi`` are ``cos(phi), sin(phi)`` of the forcing phase; ``zeta``
    (optional) the damping ratio of each mode; ``accel`` (optional) each mode's
    constant acceleration ``g`` (a constant load on a rigid-body mode,
    :attr:`plbar.model.Statics.accel`): ``g tau^2 / 2`` and ``g tau`` added.
    """
    if zeta is not None:
        p11, p12, p21, p22 = _damped.flow_matrix(w, zeta, tau)
        ec, es, vc, vs = forced_coeffs(w, f, W, ts, tau, zeta)
        eta, v = (p11 * eta0 + p12 * v0 + ec * cphi + es * sphi,
                  p21 * eta0 + p22 * v0 + vc * cphi + vs * sphi)
    else:
        co, si_w, mwsi, _ = free_flow(w, tau)
        ec, es, vc, vs = forced_coeffs(w, f, W, ts, tau)
        eta = co * eta0 + si_w * v0 + ec * cphi + es * sphi
        v = mwsi * eta0 + co * v0 + vc * cphi + vs * sphi
    if accel is None:
        return eta, v
    tau = np.asarray(tau, float)
    return eta + 0.5 * accel * tau * tau, v + accel * tau


def psi_closed_form(modes: Modes, forcing: Forcing, ts, tau, eta0, v0):
    """Closed-form ``Psi = int_0^tau etadot^2`` (Eq. (20), Appendix 2) of the ``modes`` under ``forcing``, over
    the segment ``[ts, ts + tau]`` from the modal state ``eta0, v0``.

    The velocity is written as ``A cos w u + B sin w u + Cc cos W u + Cs sin W u``
    (Eqs. (15)-(17)) and the products are integrated exactly (Eqs. (28)-(33),
    with the ``W/w`` factor of Appendix 1 restored, FORMULATION §2).

    Returns
    -------
    psi : ndarray
    cancel : ndarray
        Cancellation factor ``(|A|+|B|+|Cc|+|Cs|)^2 tau / psi``; large near
        resonance, where :func:`psi` switches to quadrature.

    With ``modes.zeta``: the damped closed form of :func:`plbar.response.damped.psi_closed_form`.
    """
    if modes.zeta is not None:
        return _damped.psi_closed_form(modes, forcing, ts, tau, eta0, v0)
    w, f, W, cphi, sphi = modes.w, modes.f, forcing.W, forcing.cphi, forcing.sphi
    cw, sw = np.cos(W * ts), np.sin(W * ts)
    th_c = cw * cphi + sw * sphi     # cos(W ts - phi)
    th_s = sw * cphi - cw * sphi     # sin(W ts - phi)
    wp, wm = w + W, w - W
    d = wp * wm
    # exact resonance (d = 0): g = inf, psi = nan or inf and the quadrature takes over (see psi)
    with np.errstate(invalid="ignore", over="ignore"):
        g = np.divide(f, d, out=np.full(np.broadcast(f, d).shape, np.inf), where=d != 0)
        Cc = -g * W * th_s
        Cs = -g * W * th_c
        A = v0 - Cc
        B = g * w * th_c - w * eta0
        # every sinc the ten product integrals need, in one call (Eqs. (28)-(33)):
        # sinc(2wt), sinc(2Wt), sinc((w-W)t), sinc((w+W)t), sinc(wt), sinc(Wt), sinc((w+W)t/2), sinc((w-W)t/2)
        ht = 0.5 * tau
        wt, Wt, pt, mt = w * tau, W * tau, wp * ht, wm * ht
        args = [2 * wt, 2 * Wt, 2 * mt, 2 * pt, wt, Wt, pt, mt]
        if len({np.shape(a) for a in args}) > 1:
            args = np.broadcast_arrays(*args)
        s2w, s2W, sm, sp, s1w, s1W, sph, smh = sinc(np.array(args))
        # int_0^t of the ten products, grouped by kernel:
        # A^2 cos^2 wu + B^2 sin^2 wu + Cc^2 cos^2 Wu + Cs^2 sin^2 Wu + 2 A Cc cos wu cos Wu + 2 B Cs sin wu sin Wu
        #   -> ht [(A^2 + B^2 + Cc^2 + Cs^2) + (A^2 - B^2) sinc(2wt) + (Cc^2 - Cs^2) sinc(2Wt)
        #          + 2 (A Cc + B Cs) sinc((w-W)t) + 2 (A Cc - B Cs) sinc((w+W)t)]
        # 2 A B cos wu sin wu + 2 Cc Cs cos Wu sin Wu + 2 A Cs cos wu sin Wu + 2 B Cc sin wu cos Wu
        #   -> t^2 [A B w sinc(wt)^2 + Cc Cs W sinc(Wt)^2] + (A Cs + B Cc) (1 - cos (w+W)t) / (w+W)
        #      + (B Cc - A Cs) (1 - cos (w-W)t) / (w-W),  (1 - cos x t) / x = x t^2 sinc(x t / 2)^2 / 2
        AA, BB, CC, SS = A * A, B * B, Cc * Cc, Cs * Cs
        ACc, BCs, ACs, BCc = A * Cc, B * Cs, A * Cs, B * Cc
        tt = tau * tau
        psi = (ht * ((AA + BB + CC + SS) + (AA - BB) * s2w + (CC - SS) * s2W + 2 * (ACc + BCs) * sm
                     + 2 * (ACc - BCs) * sp)
               + tt * (A * B * w * s1w * s1w + Cc * Cs * W * s1W * s1W + 0.5 * ((ACs + BCc) * wp * sph * sph
                                                                                + (BCc - ACs) * wm * smh * smh)))
        scale = (np.abs(A) + np.abs(B) + np.abs(Cc) + np.abs(Cs)) ** 2 * tau
        cancel = np.divide(scale, psi, out=np.full(psi.shape, np.inf), where=psi > 0)
    return psi, cancel


@lru_cache(maxsize=64)
def gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1] (cached)."""
    x, w = np.polynomial.legendre.leggauss(int(n))
    x.setflags(write=False)
    w.setflags(write=False)
    return x, w


def psi_quadrature(modes: Modes, forcing: Forcing, ts, tau, eta0, v0, n=None):
    """``int_0^tau etadot^2`` by Gauss-Legendre on the exact velocity (the arguments of :func:`psi_closed_form`).

    Undamped, the integrand is a trigonometric polynomial of frequency at most
    ``2 max(w, W)``; ``n`` nodes are chosen so the rule is exact to round-off.

    With ``modes.zeta`` the integrand is a sum of exponentials ``e^{m u}`` with
    ``|m| <= 2 max(|lambda|, W)`` (``|lambda| = w`` under-damped, the fast root of an
    over-damped mode).  The interval is cut into ``p`` equal pieces with
    ``k = 2 max(|lambda|, W) tau / p <= 100``; mapped to ``[-1, 1]`` each exponential
    of a piece has ``|c| <= k / 2``, and the ``n``-point rule errs by at most
    ``|c|^{2n} 2^{2n+1} (n!)^4 / ((2n+1) ((2n)!)^3)``, about ``(e |c| / (4 n))^{2n}``,
    times the integrand's size on the piece: with ``n >= 0.6 k + 40`` that is below
    ``0.57^{80}`` (exact to round-off), and no piece needs more than 100 nodes.
    """
    modes, forcing, (ts, tau, eta0, v0) = broadcast(modes, forcing, ts, tau, eta0, v0)
    if modes.zeta is not None:
        return _psi_pieces(modes, forcing, ts, tau, eta0, v0)
    w, f, W, cphi, sphi = modes.w, modes.f, forcing.W, forcing.cphi, forcing.sphi
    if n is None:
        k = float(np.max(2 * np.maximum(w, W) * tau)) if w.size else 0.0
        n = int(np.ceil(0.6 * k)) + 40
        n = 20 * int(np.ceil(n / 20))
    x, wt = gauss(n)
    u = 0.5 * tau[..., None] * (x + 1)
    _, v = segment(w[..., None], f[..., None], W[..., None], ts[..., None], u,
                   eta0[..., None], v0[..., None], cphi[..., None], sphi[..., None])
    return 0.5 * tau * np.sum(wt * v * v, axis=-1)


def _psi_pieces(modes: Modes, forcing: Forcing, ts, tau, eta0, v0):
    """Composite Gauss-Legendre of the damped ``int_0^tau etadot^2`` (see :func:`psi_quadrature`; the arguments
    broadcast to one shape)."""
    w, f, zeta, W, cphi, sphi = modes.w, modes.f, modes.zeta, forcing.W, forcing.cphi, forcing.sphi
    k = float(np.max(2 * np.maximum(_damped.rate(w, zeta), W) * tau)) if w.size else 0.0
    p = max(1, int(np.ceil(k / 100.0)))
    n = 20 * int(np.ceil((int(np.ceil(0.6 * k / p)) + 40) / 20))
    x, wt = gauss(n)
    u = tau[..., None] / p * (np.arange(p)[:, None] + 0.5 * (x + 1)).ravel()    # p pieces of n nodes
    e = lambda a: a[..., None]  # noqa: E731
    _, v = segment(e(w), e(f), e(W), e(ts), u, e(eta0), e(v0), e(cphi), e(sphi), e(zeta))
    return 0.5 * tau / p * np.sum(np.tile(wt, p) * v * v, axis=-1)


CANCEL_LIMIT = 1e4   #: cancellation factor above which Psi is taken by quadrature (here and in .scalar)


def psi(modes: Modes, forcing: Forcing, ts, tau, eta0, v0):
    """``Psi`` of Eq. (20): closed form, or quadrature where it would cancel.

    ``modes`` (:class:`~.records.Modes`: ``w, f, zeta``) under ``forcing`` (:class:`~.records.Forcing`: ``W`` and
    the phase's ``cos, sin``), over the segment ``[ts, ts + tau]`` from the modal state ``eta0, v0``; every array
    broadcasts.  With ``modes.zeta`` (damped modes) the closed form cancels near resonance with
    little damping and near critical damping; quadrature (exact to round-off, see
    :func:`psi_quadrature`) takes over there.

    Returns
    -------
    psi : ndarray
    closed : ndarray of bool
        True where the closed form was used (False near resonance).
    """
    p, cancel = psi_closed_form(modes, forcing, ts, tau, eta0, v0)
    bad = ~(cancel < CANCEL_LIMIT)
    if np.any(bad):
        md, fc, rest = broadcast(modes, forcing, ts, tau, eta0, v0)
        q = psi_quadrature(md.take(bad), fc.take(bad), *(a[bad] for a in rest))
        p = np.array(p, copy=True)
        p[bad] = q
    return p, ~bad
