"""Event-driven simulation of the two-state bar (FORMULATION §§2-3, §7).

An independent time integrator of the forced two-state system, used to check
the closed-form periodic responses and their stability (FORMULATION §7).  It
shares only the model and its modes with the periodic solver
(``prob.system.M, K, w1, V1, w2, V2`` and ``prob.q``); the modal flow, the
contact reaction, the switches and the event location are written here
again, on purpose differently from :mod:`plbar.response.flow` and :mod:`plbar.response.orbit`
(the flow, events and switches live in :mod:`plbar.check.segments`).

Between events the motion is exact: every mode of the active state is a
forced undamped oscillator, ``eta'' + w^2 eta = f cos(W t - phi)`` (paper
Eqs. (1)-(3)), integrated in closed form (homogeneous part plus a Duhamel
particular part, factorised with ``sinc`` so that it stays exact at and near
resonance ``W = w``, where it tends to ``tau sin(w tau) / (2 w)``).  With
Rayleigh damping (FORMULATION §8) each mode is damped (:mod:`plbar.check.viscous`), the
reaction has its damper part and the budget the dampers' loss (``Simulation.viscous``).

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
A double crossing between two samples (a near-grazing excursion shorter than about a sixteenth of
the fastest period) is not seen: the usual limit of sampling (:mod:`plbar.motion` certifies instead).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from ..errors import InputError
from ..util.record import Record, events
from ..util.reprs import build, rng
from .segments import (IMPACT, OPEN, SAMPLES_PER_RAD, SimulationError, _at, _energy, _Model, _model, _next_event,
                       _physical, _Seg, _switch, _viscous, _work)

__all__ = ["Simulation", "History", "SimulationError", "simulate", "period_map", "OPEN", "IMPACT",
           "SNAP", "SAMPLES_PER_RAD"]

SNAP = 1e-9             #: events within ``SNAP * T`` after a sample time count as before it (see simulate)
_MAX_ZERO_SEGMENTS = 50  #: consecutive zero-length segments before a chattering error


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

    def __repr__(self) -> str:
        st = np.asarray(self.state)
        return build("History", {"samples": self.t.size, "n": np.shape(self.x)[-1], "t": rng(self.t),
                                 "states": f"{{1: {int(np.sum(st == 1))}, 2: {int(np.sum(st == 2))}}}",
                                 "energy": rng(self.energy)})


@dataclass(frozen=True, kw_only=True)
class Simulation(Record):
    """Result of :func:`simulate`: a :class:`plbar.util.record.Record` of one trajectory.

    Attributes
    ----------
    T, phi : float
        Forcing period and phase.
    status : ndarray of int, shape (1,)
        0 (a contact that chatters raises :class:`SimulationError` instead).
    events : ndarray of dtype EVENT, shape (E,)
        ``time``; ``kind``: :data:`OPEN` (1, gap opens) or :data:`IMPACT` (2, plastic impact); ``loss``: the
        mechanical energy lost at each event (Eq. (14) at impacts; zero up to round-off at openings); ``traj`` 0,
        ``v`` nan.
    t0, t_end : float
        Start and end time.
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
    viscous : float
        Energy the Rayleigh dampers dissipate over ``[t0, t_end]`` (quadrature of ``v^T C v``); 0 undamped.
    """

    t0: float
    t_end: float
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
    viscous: float = 0.0

    def __repr__(self) -> str:
        return build("Simulation", {"T": self.T, "phi": self.phi, "t": f"[{self.t0:.6g}, {self.t_end:.6g}]",
                                    "n": np.size(self.x), "openings": int(np.sum(self.events["kind"] == OPEN)),
                                    "impacts": int(np.sum(self.events["kind"] == IMPACT)), "state": self.state,
                                    "strobes": np.size(self.strobe_t), "energy_residual": f"{self.energy_residual:.3g}",
                                    "history": "None" if self.history is None else f"{self.history.t.size} samples"})

    @property
    def impact_times(self) -> np.ndarray:
        """Time of each plastic impact."""
        return self.events["time"][self.events["kind"] == IMPACT]

    @property
    def impact_losses(self) -> np.ndarray:
        """Energy lost at each plastic impact (Eq. (14))."""
        return self.events["loss"][self.events["kind"] == IMPACT]

    @property
    def energy_residual(self) -> float:
        """Energy budget ``work - sum(event losses) - viscous - (energy - energy0)``; zero up to round-off."""
        return self.work - float(np.sum(self.events["loss"])) - self.viscous - (self.energy - self.energy0)


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


def _check_span(T, n_periods, t0, record):
    """Validated ``n_periods, t0`` and record times (or None)."""
    try:
        n_periods, t0 = float(n_periods), float(t0)
    except (TypeError, ValueError):
        raise InputError(f"n_periods = {n_periods!r} and t0 = {t0!r} must be numbers") from None
    if not (np.isfinite(n_periods) and n_periods > 0):
        raise InputError(f"n_periods = {n_periods!r} is not allowed; it must be finite and > 0")
    if not np.isfinite(t0):
        raise InputError(f"t0 = {t0!r} must be finite")
    if record is None:
        return n_periods, t0, None
    t_end = t0 + n_periods * T
    rec = np.asarray(record, float).ravel()
    if not np.all(np.isfinite(rec)) or rec.size and (rec.min() < t0 or rec.max() > t_end):
        raise InputError(f"record times must be finite and lie in [t0, t_end] = [{t0:g}, {t_end:g}]; got "
                         f"[{rec.min():g}, {rec.max():g}]")
    return n_periods, t0, rec


def _run(mod: _Model, T, phi, seg: _Seg, t_limit: float, t_stop: float | None = None):
    """Event loop from ``seg`` until no event is left before ``t_limit`` (or a segment starts at ``t_stop``,
    so the snap window after the last sample holds no cascade of zero-length segments): segments, events."""
    W = 2 * np.pi / T
    segs = [seg]
    times, kinds, losses = [], [], []
    zero = 0
    while t_stop is None or seg.ts < t_stop:
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
    n_periods, t0, rec = _check_span(T, n_periods, t0, record)
    seg0 = _check_state(mod, x0, v0, state)
    seg0 = _Seg(seg0.state, t0, seg0.eta, seg0.v)
    t_end = t0 + n_periods * T
    return _simulation(mod, T, phi, seg0, t_end, n_periods, rec)


def _simulation(mod: _Model, T, phi, seg0: _Seg, t_end: float, n_periods: float, rec) -> Simulation:
    """Run the events from ``seg0`` to ``t_end`` and sample the stroboscopic states, the end and the record."""
    W = 2 * np.pi / T
    snap = SNAP * T
    segs, times, kinds, losses = _run(mod, T, phi, seg0, t_end + snap, t_end)
    starts = np.array([s.ts for s in segs])

    def sample(tk):
        s = segs[int(np.searchsorted(starts, tk + snap, side="right")) - 1]
        e, u = _at(mod, W, phi, s, tk - s.ts)
        x, v = _physical(mod, s.state, e, u)
        return x, v, s.state, float(sum(_energy(mod, s.state, e, u)))

    n_strobe = int(np.floor(n_periods * (1 + 1e-12)))
    st = seg0.ts + T * np.arange(1, n_strobe + 1)
    sx, sv, ss = np.zeros((n_strobe, mod.n)), np.zeros((n_strobe, mod.n)), np.zeros(n_strobe, int)
    for k, tk in enumerate(st):
        sx[k], sv[k], ss[k], _ = sample(tk)
    xe, ve, se, Ee = sample(t_end)
    E0 = float(sum(_energy(mod, seg0.state, seg0.eta, seg0.v)))
    # work: each segment up to the next start; the last one up to t_end (backwards if it started after t_end)
    ends = np.append(starts[1:], t_end)
    work = sum(_work(mod, W, phi, s, float(te - s.ts)) for s, te in zip(segs, ends))
    visc = sum(_viscous(mod, W, phi, s, float(te - s.ts)) for s, te in zip(segs, ends))
    hist = None if rec is None else _history(mod, W, phi, segs, starts, rec)
    return Simulation(T=T, phi=phi, status=np.zeros(1, int), events=events(times, kinds, losses), t0=seg0.ts,
                      t_end=t_end, x=xe, v=ve, state=se, strobe_t=st, strobe_x=sx, strobe_v=sv, strobe_state=ss,
                      work=float(work), energy0=E0, energy=Ee, history=hist, viscous=float(visc))


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
