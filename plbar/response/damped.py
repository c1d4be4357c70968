"""Closed-form flow of forced, viscously damped modal oscillators (pure functions).

With Rayleigh damping ``C = alpha M + beta K`` every mode of either state obeys
(Eq. (1) in modal form, FORMULATION §8)

``eta'' + 2 zeta w eta' + w^2 eta = f cos(W t - phi)``,  ``zeta = alpha / (2 w) + beta w / 2``.

Its eigenvalues are ``lambda = -a +- sqrt(a^2 - w^2)`` with ``a = zeta w``: a
complex pair (under-damped, ``zeta < 1``), a double root (critical) or two real
roots (over-damped; the high modes under stiffness-proportional damping).
Everything here is written with *divided differences* of ``z -> exp(z tau)``,
which stay finite and accurate through every confluence:

* free flow ``exp(A tau) = (e^{l1 tau} - l1 s) I + s A`` with ``s = e[l1, l2]``
  (the homogeneous part of Appendix 1, Eqs. (26)-(27), with damping); ``s`` is
  ``e^{-a tau} tau sinc(w_d tau)``, ``e^{-a tau} tau sinh(k tau)/(k tau)`` or, for
  ``k tau >= 1``, ``(e^{-r1 tau} - e^{-r2 tau}) / (2 k)``: smooth through
  ``zeta = 1`` and free of overflow for any ``zeta``;
* the response from rest to ``e^{i W u}`` (the Duhamel kernels) is the second
  divided difference ``K = e[iW, l1, l2] = (e[iW, y] - e[y, z]) / (iW - z)``,
  with ``y`` the root nearest ``iW`` and ``|iW - z| >= max(W, |y|, |z|)``, so the
  only small denominator, ``iW - y`` (resonance), sits inside
  ``phi_1(x) = (e^x - 1) / x`` (a series for ``|x| < 1``); very short segments
  take the Taylor series of ``K`` itself.  ``C = Re K``, ``S = Im K`` and
  ``K' = iW K + s`` give the same ``C, S, C'`` (``S' = W C``) as the undamped
  :func:`plbar.response.flow.kernels`;
* ``Psi = int eta'^2`` (Eq. (20), Appendix 2 with damping): the velocity is
  ``A1 e^{l1 u} + A2 e^{l2 u} + B e^{iWu} + conj(B) e^{-iWu}`` and each product
  integrates to ``F(m) = (e^{m tau} - 1) / m``.  Near resonance (small ``zeta``,
  ``|H|`` large) or near ``zeta = 1`` (``A1, A2 ~ 1 / (l1 - l2)``) the sum cancels; its
  cancellation factor is returned so that :func:`plbar.response.flow.psi` takes
  Gauss-Legendre quadrature there, where the integrand is slowly varying.

All functions broadcast over their arguments; ``tau >= 0``.
"""

from __future__ import annotations

import numpy as np

from .records import Forcing, Modes

__all__ = ["roots", "flow_matrix", "kernels", "psi_closed_form", "phi1", "rate"]

_SERIES = 20        #: terms of the phi_1 and kernel series (|x| < 1: error below 1e-19)


def phi1(x):
    """``(exp(x) - 1) / x`` for complex ``x`` (1 at 0): a series for ``|x| < 1``, the quotient otherwise.

    For ``|x| >= 1`` the quotient loses at most a factor ``e`` to cancellation;
    the callers keep ``Re x`` small there (``<= 0``, or use the quotient form).
    """
    x = np.asarray(x, complex)
    small = np.abs(x) < 1.0
    xs = np.where(small, x, 0.0)
    s = np.ones_like(xs)
    for k in range(_SERIES + 1, 1, -1):
        s = 1.0 + s * xs / k
    xb = np.where(small, 1.0, x)
    return np.where(small, s, (np.exp(xb) - 1.0) / xb)


def roots(w, zeta):
    """The two roots of each mode, ``(y, z)``: ``y`` nearest the imaginary axis.

    Under-damped: ``y = -a + i w_d``, ``z = conj(y)``; critical and over-damped:
    ``y = -r1``, ``z = -r2`` with ``r1 = w^2 / (a + k)`` (no cancellation),
    ``r2 = a + k``, ``k = w sqrt(zeta^2 - 1)``.

    Returns
    -------
    y, z : complex ndarray
    a : ndarray
        ``zeta w``.
    d : ndarray
        ``w^2 (1 - zeta^2)`` (``w_d^2`` if positive, ``-k^2`` otherwise).
    """
    w, zeta = np.broadcast_arrays(np.asarray(w, float), np.asarray(zeta, float))
    a = zeta * w
    d = w * w * (1.0 - zeta) * (1.0 + zeta)
    under = d > 0
    q = np.sqrt(np.abs(d))
    r2 = a + q
    r1 = np.divide(w * w, r2, out=np.zeros_like(r2), where=r2 > 0)
    y = np.where(under, -a + 1j * q, -r1 + 0j)
    z = np.where(under, -a - 1j * q, -r2 + 0j)
    return y, z, a, d


def rate(w, zeta):
    """The largest decay or oscillation rate of each mode, ``max |lambda|`` (``w``, or ``r2`` if over-damped)."""
    y, z, _, _ = roots(w, zeta)
    return np.maximum(np.abs(y), np.abs(z))


def _cs(w, zeta, tau):
    """``ss = e[l1, l2]`` and the diagonal entries ``p11, p22`` of the free flow (stable forms), and the roots."""
    y, z, a, d = roots(w, zeta)
    tau = np.asarray(tau, float)
    q = np.sqrt(np.abs(d))
    if np.all(d > 0):                    # every mode under-damped (the usual case): one branch
        x = q * tau
        ea = np.exp(-a * tau)
        cc = ea * np.cos(x)
        ss = ea * tau * np.sinc(x / np.pi)
        return ss, cc + a * ss, cc - a * ss, y, z
    tau, a, q, d, r1, r2 = np.broadcast_arrays(tau, a, q, d, -y.real, -z.real)
    x = q * tau
    ea = np.exp(-a * tau)
    cc, ss = np.empty(x.shape), np.empty(x.shape)
    under = d > 0
    cc[under] = ea[under] * np.cos(x[under])
    ss[under] = ea[under] * tau[under] * np.sinc(x[under] / np.pi)
    near = ~under & (x < 1.0)            # critical neighbourhood: e^{-a tau} cosh(x), e^{-a tau} tau sinh(x)/x
    xn = x[near]
    cc[near] = ea[near] * np.cosh(xn)
    ss[near] = ea[near] * tau[near] * np.where(xn > 0, np.sinh(xn) / np.where(xn > 0, xn, 1.0), 1.0)
    p11, p22 = np.asarray(cc + a * ss), np.asarray(cc - a * ss)
    far = ~under & ~near                 # over-damped, k tau >= 1: two real exponentials, no cancellation
    if np.any(far):
        t, k2, s1, s2 = tau[far], 2.0 * q[far], r1[far], r2[far]
        e1, e2 = np.exp(-s1 * t), np.exp(-s2 * t)
        ss[far] = (e1 - e2) / k2
        p11[far] = (s2 * e1 - s1 * e2) / k2
        p22[far] = (s2 * e2 - s1 * e1) / k2
    return ss, p11, p22, y, z


def flow_matrix(w, zeta, tau):
    """The damped free flow over ``tau``: the entries of ``exp(A tau)``, ``A = [[0, 1], [-w^2, -2 zeta w]]``.

    Returns
    -------
    p11, p12, p21, p22 : ndarray
        ``eta(tau) = p11 eta0 + p12 v0``, ``eta'(tau) = p21 eta0 + p22 v0``.
    """
    w = np.asarray(w, float)
    ss, p11, p22, _, _ = _cs(w, zeta, tau)
    return p11, ss, -w * w * ss, p22


def _kernel_series(p, y, z, tau):
    """``e[p, y, z]`` of ``exp(. tau)`` by its Taylor series (``max(|p|, |y|, |z|) tau < 1/2``)."""
    A = np.ones_like(p)
    Bk = np.ones_like(p)
    Ck = np.ones_like(p)
    term = tau * tau / 2.0
    out = term * Ck
    for k in range(1, _SERIES + 1):
        A = A * p
        Bk = y * Bk + A
        Ck = z * Ck + Bk
        term = term * tau / (k + 2)
        out = out + term * Ck
    return out


def kernels(w, W, tau, zeta):
    """Damped Duhamel kernels ``C, S, C'`` at ``tau`` (responses from rest to ``cos W u``, ``sin W u``; ``S' = W C``).

    Parameters
    ----------
    w, W, tau, zeta : array_like
        Natural and forcing circular frequencies (> 0), time since the segment
        start (>= 0) and damping ratio (>= 0), broadcast together.

    Returns
    -------
    C, S, Cp : ndarray
    """
    ss, _, _, y, z = _cs(w, zeta, tau)
    W, tau, y, z, ss = np.broadcast_arrays(np.asarray(W, float), np.asarray(tau, float), y, z, ss)
    p = 1j * W
    # e[p, y] = (e^{p tau} - e^{y tau}) / (p - y), as tau e^{y tau} phi1((p - y) tau) where (p - y) tau is small
    x = (p - y) * tau
    near = np.abs(x) < 1.0
    dpy = np.empty(x.shape, complex)
    far = ~near
    dpy[far] = (np.exp(p[far] * tau[far]) - np.exp(y[far] * tau[far])) / (p[far] - y[far])
    if np.any(near):
        dpy[near] = tau[near] * np.exp(y[near] * tau[near]) * phi1(x[near])
    K = np.asarray((dpy - ss) / (p - z))           # |p - z| >= max(W, |y|, |z|) > 0
    short = np.maximum(np.maximum(W, np.abs(y)), np.abs(z)) * tau < 0.5
    if np.any(short):
        K[short] = _kernel_series(p[short], y[short], z[short], tau[short])
    S = K.imag
    return K.real, S, ss - W * S


def _F(m, tau):
    """``int_0^tau e^{m u} du = tau phi1(m tau)`` (``Re m <= 0``)."""
    return tau * phi1(m * tau)


def velocity_terms(modes: Modes, forcing: Forcing, ts, tau, eta0, v0):
    """The damped modal velocity over a segment as exponentials: ``v(u) = A1 e^{y u} + A2 e^{z u} + B e^{iWu} + cc``
    (``modes.zeta`` given; the arguments of :func:`plbar.response.flow.psi_closed_form`).

    Returns ``(w, W, tau, y, z, A1, A2, B, th, sing)`` broadcast: the roots ``y, z`` (:func:`roots`), their
    amplitudes, the steady part's ``B``, ``th = e^{i (W ts - phi)}`` (the load is ``Re(th e^{iWu})``) and where
    the form is singular (exact resonance without damping, a double root).
    """
    args = np.broadcast_arrays(*(np.asarray(v, float) for v in (modes.w, modes.f, forcing.W, ts, tau, eta0, v0,
                                                                 forcing.cphi, forcing.sphi, modes.zeta)))
    w, f, W, ts, tau, eta0, v0, cphi, sphi, zeta = args
    y, z, a, _ = roots(w, zeta)
    den = w * w - W * W + 2j * a * W              # 1 / H
    sing = (den == 0) | (y == z)
    H = 1.0 / np.where(sing, 1.0, den)
    th = np.exp(1j * (W * ts)) * (cphi - 1j * sphi)   # e^{i (W ts - phi)}
    P = f * H * th                                # eta_p(u) = Re(P e^{iWu})
    B = 0.5j * W * P                              # v_p(u) = B e^{iWu} + conj(B) e^{-iWu}
    h0 = eta0 - P.real
    hv0 = v0 - 2.0 * B.real
    hd0 = -w * w * h0 - 2.0 * a * hv0             # homogeneous acceleration at u = 0
    dl = np.where(sing, 1.0, y - z)
    A1 = (hd0 - z * hv0) / dl
    A2 = (y * hv0 - hd0) / dl
    return w, W, tau, y, z, A1, A2, B, th, sing


def work_closed_form(modes: Modes, forcing: Forcing, ts, tau, eta0, v0):
    """The work of the load ``f int_0^tau cos(W (ts + u) - phi) eta'(u) du`` of damped modes in closed form, and its
    cancellation factor (``inf`` where singular; quadrature takes over where it is large)."""
    f = np.asarray(modes.f, float)
    w, W, tau, y, z, A1, A2, B, th, sing = velocity_terms(modes, forcing, ts, tau, eta0, v0)
    iW = 1j * W
    terms = [th * A1 * _F(y + iW, tau), th * A2 * _F(z + iW, tau), th * B * _F(2 * iW, tau), th * B.conj() * tau,
             th.conj() * A1 * _F(y - iW, tau), th.conj() * A2 * _F(z - iW, tau), th.conj() * B * tau,
             th.conj() * B.conj() * _F(-2 * iW, tau)]
    work = 0.5 * f * sum(t.real for t in terms)
    size = 0.5 * np.abs(f) * sum(np.abs(t) for t in terms)
    scale = np.abs(f) * (np.abs(v0) + np.abs(w * eta0) + np.abs(f) * tau) * tau
    cancel = np.divide(size, scale, out=np.where(size > 0, np.inf, 0.0), where=scale > 0)
    return np.where(sing, 0.0, work), np.where(sing, np.inf, cancel)


def psi_closed_form(modes: Modes, forcing: Forcing, ts, tau, eta0, v0):
    """``Psi = int_0^tau eta'^2`` of damped modes in closed form, and its cancellation factor.

    Same arguments as :func:`plbar.response.flow.psi_closed_form`, ``modes.zeta`` given.

    Returns
    -------
    psi : ndarray
    cancel : ndarray
        ``sum |terms| / psi`` (``inf`` where the roots or the resonance make the
        closed form singular); :func:`plbar.response.flow.psi` takes quadrature
        where it is large.
    """
    w, W, tau, y, z, A1, A2, B, _, sing = velocity_terms(modes, forcing, ts, tau, eta0, v0)
    iW = 1j * W
    terms = [A1 * A1 * _F(2 * y, tau), 2 * A1 * A2 * _F(y + z, tau), A2 * A2 * _F(2 * z, tau),
             2 * A1 * B * _F(y + iW, tau), 2 * A1 * B.conj() * _F(y - iW, tau),
             2 * A2 * B * _F(z + iW, tau), 2 * A2 * B.conj() * _F(z - iW, tau),
             2 * (B * B * _F(2 * iW, tau)).real + 0j, 2 * (B * B.conj()).real * tau + 0j]
    psi = sum(t.real for t in terms)
    size = sum(np.abs(t) for t in terms)
    cancel = np.divide(size, psi, out=np.full(psi.shape, np.inf), where=psi > 0)
    return np.where(sing, 0.0, psi), np.where(sing, np.inf, cancel)
