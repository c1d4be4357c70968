"""Event-driven simulation of the two-state bar (FORMULATION §§2-3, §7).

An independent time integrator of the forced two-state system, used to check
the closed-form periodic responses and their stability (FORMULATION §7).  It
shares only the model and its modes with the periodic solver
(``prob.system.M, K, w1, V1, w2, V2`` and ``prob.q``); the modal flow, the
contact reaction, the switches and the event location are written here
again, on purpose differently from :mod:`plbar.flow` and :mod:`plbar.orbit`.

Between events the motion is exact: every mode of the active state is a
forced undamped oscillator, ``eta'' + w^2 eta = f cos(W t - phi)`` (paper
Eqs. (1)-(3)), integrated in closed form (homogeneous part plus a Duhamel
particular part, factorised with ``sinc`` so that it stays exact at and near
resonance ``W = w``, where it tends to ``tau sin(w tau) / (2 w)``).

Events (paper Sec. 2.2, FORMULATION §3):

* **gap opens** (state I -> II) when the contact reaction stops compressing,
  i.e. the margin ``-R(t)`` turns negative, with
  ``R = (M x'' + K x - q cos(W t - phi))_c`` and ``x_c = 0`` (Eq. (4));
  positions and velocities are embedded with ``x_c = v_c = 0``;
* **plastic impact** (state II -> I) when the gap closes, i.e. the margin
  ``-x_c(t)`` turns negative (Eq. (5)); the contact DOF stops and the
  generalised momenta of the other DOFs are conserved,
  ``M_rr v_r^+ = (M v^-)_r``; the energy lost is Eq. (14) in its momentum
  form.

An event is found by sampling the closed-form margin of the current segment
densely (``SAMPLES_PER_RAD`` samples per radian of the fastest of the
state's modal frequencies and the forcing frequency), bracketing the first
sign change and refining it with :func:`scipy.optimize.brentq` to round-off.
A double crossing between two samples (a near-grazing excursion shorter than
about a sixteenth of the fastest period) is not seen; this is the usual
limit of event detection by sampling.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from .errors import InputError, PlbarError

__all__ = ["Simulation", "History", "SimulationError", "simulate", "period_map", "OPEN", "IMPACT",
           "SNAP", "SAMPLES_PER_RAD"]

OPEN = 1      #: event kind: the gap opens (state I -> II)
IMPACT = 2    #: event kind: plastic impact (state II -> I)

SAMPLES_PER_RAD = 2.5   #: event-search samples per radian of the fastest frequency (~16 per period)
SNAP = 1e-9             #: events within ``SNAP * T`` after a sample time count as before it (see simulate)
_WINDOW = 512           #: samples evaluated at once in the event search
_MAX_ZERO_SEGMENTS = 50  #: consecutive zero-length segments before a chattering error
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

    @property
    def n(self) -> int:
        return self.q.size


def _model(prob) -> _Model:
    s = prob.system
    M = np.asarray(s.M, float)
    K = np.asarray(s.K, float)
    q = np.asarray(prob.q, float)
    n = M.shape[0]
    if q.shape != (n,) or not np.all(np.isfinite(q)):
        raise InputError(f"load vector prob.q must be finite and of length {n}, got shape {q.shape}")
    Mrr = M[:-1, :-1]
    Mrr_inv = np.linalg.inv(Mrr)
    V1, V2 = np.asarray(s.V1, float), np.asarray(s.V2, float)
    w1, w2 = np.asarray(s.w1, float), np.asarray(s.w2, float)
    B1, B2 = V1.T @ Mrr, V2.T @ M
    # reaction with x_c = 0 and the state I acceleration a_r = M_rr^{-1} (q_r cos - K_rr x_r)
    H = M[-1, :-1] @ Mrr_inv
    rho = K[-1, :-1] - H @ K[:-1, :-1]
    r_q = float(H @ q[:-1] - q[-1])
    return _Model(M, K, q, (w1, w2), (V1, V2), (B1, B2), (V1.T @ q[:-1], V2.T @ q), rho @ V1, r_q,
                  Mrr_inv @ M[:-1, :], np.linalg.inv(M), Mrr_inv)


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
    S = (np.sin(W * tau) - W * cs * s) / (w * (w + W))
    return C, Cp, S, W * C


def modal_flow(w, f, W, theta, tau, eta, v):
    """Exact modal state at ``tau`` after a segment start with ``eta, v``.

    Each mode obeys ``eta'' + w^2 eta = f cos(W u + theta)`` (Eq. (1) in
    modal form, ``theta = W t_s - phi``): free vibration from ``eta, v``
    plus the Duhamel response from rest (:func:`duhamel`).

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
    tau = np.asarray(tau, float)
    t = tau[..., None] if tau.ndim else tau
    co, si = np.cos(w * t), np.sin(w * t)
    C, Cp, S, Sp = duhamel(w, W, t)
    ct, st = np.cos(theta), np.sin(theta)
    e = co * eta + si / w * v + f * (ct * C - st * S)
    u = -w * si * eta + co * v + f * (ct * Cp - st * Sp)
    return e, u


def _modal_displacement(w, f, W, theta, tau, eta, v):
    """The displacement part of :func:`modal_flow` alone (cheaper, for the event search)."""
    tau = np.asarray(tau, float)
    t = tau[..., None] if tau.ndim else tau
    sig = 0.5 * (w + W) * t
    s = t * np.sinc(0.5 * (w - W) * t / np.pi)
    C = np.sin(sig) * s / (w + W)
    S = (np.sin(W * t) - W * np.cos(sig) * s) / (w * (w + W))
    return np.cos(w * t) * eta + np.sin(w * t) / w * v + f * (np.cos(theta) * C - np.sin(theta) * S)


@dataclass(frozen=True)
class _Seg:
    """A segment: state (1 or 2), start time and modal state at the start."""

    state: int
    ts: float
    eta: np.ndarray
    v: np.ndarray


def _at(mod: _Model, W, phi, seg: _Seg, tau):
    i = seg.state - 1
    return modal_flow(mod.w[i], mod.f[i], W, W * seg.ts - phi, tau, seg.eta, seg.v)


def _margin(mod: _Model, W, phi, seg: _Seg, tau):
    """Admissibility margin of the segment's state (``>= 0`` while it holds): ``-R`` or ``-x_c``."""
    i = seg.state - 1
    e = _modal_displacement(mod.w[i], mod.f[i], W, W * seg.ts - phi, tau, seg.eta, seg.v)
    if seg.state == 1:
        return -(e @ mod.rho_eta + mod.r_q * np.cos(W * (seg.ts + np.asarray(tau, float)) - phi))
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
    return 1.0 / (SAMPLES_PER_RAD * max(float(mod.w[state - 1].max()), W))


def _refine(g, a, b):
    """Root of ``g`` on ``[a, b]`` with ``g(a) >= 0 > g(b)``, to round-off."""
    ga = g(a)
    if ga <= 0.0:
        return a
    return brentq(g, a, b, xtol=1e-15 * max(abs(b), 1e-300), rtol=4 * np.finfo(float).eps, maxiter=200)


def _next_event(mod: _Model, W, phi, seg: _Seg, tau_max: float):
    """Local time of the first event of ``seg`` in ``[0, tau_max]``, or None.

    The margin is sampled on a grid of step :func:`_step`; the first sample
    below zero brackets the root with its predecessor.  Right at the segment
    start the margin is zero up to round-off (both switches start on the
    constraint), so the first interval is resolved on a geometric grid and
    a margin below ``-1e-12`` of its scale there is an immediate event.
    """
    g = lambda t: float(_margin(mod, W, phi, seg, t))  # noqa: E731
    h = _step(mod, W, seg.state)
    m0 = g(0.0)
    a = 0.0
    first = True
    size = 32
    while a < tau_max:
        taus = a + h * np.arange(1, size + 1)
        taus = taus[taus < tau_max]
        taus = np.append(taus, tau_max) if taus.size < size else taus
        size = min(2 * size, _WINDOW)
        m = _margin(mod, W, phi, seg, taus)
        if first:
            tol = 1e-12 * max(np.abs(m).max(), abs(m0), 1e-300)
            if m0 < -tol:
                return 0.0
            if m[0] < 0 and m0 <= tol:
                # resolve the start: geometric samples towards tau = 0
                geo = taus[0] * np.logspace(-12, 0, 49)
                mg = _margin(mod, W, phi, seg, geo)
                neg = np.flatnonzero(mg < -tol)
                k = int(neg[0]) if neg.size else int(np.flatnonzero(mg < 0)[0])
                if k == 0:
                    return 0.0
                return _refine(g, geo[k - 1], geo[k])
            first = False
        neg = np.flatnonzero(m < 0)
        if neg.size:
            k = int(neg[0])
            lo = taus[k - 1] if k > 0 else a
            return _refine(g, lo, taus[k])
        a = float(taus[-1])
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


def _work(mod: _Model, W, phi, seg: _Seg, tau: float) -> float:
    """Work of the load over ``[ts, ts + tau]``: ``int q cos(W t - phi) . v dt``, Gauss-Legendre.

    The segment is split into pieces of at most two periods of the fastest
    frequency in the integrand, each integrated with 24 Gauss points (exact
    to round-off for this trigonometric polynomial).  ``tau`` may be negative.
    """
    if tau == 0.0:
        return 0.0
    i = seg.state - 1
    Om = float(mod.w[i].max()) + W
    npc = max(1, int(np.ceil(abs(tau) * Om / (4 * np.pi))))
    edges = np.linspace(0.0, tau, npc + 1)
    half = 0.5 * np.diff(edges)
    nodes = (edges[:-1, None] + half[:, None] * (_GL_X + 1)).ravel()
    _, v = _at(mod, W, phi, seg, nodes)
    integrand = np.cos(W * (seg.ts + nodes) - phi) * (v @ mod.f[i])
    return float(np.sum((half[:, None] * _GL_W).ravel() * integrand))


# ---------------------------------------------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class History:
    """A recorded time history.

    Attributes
    ----------
    t : ndarray, shape (K,)
    x, v : ndarray, shape (K, n)
        Physical displacements and velocities (contact DOF last).
    state : ndarray of int, shape (K,)
    ek, ep : ndarray, shape (K,)
        Kinetic and potential energy (Eqs. (12)-(13)).
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    state: np.ndarray
    ek: np.ndarray
    ep: np.ndarray

    @property
    def energy(self) -> np.ndarray:
        """Mechanical energy ``ek + ep``."""
        return self.ek + self.ep


@dataclass(frozen=True)
class Simulation:
    """Result of :func:`simulate`.

    Attributes
    ----------
    T, phi, t0, t_end : float
        Forcing period and phase, start and end time.
    event_times : ndarray, shape (E,)
    event_kinds : ndarray of int, shape (E,)
        :data:`OPEN` (1, gap opens) or :data:`IMPACT` (2, plastic impact).
    event_losses : ndarray, shape (E,)
        Mechanical energy lost at each event (Eq. (14) at impacts; zero up
        to round-off at openings).
    x, v : ndarray, shape (n,)
        Final physical state at ``t_end`` (contact DOF last).
    state : int
        Final state (1 or 2).
    strobe_t : ndarray, shape (S,)
        Stroboscopic times ``t0 + k T``, ``k = 1 .. floor(n_periods)``.
    strobe_x, strobe_v : ndarray, shape (S, n)
    strobe_state : ndarray of int, shape (S,)
    work : float
        Work of the load over ``[t0, t_end]`` (Gauss quadrature per segment).
    energy0, energy : float
        Mechanical energy at ``t0`` and at ``t_end``.
    history : History or None
        The recorded time history, if a grid was given.
    """

    T: float
    phi: float
    t0: float
    t_end: float
    event_times: np.ndarray
    event_kinds: np.ndarray
    event_losses: np.ndarray
    x: np.ndarray
    v: np.ndarray
    state: int
    strobe_t: np.ndarray
    strobe_x: np.ndarray
    strobe_v: np.ndarray
    strobe_state: np.ndarray
    work: float
    energy0: float
    energy: float
    history: History | None = None

    @property
    def impact_times(self) -> np.ndarray:
        return self.event_times[self.event_kinds == IMPACT]

    @property
    def impact_losses(self) -> np.ndarray:
        """Energy lost at each plastic impact (Eq. (14))."""
        return self.event_losses[self.event_kinds == IMPACT]

    @property
    def opening_times(self) -> np.ndarray:
        return self.event_times[self.event_kinds == OPEN]

    @property
    def energy_residual(self) -> float:
        """Energy budget ``work - sum(event losses) - (energy - energy0)``; zero up to round-off."""
        return self.work - float(np.sum(self.event_losses)) - (self.energy - self.energy0)


def _check_state(mod: _Model, x0, v0, state):
    n = mod.n
    if state not in (1, 2):
        raise InputError(f"state = {state!r} is not allowed; use 1 (in contact) or 2 (gap open)")
    x0 = np.asarray(x0, float)
    v0 = np.asarray(v0, float)
    for nm, a in (("x0", x0), ("v0", v0)):
        if a.shape not in ((n,), (n - 1,)):
            raise InputError(f"{nm} has shape {a.shape}; give {n} values (all free DOFs) or {n - 1} (state I, "
                             "without the contact DOF)")
        if not np.all(np.isfinite(a)):
            raise InputError(f"{nm} = {a.tolist()!r} must be finite")
        if a.shape == (n - 1,) and state == 2:
            raise InputError(f"{nm} has {n - 1} values, but state 2 needs all {n} DOFs")
    if x0.shape != v0.shape:
        raise InputError(f"x0 and v0 must have the same shape, got {x0.shape} and {v0.shape}")
    scale = max(float(np.abs(x0).max(initial=0.0)), 1e-300)
    if state == 1:
        if x0.size == n and (x0[-1] != 0 or v0[-1] != 0):
            raise InputError(f"in state 1 the contact DOF is held: x0[-1] = {float(x0[-1]):g} and "
                             f"v0[-1] = {float(v0[-1]):g} must be 0")
        return _Seg(1, 0.0, mod.B[0] @ x0[:n - 1], mod.B[0] @ v0[:n - 1])
    if x0[-1] > 1e-12 * scale:
        raise InputError(f"x0[-1] = {float(x0[-1]):g} penetrates the wall; state 2 needs x_c <= 0")
    return _Seg(2, 0.0, mod.B[1] @ x0, mod.B[1] @ v0)


def _check_forcing(T, phi):
    try:
        T, phi = float(T), float(phi)
    except (TypeError, ValueError):
        raise InputError(f"T = {T!r} and phi = {phi!r} must be numbers") from None
    if not (np.isfinite(T) and T > 0):
        raise InputError(f"T = {T!r} is not allowed; the forcing period must be finite and > 0")
    if not np.isfinite(phi):
        raise InputError(f"phi = {phi!r} must be finite")
    return T, phi


def _run(mod: _Model, T, phi, seg: _Seg, t_limit: float):
    """Event loop from ``seg`` until no event is left before ``t_limit``: segments and event data."""
    W = 2 * np.pi / T
    segs = [seg]
    times, kinds, losses = [], [], []
    zero = 0
    while True:
        tau = _next_event(mod, W, phi, seg, t_limit - seg.ts)
        if tau is None:
            break
        kind = OPEN if seg.state == 1 else IMPACT
        seg, loss = _switch(mod, W, phi, seg, tau)
        zero = zero + 1 if tau == 0.0 else 0
        if zero > _MAX_ZERO_SEGMENTS:
            raise SimulationError(f"the contact chatters at t = {seg.ts:.12g}: {zero} switches without time "
                                  "passing (a grazing or sticking contact this simulator does not resolve)")
        segs.append(seg)
        times.append(seg.ts)
        kinds.append(kind)
        losses.append(loss)
    return segs, np.array(times), np.array(kinds, int), np.array(losses)


def simulate(prob, T, phi, x0, v0, state: int = 1, n_periods: float = 1.0, t0: float = 0.0,
             record=None) -> Simulation:
    """Simulate the forced two-state bar from a given state (event driven, exact between events).

    The load is ``q(t) = q cos(W t - phi)`` with ``W = 2 pi / T`` (Eq. (1));
    the run covers ``[t0, t0 + n_periods T]``.

    Parameters
    ----------
    prob : Problem
        Only ``prob.system`` (matrices and modes) and ``prob.q`` are used;
        ``q`` may be zero (free vibration).
    T, phi : float
        Forcing period (> 0) and phase.
    x0, v0 : array_like, shape (n,) or (n-1,)
        Physical displacements and velocities at ``t0`` (contact DOF last).
        In state 1, ``n - 1`` values (the DOFs other than the contact) are
        enough; with ``n`` values the contact entries must be 0.
    state : {1, 2}
        1: in contact (state I), 2: gap open (state II, ``x0[-1] <= 0``).
        A state 1 start with a tensile reaction opens at once.
    n_periods : float
        Length of the run in forcing periods (> 0).
    t0 : float
        Start time (absolute: the forcing phase is ``W t - phi``).
    record : array_like, optional
        Times in ``[t0, t_end]`` at which to record the history.

    Returns
    -------
    Simulation

    Notes
    -----
    The stroboscopic samples at ``t0 + k T`` and the final state are taken
    *after* any event that falls within ``SNAP * T`` after the sample time,
    with the new state's flow continued back to the sample time.  This is
    the smooth extension of the stroboscopic map (FORMULATION §7): on a
    periodic orbit the impact falls on the sample time itself, and round-off
    must not decide whether the sample is taken just before or just after
    it.  The recorded history is the plain state at each time.
    """
    mod = _model(prob)
    T, phi = _check_forcing(T, phi)
    try:
        n_periods, t0 = float(n_periods), float(t0)
    except (TypeError, ValueError):
        raise InputError(f"n_periods = {n_periods!r} and t0 = {t0!r} must be numbers") from None
    if not (np.isfinite(n_periods) and n_periods > 0):
        raise InputError(f"n_periods = {n_periods!r} is not allowed; it must be finite and > 0")
    if not np.isfinite(t0):
        raise InputError(f"t0 = {t0!r} must be finite")
    seg0 = _check_state(mod, x0, v0, state)
    seg0 = _Seg(seg0.state, t0, seg0.eta, seg0.v)
    t_end = t0 + n_periods * T
    rec = None
    if record is not None:
        rec = np.asarray(record, float).ravel()
        if not np.all(np.isfinite(rec)) or rec.size and (rec.min() < t0 or rec.max() > t_end):
            raise InputError(f"record times must be finite and lie in [t0, t_end] = [{t0:g}, {t_end:g}]; got "
                             f"[{rec.min():g}, {rec.max():g}]")
    W = 2 * np.pi / T
    snap = SNAP * T
    segs, times, kinds, losses = _run(mod, T, phi, seg0, t_end + snap)
    starts = np.array([s.ts for s in segs])

    def sample(tk):
        s = segs[int(np.searchsorted(starts, tk + snap, side="right")) - 1]
        e, u = _at(mod, W, phi, s, tk - s.ts)
        x, v = _physical(mod, s.state, e, u)
        return x, v, s.state, float(sum(_energy(mod, s.state, e, u)))

    n_strobe = int(np.floor(n_periods * (1 + 1e-12)))
    st = t0 + T * np.arange(1, n_strobe + 1)
    sx, sv, ss = np.zeros((n_strobe, mod.n)), np.zeros((n_strobe, mod.n)), np.zeros(n_strobe, int)
    for k, tk in enumerate(st):
        sx[k], sv[k], ss[k], _ = sample(tk)
    xe, ve, se, Ee = sample(t_end)
    E0 = float(sum(_energy(mod, seg0.state, seg0.eta, seg0.v)))
    # work: each segment up to the next start; the last one up to t_end (backwards if it started after t_end)
    ends = np.append(starts[1:], t_end)
    work = sum(_work(mod, W, phi, s, float(te - s.ts)) for s, te in zip(segs, ends))
    hist = None
    if rec is not None:
        hist = _history(mod, W, phi, segs, starts, rec)
    return Simulation(T, phi, t0, t_end, times, kinds, losses, xe, ve, se, st, sx, sv, ss, float(work), E0, Ee,
                      hist)


def _history(mod: _Model, W, phi, segs, starts, rec) -> History:
    K, n = rec.size, mod.n
    x, v = np.zeros((K, n)), np.zeros((K, n))
    state, ek, ep = np.zeros(K, int), np.zeros(K), np.zeros(K)
    j = np.searchsorted(starts, rec, side="right") - 1
    for i in np.unique(j):
        sel = j == i
        s = segs[i]
        e, u = _at(mod, W, phi, s, rec[sel] - s.ts)
        x[sel], v[sel] = _physical(mod, s.state, e, u)
        ek[sel], ep[sel] = _energy(mod, s.state, e, u)
        state[sel] = s.state
    return History(rec, x, v, state, ek, ep)


def period_map(prob, T, phi, x_r, v_r):
    """One-period stroboscopic map from state I at ``t = 0``, just after an impact.

    The Poincare map of the periodic solver (paper Sec. 2.3, FORMULATION
    §4/§7): start in contact at ``t = 0`` with ``x_r, v_r`` (the DOFs other
    than the contact), simulate until the gap opens and then until the next
    plastic impact, and carry the state I flow from the impact time to
    ``t = T``.  When the impact falls after ``T`` the state I flow is run
    backwards: this smooth extension makes the map differentiable at orbits
    whose impact is at ``t = T`` (it is what the saltation matrices
    linearise), so finite differences of it give the monodromy matrix.

    Parameters
    ----------
    prob : Problem
    T, phi : float
    x_r, v_r : array_like, shape (n-1,)

    Returns
    -------
    x_r, v_r : ndarray, shape (n-1,)
        State I displacements and velocities at ``t = T``.

    Raises
    ------
    SimulationError
        If the motion leaves the class "one opening and one impact per
        period": no opening before ``2 T``, no impact before ``3 T``, or a
        second opening before ``T``.
    """
    mod = _model(prob)
    T, phi = _check_forcing(T, phi)
    n = mod.n
    x_r, v_r = np.asarray(x_r, float), np.asarray(v_r, float)
    if x_r.shape != (n - 1,) or v_r.shape != (n - 1,):
        raise InputError(f"x_r and v_r must have {n - 1} values (state I DOFs), got {x_r.shape} and {v_r.shape}")
    W = 2 * np.pi / T
    seg = _Seg(1, 0.0, mod.B[0] @ x_r, mod.B[0] @ v_r)
    tau = _next_event(mod, W, phi, seg, 2 * T)
    if tau is None:
        raise SimulationError(f"period_map(T = {T:g}): the gap does not open before t = 2 T")
    seg, _ = _switch(mod, W, phi, seg, tau)
    tau = _next_event(mod, W, phi, seg, 3 * T - seg.ts)
    if tau is None:
        raise SimulationError(f"period_map(T = {T:g}): no impact before t = 3 T")
    seg, _ = _switch(mod, W, phi, seg, tau)
    if seg.ts < T:
        tau = _next_event(mod, W, phi, seg, T - seg.ts)
        if tau is not None and seg.ts + tau < T * (1 - SNAP):
            raise SimulationError(f"period_map(T = {T:g}): the gap opens again at t = {seg.ts + tau:.12g} < T")
    e, u = _at(mod, W, phi, seg, T - seg.ts)
    return e @ mod.V[0].T, u @ mod.V[0].T
