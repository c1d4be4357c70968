"""Work of the load over a segment, in closed form (pure functions).

Over a segment that starts at ``ts`` with modal state ``eta0, v0`` the work of
the load on mode ``j`` up to ``ts + tau`` is

``W_j = f_j int_0^tau cos(W (ts + u) - phi) etadot_j(u) du``

with the exact velocity ``etadot = A cos w u + B sin w u + Cc cos W u + Cs sin W u``
(Eqs. (15)-(17), the same decomposition as ``Psi`` in :mod:`.flow`), so every
product integrates exactly.  This is independent of the energy formulas
(Eqs. (12)-(14)): the energy budget ``work = losses + change of energy`` of a
simulation is a check, not an identity of the code.  Near resonance the
closed form cancels and Gauss-Legendre quadrature of the exact velocity
takes over (as for ``Psi``).
"""

from __future__ import annotations

import numpy as np

from . import damped as _damped
from .flow import CANCEL_LIMIT, gauss, segment, sinc
from .records import Forcing, Modes, broadcast

__all__ = ["work_closed_form", "work_quadrature_segment", "segment_work"]


def _h(x, tau):
    """``(1 - cos(x tau)) / x``, smooth through ``x = 0``."""
    s = sinc(0.5 * x * tau)
    return 0.5 * x * tau * tau * s * s


def work_closed_form(modes: Modes, forcing: Forcing, ts, tau, eta0, v0):
    """Closed-form work of the load on each mode over ``[ts, ts + tau]``.

    Parameters
    ----------
    modes : Modes
        Natural circular frequencies ``w`` and modal load amplitudes ``f`` (array_like); with ``zeta``, the damped
        closed form of :func:`plbar.response.damped.work_closed_form`.
    forcing : Forcing
        Forcing circular frequency ``W`` and ``cphi, sphi``, the ``cos(phi), sin(phi)`` of the forcing phase.
    ts, tau : array_like
        Segment start (absolute) and length.
    eta0, v0 : array_like
        Modal state at ``ts``.

    Returns
    -------
    work : ndarray
        Broadcast shape of the inputs (per mode; sum over the last axis for the total).
    cancel : ndarray
        Cancellation factor ``(|A|+|B|+|Cc|+|Cs|) / (|(w eta0, v0)| + |f| tau)``; large near resonance.
    """
    if modes.zeta is not None:
        return _damped.work_closed_form(modes, forcing, ts, tau, eta0, v0)
    w, f, W, cphi, sphi = modes.w, modes.f, forcing.W, forcing.cphi, forcing.sphi
    cw, sw = np.cos(W * ts), np.sin(W * ts)
    th_c = cw * cphi + sw * sphi     # cos(W ts - phi)
    th_s = sw * cphi - cw * sphi     # sin(W ts - phi)
    wp, wm = w + W, w - W
    d = wp * wm
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        g = np.divide(f, d, out=np.full(np.broadcast(f, d).shape, np.inf), where=d != 0)
        Cc = -g * W * th_s
        Cs = -g * W * th_c
        A = v0 - Cc
        B = g * w * th_c - w * eta0
        cm, cp = tau * sinc(wm * tau), tau * sinc(wp * tau)
        hp, hm = _h(wp, tau), _h(wm, tau)
        c2 = tau * sinc(2 * W * tau)
        sW = sinc(W * tau)
        scW = 0.5 * W * tau * tau * sW * sW                      # int sin Wu cos Wu
        cos_v = A * 0.5 * (cm + cp) + B * 0.5 * (hp + hm) + Cc * 0.5 * (tau + c2) + Cs * scW
        sin_v = A * 0.5 * (hp - hm) + B * 0.5 * (cm - cp) + Cc * scW + Cs * 0.5 * (tau - c2)
        work = f * (th_c * cos_v - th_s * sin_v)
        scale = np.hypot(w * eta0, v0) + np.abs(f) * tau
        num = np.broadcast_to(np.abs(A) + np.abs(B) + np.abs(Cc) + np.abs(Cs), np.shape(work))
        cancel = np.divide(num, scale, out=np.where(num > 0, np.inf, 0.0), where=scale > 0)
    cancel = np.where(np.isfinite(work), cancel, np.inf)
    return work, cancel


def work_quadrature_segment(modes: Modes, forcing: Forcing, ts, tau, eta0, v0, n=None):
    """The work of :func:`work_closed_form` by Gauss-Legendre on the exact velocity (any frequencies; damped
    modes with ``modes.zeta``).

    The integrand is a sum of products of ``cos(W u)``, ``sin(W u)`` and the modal exponentials; pieces of at
    most two periods of the fastest frequency with ``n`` nodes each (at least 40) integrate it to round-off.
    """
    modes, forcing, (ts, tau, eta0, v0) = broadcast(modes, forcing, ts, tau, eta0, v0)
    w, f, zeta, W, cphi, sphi = modes.w, modes.f, modes.zeta, forcing.W, forcing.cphi, forcing.sphi
    span = float(np.max((np.maximum(w, W) + W) * np.abs(tau))) if w.size else 0.0
    pieces = max(1, int(np.ceil(span / (4 * np.pi))))
    n = n or 40
    x, wt = gauss(n)
    edges = np.linspace(0.0, 1.0, pieces + 1)
    u = (edges[:-1, None] + 0.5 * np.diff(edges)[:, None] * (x + 1)).ravel()      # (pieces n,) in [0, 1]
    wts = (0.5 * np.diff(edges)[:, None] * wt).ravel()
    t = tau[..., None] * u
    _, v = segment(w[..., None], f[..., None], W[..., None], ts[..., None], t, eta0[..., None], v0[..., None],
                   cphi[..., None], sphi[..., None], zeta=None if zeta is None else zeta[..., None])
    force = cphi[..., None] * np.cos(W[..., None] * (ts[..., None] + t)) + \
        sphi[..., None] * np.sin(W[..., None] * (ts[..., None] + t))
    return tau * np.sum(wts * f[..., None] * force * v, axis=-1)


def segment_work(modes: Modes, forcing: Forcing, ts, tau, eta0, v0):
    """Work per mode over ``[ts, ts + tau]`` (the arguments of :func:`work_closed_form`): closed form, or
    quadrature where it would cancel (damped modes with ``modes.zeta``: the exponential form of
    :func:`plbar.response.damped.work_closed_form`)."""
    p, cancel = work_closed_form(modes, forcing, ts, tau, eta0, v0)
    bad = ~(cancel < CANCEL_LIMIT)
    if np.any(bad):
        md, fc, rest = broadcast(modes, forcing, ts, tau, eta0, v0)
        p = np.array(p, copy=True)
        p[bad] = work_quadrature_segment(md.take(bad), fc.take(bad), *(a[bad] for a in rest))
    return p
