"""The simulator's segments: its own model data, closed-form modal flow, event search and switches.

Written independently of :mod:`plbar.response` on purpose (see
:mod:`plbar.check.simulate`); it imports :mod:`plbar.model` data only
through ``prob.system`` and ``prob.q``.  With Rayleigh damping it builds
``C = alpha M + beta K`` from ``prob.system.alpha, beta`` itself, its own modal
ratios, its own reaction and its own damped flow (:mod:`plbar.check.viscous`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, PlbarError
from .viscous import damped_flow, flow_rate, modal_ratios

__all__ = ["duhamel", "modal_flow", "OPEN", "IMPACT", "SAMPLES_PER_RAD"]

OPEN = 1      #: event kind: the gap opens (state I -> II)
IMPACT = 2    #: event kind: plastic impact (state II -> I)

SAMPLES_PER_RAD = 2.5   #: event-search samples per radian of the fastest frequency (~16 per period)
ROUNDOFF = 1e-12        #: a margin within ROUNDOFF of its size (:func:`_tolerance`) is zero: no event
_WINDOW = 512           #: samples evaluated at once in the event search
_GL_X, _GL_W = np.polynomial.legendre.leggauss(24)


class SimulationError(PlbarError):
    """The simulation cannot continue (chattering contact, or a map left its orbit class)."""


# ---------------------------------------------------------------------------------------------------------------
# model
# ---------------------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Model:
    """Everything the simulator needs, computed from ``prob.system`` and ``prob.q`` only."""

    M: np.ndarray
    K: np.ndarray
    q: np.ndarray
    w: tuple            # (w1, w2): modal frequencies of state I and II
    V: tuple            # (V1, V2): modes (x = V eta)
    B: tuple            # (V1^T M_rr, V2^T M): physical -> modal (eta = B x)
    f: tuple            # (f1, f2): modal load amplitudes
    rho_eta: np.ndarray  # R = rho_eta . eta^I + r_q cos(W t - phi)
    r_q: float
    G: np.ndarray       # M_rr^{-1} M_r:, the impact velocity map v_r^+ = G v^-
    Minv: np.ndarray
    Mrr_inv: np.ndarray
    zeta: tuple | None = None       # (zeta1, zeta2) modal ratios of C = alpha M + beta K, None undamped
    rho_v: np.ndarray | None = None  # damped: R = rho_eta . eta + rho_v . eta' + r_q cos(W t - phi)
    floor: tuple = (0.0, 0.0)       # each state's margin under the static load: the size of a bar at rest

    @property
    def n(self) -> int:
        return self.q.size

    def rate(self, state: int) -> float:
        """The fastest modal rate of a state (frequency, or decay of an over-damped mode)."""
        w = self.w[state - 1]
        return float(w.max()) if self.zeta is None else flow_rate(w, self.zeta[state - 1])


def _model(prob) -> _Model:
    s = prob.system
    M = np.asarray(s.M, float)
    K = np.asarray(s.K, float)
    q = np.asarray(prob.q, float)
    n = M.shape[0]
    if q.shape != (n,) or not np.all(np.isfinite(q)):
        raise InputError(f"load vector prob.q must be finite and of length {n}, got shape {q.shape}")
    if getattr(prob, "affine", False):
        raise InputError(f"plbar.simulate (the sampling check) takes no gap and no constant load ({prob.static_part}):"
                         " its flows are the paper's; simulate the case with plbar.motion.run (a given start: "
                         "plbar.motion.given), which takes both")
    Mrr = M[:-1, :-1]
    Mrr_inv = np.linalg.inv(Mrr)
    V1, V2 = np.asarray(s.V1, float), np.asarray(s.V2, float)
    w1, w2 = np.asarray(s.w1, float), np.asarray(s.w2, float)
    B1, B2 = V1.T @ Mrr, V2.T @ M
    # reaction with x_c = 0 and the state I acceleration a_r = M_rr^{-1} (q_r cos - K_rr x_r)
    H = M[-1, :-1] @ Mrr_inv
    rho = K[-1, :-1] - H @ K[:-1, :-1]
    r_q = float(H @ q[:-1] - q[-1])
    zeta = rho_v = None
    alpha, beta = float(getattr(s, "alpha", 0.0)), float(getattr(s, "beta", 0.0))
    if alpha or beta:                    # Rayleigh damping: a_r = M_rr^{-1} (q_r cos - K_rr x_r - C_rr v_r)
        C = alpha * M + beta * K
        zeta = (modal_ratios(C[:-1, :-1], V1, w1), modal_ratios(C, V2, w2))
        rho_v = (C[-1, :-1] - H @ C[:-1, :-1]) @ V1
    f1, f2 = V1.T @ q[:-1], V2.T @ q
    floor = (float(np.sum(np.abs((rho @ V1) * f1) / w1**2) + abs(r_q)),
             float(np.sum(np.abs(V2[-1] * f2) / _nonzero(w2)**2)))
    return _Model(M, K, q, (w1, w2), (V1, V2), (B1, B2), (f1, f2), rho @ V1, r_q,
                  Mrr_inv @ M[:-1, :], np.linalg.inv(M), Mrr_inv, zeta, rho_v, floor)


# ---------------------------------------------------------------------------------------------------------------
# closed-form modal flow
# ---------------------------------------------------------------------------------------------------------------

def duhamel(w, W, tau):
    """Responses from rest of ``eta'' + w^2 eta = cos(W u)`` and ``= sin(W u)``, and their rates.

    ``C = (cos W tau - cos w tau) / (w^2 - W^2)`` and
    ``S = (w sin W tau - W sin w tau) / (w (w^2 - W^2))`` are written with
    ``sigma = (w + W) tau / 2`` and ``s = tau sinc((w - W) tau / 2)`` as

    ``C  = sin(sigma) s / (w + W)``,
    ``C' = (W cos(sigma) s + sin(w tau)) / (w + W)``,
    ``S  = (sin(W tau) - W cos(sigma) s) / (w (w + W))``,  ``S' = W C``,

    which never divide by ``w - W`` (exact at resonance, where
    ``C -> tau sin(w tau) / (2 w)``, FORMULATION §2).  Valid for negative
    ``tau`` too.

    Parameters
    ----------
    w, W : array_like
        Natural and forcing circular frequencies, > 0.
    tau : array_like
        Time since the segment start.

    Returns
    -------
    C, Cp, S, Sp : ndarray
    """
    sig = 0.5 * (w + W) * tau
    s = tau * np.sinc(0.5 * (w - W) * tau / np.pi)
    cs = np.cos(sig)
    C = np.sin(sig) * s / (w + W)
    Cp = (W * cs * s + np.sin(w * tau)) / (w + W)
    S = (np.sin(W * tau) - W * cs * s) / (_nonzero(w) * (w + W))
    if np.any(w == 0):      # a rigid-body mode: S -> (tau - sin(W tau) / W) / W
        S = np.where(w == 0, (tau - np.sin(W * tau) / W) / W, S)
    return C, Cp, S, W * C


def _nonzero(w):
    """``w`` with its zeros (rigid-body modes) replaced by 1, for a quotient whose limit is taken apart."""
    return np.where(w == 0, 1.0, w)


def _sin_over(w, t):
    """``sin(w t) / w``, ``t`` where ``w = 0`` (a rigid-body mode's free flow ``eta0 + v0 t``)."""
    return np.where(w == 0, t, np.sin(w * t) / _nonzero(w))


def modal_flow(w, f, W, theta, tau, eta, v, zeta=None):
    """Exact modal state at ``tau`` after a segment start with ``eta, v``.

    Each mode obeys ``eta'' + w^2 eta = f cos(W u + theta)`` (Eq. (1) in
    modal form, ``theta = W t_s - phi``): free vibration from ``eta, v``
    plus the Duhamel response from rest (:func:`duhamel`).  With ``zeta``
    (damped modes): :func:`plbar.check.viscous.damped_flow`.

    Parameters
    ----------
    w, f : ndarray, shape (m,)
    W, theta : float
    tau : float or ndarray, shape (K,)
    eta, v : ndarray, shape (m,)

    Returns
    -------
    eta, v : ndarray, shape (m,) or (K, m)
    """
    if zeta is not None:
        return damped_flow(w, zeta, f, W, theta, tau, eta, v)
    tau = np.asarray(tau, float)
    t = tau[..., None] if tau.ndim else tau
    co, si = np.cos(w * t), np.sin(w * t)
    C, Cp, S, Sp = duhamel(w, W, t)
    ct, st = np.cos(theta), np.sin(theta)
    e = co * eta + _sin_over(w, t) * v + f * (ct * C - st * S)
    u = -w * si * eta + co * v + f * (ct * Cp - st * Sp)
    return e, u


def _modal_displacement(w, f, W, theta, tau, eta, v):
    """The displacement part of :func:`modal_flow` alone (cheaper, for the event search)."""
    tau = np.asarray(tau, float)
    t = tau[..., None] if tau.ndim else tau
    sig = 0.5 * (w + W) * t
    s = t * np.sinc(0.5 * (w - W) * t / np.pi)
    C = np.sin(sig) * s / (w + W)
    S = (np.sin(W * t) - W * np.cos(sig) * s) / (_nonzero(w) * (w + W))
    if np.any(w == 0):
        S = np.where(w == 0, (t - np.sin(W * t) / W) / W, S)
    return np.cos(w * t) * eta + _sin_over(w, t) * v + f * (np.cos(theta) * C - np.sin(theta) * S)


@dataclass(frozen=True)
class _Seg:
    """A segment: state (1 or 2), start time and modal state at the start."""

    state: int
    ts: float
    eta: np.ndarray
    v: np.ndarray


def _at(mod: _Model, W, phi, seg: _Seg, tau):
    i = seg.state - 1
    z = None if mod.zeta is None else mod.zeta[i]
    return modal_flow(mod.w[i], mod.f[i], W, W * seg.ts - phi, tau, seg.eta, seg.v, z)


def _margin(mod: _Model, W, phi, seg: _Seg, tau):
    """Admissibility margin of the segment's state (``>= 0`` while it holds): ``-R`` or ``-x_c``."""
    i = seg.state - 1
    if mod.zeta is None:
        e = _modal_displacement(mod.w[i], mod.f[i], W, W * seg.ts - phi, tau, seg.eta, seg.v)
        r = e @ mod.rho_eta if seg.state == 1 else None
    else:                                    # damped: the reaction has its damper part
        e, u = _at(mod, W, phi, seg, tau)
        r = e @ mod.rho_eta + u @ mod.rho_v if seg.state == 1 else None
    if seg.state == 1:
        return -(r + mod.r_q * np.cos(W * (seg.ts + np.asarray(tau, float)) - phi))
    return -(e @ mod.V[1][-1])


def _physical(mod: _Model, state: int, eta, v):
    """Full physical ``x, v`` (contact DOF last, zero in state I)."""
    V = mod.V[state - 1]
    x, u = eta @ V.T, v @ V.T
    if state == 1:
        x = np.concatenate([x, np.zeros(x.shape[:-1] + (1,))], axis=-1)
        u = np.concatenate([u, np.zeros(u.shape[:-1] + (1,))], axis=-1)
    return x, u


def _energy(mod: _Model, state: int, eta, v):
    """Kinetic and potential energy (Eqs. (12)-(13))."""
    w = mod.w[state - 1]
    return 0.5 * np.sum(v * v, axis=-1), 0.5 * np.sum((w * eta) ** 2, axis=-1)


# ---------------------------------------------------------------------------------------------------------------
# events
# ---------------------------------------------------------------------------------------------------------------

def _step(mod: _Model, W, state) -> float:
    return 1.0 / (SAMPLES_PER_RAD * max(mod.rate(state), W))


def _scale(mod: _Model, seg: _Seg) -> float:
    """Size of the terms of the segment's margin at its start (its round-off level is a fraction of it)."""
    if seg.state == 1:
        return float(np.abs(mod.rho_eta) @ np.abs(seg.eta) + abs(mod.r_q))
    return float(np.abs(mod.V[1][-1]) @ np.abs(seg.eta))


def _tolerance(mod: _Model, seg: _Seg, m: np.ndarray) -> float:
    """Round-off level of the segment's margin: ``ROUNDOFF`` times the largest of its terms at the start, its
    samples ``m`` and the state's margin under the static load (a bar at rest, whose margin is zero in exact
    arithmetic far from the load, has no size of its own: its modal sums cancel to ~1e-17, of either sign)."""
    return ROUNDOFF * max(_scale(mod, seg), float(np.abs(m).max(initial=0.0)), mod.floor[seg.state - 1], 1e-300)


def _refine(g, a, b):
    """Root of ``g`` on ``[a, b]`` with ``g(a) >= 0 > g(b)``, to round-off.

    The bracket comes from a batched evaluation of the margin; ``g`` evaluates it alone, with another
    summation order.  Brackets are chosen beyond the margin's round-off level, so the two agree on the
    signs; if they did not, the event is reported as a :class:`SimulationError`, never as a root finder's
    error.
    """
    ga = g(a)
    if ga <= 0.0:
        return a
    gb = g(b)
    if not gb < 0.0:
        raise SimulationError(f"no sign change of the contact margin on [{a:.15g}, {b:.15g}] of a segment "
                              f"(margins {ga:.3g}, {gb:.3g}): an event at round-off level this simulator "
                              "does not resolve")
    from scipy.optimize import brentq       # lazily: plbar's import stays light

    return brentq(g, a, b, xtol=1e-15 * max(abs(b), 1e-300), rtol=4 * np.finfo(float).eps, maxiter=200)


def _next_event(mod: _Model, W, phi, seg: _Seg, tau_max: float):
    """Local time of the first event of ``seg`` in ``[0, tau_max]``, or None.

    The margin is sampled on a grid of step :func:`_step`; the first sample
    below its round-off level (:func:`_tolerance`) brackets the root with its
    predecessor: a margin within round-off of zero is zero, no event (a bar at
    rest loaded far from its contact has a margin that vanishes to a high order
    in time, whose modal sums are noise of either sign).  A last sample in that band is
    an event if the margin one step later is below it (a crossing just before ``tau_max``,
    e.g. an impact at the end of a run).  Right at the segment
    start the margin is zero up to round-off (both switches start on the
    constraint), so the first interval is resolved on a geometric grid and
    a margin below the round-off level there is an immediate event.
    """
    g = lambda t: float(_margin(mod, W, phi, seg, t))  # noqa: E731
    h = _step(mod, W, seg.state)
    m0 = g(0.0)
    a = 0.0
    first = True
    size = 32
    m = np.zeros(1)
    while a < tau_max:
        taus = a + h * np.arange(1, size + 1)
        taus = taus[taus < tau_max]
        taus = np.append(taus, tau_max) if taus.size < size else taus
        size = min(2 * size, _WINDOW)
        m = _margin(mod, W, phi, seg, taus)
        tol = _tolerance(mod, seg, np.append(m, m0))
        if first:
            if m0 < -tol:
                return 0.0
            if m[0] < 0 and m0 <= tol:
                # resolve the start: geometric samples towards tau = 0
                geo = taus[0] * np.logspace(-12, 0, 49)
                mg = _margin(mod, W, phi, seg, geo)
                neg = np.flatnonzero(mg < -tol)
                if neg.size:
                    k = int(neg[0])
                    return 0.0 if k == 0 else _refine(g, geo[k - 1], geo[k])
            first = False
        neg = np.flatnonzero(m < -tol)      # below zero by round-off only: no event there
        if neg.size:
            k = int(neg[0])
            up = np.flatnonzero(m[:k] >= 0)     # the last sample not below zero (not one in the round-off band)
            lo = taus[up[-1]] if up.size else a
            return _refine(g, lo, taus[k])
        a = float(taus[-1])
    if m[-1] < 0 and g(tau_max) < 0 and g(tau_max + h) < -tol:   # a crossing just before the end, in the band
        up = np.flatnonzero(m >= 0)
        return _refine(g, taus[up[-1]] if up.size else taus[0], tau_max)
    return None


def _switch(mod: _Model, W, phi, seg: _Seg, tau: float):
    """Apply the event at ``seg.ts + tau``: the new segment and the energy lost."""
    eta, v = _at(mod, W, phi, seg, tau)
    E0 = sum(_energy(mod, seg.state, eta, v))
    t = seg.ts + tau
    if seg.state == 1:  # gap opens: x^II = E x^I, v^II = E v^I (FORMULATION §3)
        x, u = _physical(mod, 1, eta, v)
        new = _Seg(2, t, mod.B[1] @ x, mod.B[1] @ u)
    else:               # plastic impact: x_r kept, M_rr v_r^+ = (M v^-)_r
        x, u = _physical(mod, 2, eta, v)
        new = _Seg(1, t, mod.B[0] @ x[:-1], mod.B[0] @ (mod.G @ u))
    E1 = sum(_energy(mod, new.state, new.eta, new.v))
    return new, float(E0 - E1)


def _quadrature(tau: float, rate: float):
    """Gauss-Legendre nodes and weights over ``[0, tau]``, in pieces of two periods of ``rate`` (24 points each)."""
    npc = max(1, int(np.ceil(abs(tau) * rate / (4 * np.pi))))
    edges = np.linspace(0.0, tau, npc + 1)
    half = 0.5 * np.diff(edges)
    nodes = (edges[:-1, None] + half[:, None] * (_GL_X + 1)).ravel()
    return nodes, (half[:, None] * _GL_W).ravel()


def _work(mod: _Model, W, phi, seg: _Seg, tau: float) -> float:
    """Work of the load over ``[ts, ts + tau]``: ``int q cos(W t - phi) . v dt``, Gauss-Legendre.

    The segment is split into pieces of at most two periods of the fastest
    frequency in the integrand (or decay rate, with damping), each integrated
    with 24 Gauss points (exact to round-off for this exponential polynomial).
    ``tau`` may be negative.
    """
    if tau == 0.0:
        return 0.0
    i = seg.state - 1
    nodes, wts = _quadrature(tau, mod.rate(seg.state) + W)
    _, v = _at(mod, W, phi, seg, nodes)
    integrand = np.cos(W * (seg.ts + nodes) - phi) * (v @ mod.f[i])
    return float(np.sum(wts * integrand))


def _viscous(mod: _Model, W, phi, seg: _Seg, tau: float) -> float:
    """Energy the dampers dissipate over ``[ts, ts + tau]``: ``int sum_j 2 zeta_j w_j eta_j'^2 dt`` (Gauss-Legendre).

    ``v^T C v = sum_j 2 zeta_j w_j eta_j'^2`` in the modes of the segment's state.
    Zero without damping; ``tau`` may be negative.
    """
    if tau == 0.0 or mod.zeta is None:
        return 0.0
    i = seg.state - 1
    nodes, wts = _quadrature(tau, 2 * mod.rate(seg.state))
    _, v = _at(mod, W, phi, seg, nodes)
    return float(np.sum(wts * ((v * v) @ (2 * mod.zeta[i] * mod.w[i]))))


