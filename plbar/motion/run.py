"""Run many trajectories for many forcing periods in the compiled kernel and keep what the survey needs
(:class:`Run`)."""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import partial

import numpy as np

from ..errors import InputError
from ..model import Problem
from ..util.record import Record, events, messages
from ..util.reprs import build, listing, rng
from ..util.threads import map_chunks, n_threads, off_main
from .compile import kind
from .model import FREE, OK, STUCK, Padded, padded

__all__ = ["Run", "Start", "Stopped", "energy", "given", "prepare", "rest", "run", "halt_flag"]


class Stopped(Exception):
    """A simulation stopped by its halt flag (:func:`halt_flag`, set by another thread: a cancelled search)."""


def halt_flag() -> np.ndarray:
    """A fresh halt flag for :func:`run`: ``flag[0] = 1`` from any thread stops the compiled kernel at its next
    round (every trajectory, within microseconds) and :func:`run` raises :class:`Stopped`."""
    return np.zeros(1, np.int64)


@dataclass(frozen=True)
class Start:
    """Initial states of a batch, in the padded modal coordinates of :mod:`.model`.

    ``state`` (B,) is ``STUCK`` (0) or ``FREE`` (1); ``eta, vel`` (B, m).
    """

    state: np.ndarray
    eta: np.ndarray
    vel: np.ndarray


def rest(pad: Padded, B: int) -> Start:
    """``B`` structures at rest: in the static equilibrium (:attr:`Padded.rest_state`): against the stop with no
    reaction (no gap, the paper), held by it (an interference), or free (a clearance)."""
    return Start(np.full(B, pad.rest_state), np.zeros((B, pad.m)), np.zeros((B, pad.m)))


def given(prob: Problem, x, v) -> Start:
    """One structure started from the physical state ``x, v`` (in ``prob``'s contact coordinates: the contact
    coordinate ``u`` last, :func:`plbar.model.contact_coordinates`), for :func:`run`: free (state II) where ``u < d``
    (the stop's gap), or at the stop and leaving it (``v_c < 0``); held (state I) at the stop with ``v_c = 0``.  A
    start past the stop, or at it and moving into it, is refused (:class:`plbar.errors.InputError`).  The modal
    coordinates are those of ``x - x_s``, ``x_s`` the state's static equilibrium (FORMULATION §9), padded as
    :func:`plbar.motion.padded` pads them."""
    s, st = prob.system, prob.statics
    n = s.n
    m = max(s.w1.size, s.w2.size)
    x, v = (np.asarray(a, float) for a in (x, v))
    if x.shape != (n,) or v.shape != (n,) or not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
        raise InputError(f"a start needs finite x and v with one entry per DOF, shape ({n},); got shapes "
                         f"{x.shape}, {v.shape}")
    d, u, vc = st.gap, x[-1], v[-1]
    tol = 1e-12 * max(abs(d), float(np.max(np.abs(x))), 1e-300)
    if u > d + tol or (u >= d - tol and vc > 0.0):
        raise InputError(f"the start is past the stop or moving into it (u = {u:.6g}, v_c = {vc:.6g}, the stop at "
                         f"u = {d:.6g}): start on the free side, or at the stop at rest or leaving it")
    eta, vel = np.zeros((1, m)), np.zeros((1, m))
    if u < d - tol or vc < 0.0:
        state, M = FREE, s.M
        eta[0, :s.w2.size] = s.V2.T @ (M @ (x - st.x2))
        vel[0, :s.w2.size] = s.V2.T @ (M @ v)
    else:
        state, M = STUCK, s.M[:-1, :-1]
        eta[0, :s.w1.size] = s.V1.T @ (M @ (x - st.x1)[:-1])
        vel[0, :s.w1.size] = s.V1.T @ (M @ v[:-1])
    return Start(np.array([state]), eta, vel)


@dataclass(frozen=True, kw_only=True)
class Run(Record):
    """What a batched simulation recorded: per trajectory ``b`` and recorded forcing period ``r``
    (a :class:`plbar.util.record.Record`: ``T, phi, status, events``, and the accounts below).

    Attributes
    ----------
    T, phi : ndarray, shape (B,)
    status : ndarray of int, shape (B,)
        A code of :data:`plbar.util.record.STATUS`: 0 ok, 1 stopped by a chattering contact, 2 stalled.
    events : ndarray of dtype EVENT, shape (E,)
        The recorded window's events: ``traj``, ``time`` (absolute), ``kind`` (1 opening, 2 impact, 3 rebound,
        4 the impact that ends a chattering sequence), ``loss`` (``v`` nan: not kept).
    periods, record : int
        Forcing periods simulated, and how many of the last ones are recorded (``R``).
    impacts, openings : ndarray of int, shape (B, R)
    loss : ndarray, shape (B, R)
        Impact loss (Eq. (14)) per recorded period.
    d_eq, d_w : ndarray, shape (B, R)
        ``sum_j w_j Psi_j`` and ``sum_j Psi_j`` over each recorded period (both states).
    work_rec, stuck, amp : ndarray, shape (B, R)
        Work of the load, time in state I, largest ``-x_c`` per recorded period.
    strobe_x, strobe_v : ndarray, shape (B, R + 1, n)
        Physical state at the boundaries of the recorded periods (after any event there).
    strobe_state : ndarray of int, shape (B, R + 1)
    work, losses, energy0, energy_end : ndarray, shape (B,)
        Totals over the whole run: the energy budget is ``work - losses - viscous - (energy_end - energy0)``.
    viscous, viscous_rec : ndarray, shapes (B,), (B, R)
        Energy taken by inherent damping over the whole run and per recorded period (0 undamped).
    stop_time : ndarray, shape (B,)
        Where a stopped trajectory (``status`` not 0) stopped (absolute time); nan where it ran to the end.
    final : Start
        The state at the end (to continue from).
    rounds : int
        Rounds (certified steps and switches) over all trajectories.
    """

    periods: int
    record: int
    impacts: np.ndarray
    openings: np.ndarray
    loss: np.ndarray
    d_eq: np.ndarray
    d_w: np.ndarray
    work_rec: np.ndarray
    stuck: np.ndarray
    amp: np.ndarray
    strobe_x: np.ndarray
    strobe_v: np.ndarray
    strobe_state: np.ndarray
    work: np.ndarray
    losses: np.ndarray
    energy0: np.ndarray
    energy_end: np.ndarray
    final: Start
    rounds: int
    viscous: np.ndarray = None
    viscous_rec: np.ndarray = None
    stop_time: np.ndarray = None

    @property
    def messages(self) -> list[str]:
        """One line for each trajectory that stopped before the end (none when all ran to the end)."""
        out = []
        bad = np.flatnonzero(self.status != OK)
        for b, why in zip(bad, messages(self.status[bad])):
            t = np.nan if self.stop_time is None else float(self.stop_time[b])
            out.append(f"T = {self.T[b]:.10g}: stopped at t = {t:.10g} (forcing period {int(t // self.T[b])} of "
                       f"{self.periods}) by {why}")
        return out

    @property
    def energy_residual(self) -> np.ndarray:
        """``(work - losses - viscous - (energy_end - energy0)) / max(|work|, energies)``: zero up to round-off."""
        scale = np.maximum.reduce([np.abs(self.work), self.energy0, self.energy_end, np.full(self.T.size, 1e-300)])
        visc = 0.0 if self.viscous is None else self.viscous
        return (self.work - self.losses - visc - (self.energy_end - self.energy0)) / scale

    def __repr__(self) -> str:
        return build("Run", {"B": self.T.size, "T": rng(self.T), "periods": self.periods, "record": self.record,
                             "stopped": int(np.sum(self.status != 0)),
                             "impacts/T": rng(self.impacts.mean(axis=1)) if self.record else "-",
                             "energy_residual": rng(np.abs(self.energy_residual)), "rounds": self.rounds},
                     listing(self.messages, 3))


def _check(T, phi, periods, record):
    T = np.atleast_1d(np.asarray(T, float))
    if T.ndim != 1 or not T.size or not np.all(np.isfinite(T) & (T > 0)):
        raise InputError("forcing periods T must be finite and > 0")
    phi = np.broadcast_to(np.asarray(phi, float), T.shape).copy()
    if not np.all(np.isfinite(phi)):
        raise InputError("phase phi must be finite")
    if int(periods) != periods or periods < 1:
        raise InputError(f"periods = {periods!r} must be a positive integer (forcing periods simulated)")
    if int(record) != record or not 0 <= record <= periods:
        raise InputError(f"record = {record!r} must be an integer in [0, periods = {periods}]")
    return T, phi, int(periods), int(record)


def run(prob: Problem | Padded, T, phi=0.0, periods: int = 1000, record: int = 100, start: Start | None = None,
        progress=None, accounts: bool = True, halt: np.ndarray | None = None) -> Run:
    """Simulate trajectories from ``start`` (default: at rest against the wall) and record the last periods.

    Each trajectory runs in the compiled kernel (:mod:`plbar.motion.kernel`), one at a time, on
    every core (:func:`plbar.util.threads.map_chunks`); the results do not depend on the number of
    threads.  The first call after an install compiles the kernel (cached on disk).

    Parameters
    ----------
    prob : Problem or Padded
    T : array_like, shape (B,)
        Forcing periods.
    phi : float or array_like
        Forcing phases (load ``q cos(2 pi t / T - phi)``, Eq. (1)); 0 for a survey.
    periods : int
        Forcing periods simulated.
    record : int
        How many of the last periods are recorded (statistics, boundary states, events).
    start : Start, optional
    progress : callable, optional
        Called with the number of periods completed by the slowest trajectory since the last call.
    accounts : bool
        Account the pieces (work, ``Psi`` sums, amplitude); without, only events and boundary states are
        recorded (a replay that checks the switches) and the energy budget is not closed (``work`` is 0).
    halt : ndarray, optional
        A :func:`halt_flag` another thread may set to stop the simulation; a Ctrl-C in the calling thread sets it
        too, so that the kernels on the other threads return before the KeyboardInterrupt goes on.

    Returns
    -------
    Run

    Raises
    ------
    Stopped
        If ``halt`` was set.
    """
    from .kernel import advance, jit  # numba: only a simulation pays its import (and first compile)
    from .kernel import data as D

    pad = prob if isinstance(prob, Padded) else padded(prob)
    T, phi, periods, record = _check(T, phi, periods, record)
    s0 = start or rest(pad, T.size)
    B = T.size
    tr = D.trajectories(T, phi, s0.state, s0.eta, s0.vel)
    rc = D.records(B, pad.m, record, 4 * record + 16, periods - record)
    acc = D.accounts(B, record, accounts)
    _, ti, z, tot = tr
    if record == periods:                         # the boundary at t = 0 is recorded too
        rc[2][:, 0], rc[3][:, 0], rc[4][:, 0] = z[:, 0], z[:, 1], ti[:, D.STATE]
    e0 = energy(pad, ti[:, D.STATE], z[:, 0], z[:, 1])
    halt = halt_flag() if halt is None else halt
    step = partial(advance, D.model(pad), tr, damping=D.damping(pad), acc=acc, large=D.large(pad), halt=halt)
    rc = _drive(step, ti, rc, periods, progress, halt)
    jit.mark_compiled(advance, kind(pad, accounts))
    return _collect(pad, T, phi, periods, record, tr, rc, acc, e0)


def prepare(prob: Problem | Padded, accounts: bool = True) -> None:
    """Have the compiled kernel for simulations of ``prob`` ready in this process (one forcing period simulated).

    The first call after an install compiles it (cached on disk); later sessions load it from the cache.  A study
    calls this before its worker processes are forked, so that they inherit the loaded kernel instead of each
    loading (or compiling) it.
    """
    run(prob, [1.0], 0.0, 1, 1, accounts=accounts)


def _collect(pad: Padded, T, phi, periods, record, tr, rc, acc, e0) -> Run:
    """The :class:`Run` of a finished simulation (events per trajectory in order, boundary states physical)."""
    from .kernel import data as D

    per, ev, sx, sv, ss = rc.per, rc.ev, rc.sx, rc.sv, rc.ss
    _, ti, z, tot = tr
    B = T.size
    state = ti[:, D.STATE].copy()
    e_end = energy(pad, state, z[:, 0], z[:, 1])
    ev_n = ti[:, D.EVENTS]
    rows = np.repeat(np.arange(B), ev_n)
    cols = np.concatenate([np.arange(k) for k in ev_n]) if B else np.zeros(0, int)
    a = acc if acc is not None else np.zeros((B, record, 6))
    tf = tr[0]
    stop = np.where(ti[:, D.STATUS] != OK, ti[:, D.PERIOD] * tf[:, D.T] + tf[:, D.TP] + tf[:, D.P], np.nan)
    return Run(T=T, phi=phi, status=ti[:, D.STATUS].copy(),
               events=events(ev[rows, cols, D.TIME], ev[rows, cols, D.KIND].astype(int), ev[rows, cols, D.LOSS],
                             traj=rows),
               periods=periods, record=record, impacts=per[..., D.IMPACTS].astype(int),
               openings=per[..., D.OPENINGS].astype(int), loss=per[..., D.LOSS].copy(), d_eq=a[..., D.D_EQ].copy(),
               d_w=a[..., D.D_W].copy(), work_rec=a[..., D.WORK_REC].copy(), stuck=a[..., D.STUCK_T].copy(),
               amp=a[..., D.AMP].copy(), strobe_x=_physical(pad, ss, sx, True), strobe_v=_physical(pad, ss, sv),
               strobe_state=ss, work=tot[:, D.WORK].copy(), losses=tot[:, D.LOSSES].copy(), energy0=e0,
               energy_end=e_end, final=Start(state, z[:, 0].copy(), z[:, 1].copy()),
               rounds=int(ti[:, D.ROUNDS].sum()), viscous=tot[:, D.VISC].copy(), viscous_rec=a[..., D.VISC_REC].copy(),
               stop_time=stop)


def _physical(pad: Padded, state, modal, positions: bool = False) -> np.ndarray:
    """Physical states ``V[state] eta`` of modal boundary states ``(B, R + 1, m)`` (``positions``: plus the state's
    static equilibrium, a gap's)."""
    out = np.zeros(modal.shape[:2] + (pad.n,))
    for s in (0, 1):
        sel = state == s
        out[sel] = modal[sel] @ pad.V[s].T + (pad.xs[s] if positions else 0.0)
    return out


def _drive(step, ti, rc, periods: int, progress, halt):
    """Advance every trajectory to the end, in blocks of periods (progress between them), on every core.

    ``step(rc, idx, stop)`` advances trajectories ``idx`` to period ``stop``; where one has no room left to
    record an event it stops there, the records grow and it goes on.  Raises :class:`Stopped` once ``halt[0]``
    is set; an exception here (a Ctrl-C) sets it first, so no kernel runs on after it.
    """
    from .kernel import data as D

    block = periods if progress is None else 1
    done, stop = 0, 0
    while stop < periods:
        stop = min(periods, stop + block)
        t0 = time.perf_counter()
        while True:
            idx = np.flatnonzero((ti[:, D.STATUS] == OK) & (ti[:, D.PERIOD] < stop))
            if not idx.size:
                break
            ti[:, D.NEED] = 0
            off_main(partial(_on_threads, step, rc, idx, stop), partial(halt.fill, 1))   # a Ctrl-C: halt at once
            if halt[0]:
                raise Stopped("the simulation was stopped")
            if not ti[:, D.NEED].any():
                break
            rc = D.grow_events(rc)
        if progress is not None:
            alive = ti[:, D.STATUS] == OK
            slow = int(ti[alive, D.PERIOD].min()) if alive.any() else periods
            if slow > done:
                progress(slow - done)
                done = slow
            block = max(1, min(periods, int(block * min(4.0, 0.5 / max(time.perf_counter() - t0, 1e-3)))))
    if progress is not None and periods > done:
        progress(periods - done)                     # the last periods (and any stopped trajectory's rest)
    return rc


def _on_threads(step, rc, idx, stop: int) -> None:
    """``step`` the trajectories ``idx`` to period ``stop`` on every core (each thread a contiguous share: one
    compiled layout)."""
    n = max(1, min(n_threads(), idx.size))
    map_chunks(lambda a, b: [step(rc=rc, idx=np.ascontiguousarray(idx[i::n]), stop=stop) for i in range(a, b)], n, 1)


def energy(pad: Padded, state, eta, vel) -> np.ndarray:
    """Mechanical energy ``sum (etadot^2 + w^2 eta^2) / 2`` (Eqs. (12)-(13)) of rows in ``state``, plus the state's
    static energy (a gap's, :class:`plbar.model.Statics`; 0 without one), less ``g . eta`` (the potential of a
    constant load on a rigid-body mode, :attr:`Padded.g`; 0 without one)."""
    w = pad.w[state]
    out = 0.5 * np.sum(vel * vel + (w * eta) ** 2, axis=-1) + pad.es[state]
    g = pad.g[state]
    return out - np.sum(g * eta, axis=-1) if np.any(g) else out
