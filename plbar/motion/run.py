"""Run a batch of trajectories for many forcing periods and keep what the survey needs (:class:`Run`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model import Problem
from ..util.reprs import build, rng
from .accounting import Pieces, account
from .integrate import CHATTER, MAX_STALL, MAX_ZERO, STALLED, Batch, decide, energy, strobe, switch
from .model import STUCK, Padded, padded

__all__ = ["Run", "Start", "run", "rest"]

_FLUSH = 20000   #: pieces accounted at once


@dataclass(frozen=True)
class Start:
    """Initial states of a batch, in the padded modal coordinates of :mod:`.model`.

    ``state`` (B,) is ``STUCK`` (0) or ``FREE`` (1); ``eta, vel`` (B, m).
    """

    state: np.ndarray
    eta: np.ndarray
    vel: np.ndarray


def rest(pad: Padded, B: int) -> Start:
    """``B`` bars at rest against the wall."""
    return Start(np.full(B, STUCK), np.zeros((B, pad.m)), np.zeros((B, pad.m)))


@dataclass(frozen=True)
class Run:
    """What a batched simulation recorded: per trajectory ``b`` and recorded forcing period ``r``.

    Attributes
    ----------
    T, phi : ndarray, shape (B,)
    periods, record : int
        Forcing periods simulated, and how many of the last ones are recorded (``R``).
    status : ndarray of int, shape (B,)
        0 ok, 1 stopped by a chattering contact, 2 stalled.
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
    events : dict of ndarray
        The recorded window's events: ``traj``, ``time`` (absolute), ``kind`` (1 opening, 2 impact), ``loss``.
    work, losses, energy0, energy_end : ndarray, shape (B,)
        Totals over the whole run: the energy budget is ``work - losses - viscous - (energy_end - energy0)``.
    viscous, viscous_rec : ndarray, shapes (B,), (B, R)
        Energy taken by inherent damping over the whole run and per recorded period (0 undamped).
    final : Start
        The state at the end (to continue from).
    rounds : int
        Batched rounds used.
    """

    T: np.ndarray
    phi: np.ndarray
    periods: int
    record: int
    status: np.ndarray
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
    events: dict
    work: np.ndarray
    losses: np.ndarray
    energy0: np.ndarray
    energy_end: np.ndarray
    final: Start
    rounds: int
    viscous: np.ndarray = None
    viscous_rec: np.ndarray = None

    @property
    def energy_residual(self) -> np.ndarray:
        """``(work - losses - viscous - (energy_end - energy0)) / max(|work|, energies)``: zero up to round-off."""
        scale = np.maximum.reduce([np.abs(self.work), self.energy0, self.energy_end, np.full(self.T.size, 1e-300)])
        visc = 0.0 if self.viscous is None else self.viscous
        return (self.work - self.losses - visc - (self.energy_end - self.energy0)) / scale

    def __repr__(self) -> str:
        return build("Run", {"B": self.T.size, "T": rng(self.T), "periods": self.periods, "record": self.record,
                             "impacts/T": rng(self.impacts.mean(axis=1)) if self.record else "-",
                             "energy_residual": rng(np.abs(self.energy_residual)), "rounds": self.rounds})


class _Recorder:
    """Collects pieces, events and period boundaries while the batch runs (internal)."""

    def __init__(self, pad: Padded, b: Batch, record: int, accounts: bool = True):
        B, R, n = b.T.size, record, pad.n
        self.accounts = accounts
        self.pad, self.b, self.R, self.first = pad, b, R, b.periods - R
        self.pieces: list[Pieces] = []
        self.size = 0
        z = np.zeros((B, R))
        self.impacts, self.openings = np.zeros((B, R), int), np.zeros((B, R), int)
        self.loss, self.d_eq, self.d_w, self.work_rec, self.stuck, self.amp, self.visc_rec = \
            (z.copy() for _ in range(7))
        self.sx, self.sv = np.zeros((B, R + 1, n)), np.zeros((B, R + 1, n))
        self.ss = np.zeros((B, R + 1), int)
        self.work, self.losses, self.visc = np.zeros(B), np.zeros(B), np.zeros(B)
        self.ev: list[tuple] = []

    def boundary(self, idx, k, state, eta, vel):
        """State at the boundary ``k`` (0 .. periods) of ``idx``, if recorded."""
        r = k - self.first
        sel = r >= 0
        if sel.any():
            i, rr, st = idx[sel], r[sel], state[sel]
            self.sx[i, rr] = np.einsum("bij,bj->bi", self.pad.V[st], eta[sel])
            self.sv[i, rr] = np.einsum("bij,bj->bi", self.pad.V[st], vel[sel])
            self.ss[i, rr] = st

    def events(self, idx, period, time, kind, loss):
        np.add.at(self.losses, idx, loss)
        r = period - self.first
        sel = r >= 0
        if sel.any():
            i, rr = idx[sel], r[sel]
            np.add.at(self.impacts, (i, rr), kind[sel] == 2)
            np.add.at(self.openings, (i, rr), kind[sel] == 1)
            np.add.at(self.loss, (i, rr), loss[sel])
            self.ev.append((i, time[sel], kind[sel], loss[sel]))

    def add(self, pcs: Pieces):
        if not self.accounts:
            return
        self.pieces.append(pcs)
        self.size += len(pcs)
        if self.size >= _FLUSH:
            self.flush()

    def flush(self):
        if not self.pieces:
            return
        pcs = Pieces(*(np.concatenate([getattr(p, k) for p in self.pieces])
                       for k in ("traj", "period", "state", "tp", "tau", "eta", "vel")))
        self.pieces, self.size = [], 0
        full = pcs.period >= self.first
        acc = account(self.pad, pcs, self.b.W, self.b.phi, full)
        np.add.at(self.work, pcs.traj, acc.work)
        np.add.at(self.visc, pcs.traj, acc.viscous)
        i, r = pcs.traj[full], pcs.period[full] - self.first
        np.add.at(self.visc_rec, (i, r), acc.viscous[full])
        for name in ("d_eq", "d_w", "stuck"):
            np.add.at(getattr(self, name), (i, r), getattr(acc, name)[full])
        np.add.at(self.work_rec, (i, r), acc.work[full])
        np.maximum.at(self.amp, (i, r), acc.amp[full])


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
        progress=None, accounts: bool = True) -> Run:
    """Simulate a batch of forcing periods from ``start`` (default: at rest against the wall) and record the end.

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
        Called with the number of periods completed by the slowest trajectory.
    accounts : bool
        Account the pieces (work, ``Psi`` sums, amplitude); without, only events and boundary states are
        recorded (a replay that checks the switches) and the energy budget is not closed (``work`` is 0).

    Returns
    -------
    Run
    """
    pad = prob if isinstance(prob, Padded) else padded(prob)
    T, phi, periods, record = _check(T, phi, periods, record)
    s0 = start or rest(pad, T.size)
    b = Batch(pad, T, phi, periods, s0.state.copy(), s0.eta.copy(), s0.vel.copy())
    rec = _Recorder(pad, b, record, accounts)
    e0 = energy(pad, b.state, b.eta, b.vel)
    all_idx = np.arange(T.size)
    rec.boundary(all_idx, np.zeros(T.size, int), b.state, b.eta, b.vel)
    rounds = _loop(b, rec, progress)
    rec.flush()
    e_end = energy(pad, b.state, b.eta, b.vel)
    ev = rec.ev
    events = {k: (np.concatenate([e[j] for e in ev]) if ev else np.zeros(0, int if k in ("traj", "kind") else float))
              for j, k in enumerate(("traj", "time", "kind", "loss"))}
    order = np.argsort(events["traj"], kind="stable")            # per trajectory, in order of occurrence
    events = {k: v[order] for k, v in events.items()}
    return Run(T, phi, periods, record, b.status, rec.impacts, rec.openings, rec.loss, rec.d_eq, rec.d_w,
               rec.work_rec, rec.stuck, rec.amp, rec.sx, rec.sv, rec.ss, events, rec.work, rec.losses, e0, e_end,
               Start(b.state.copy(), b.eta.copy(), b.vel.copy()), rounds, rec.visc, rec.visc_rec)


def _loop(b: Batch, rec: _Recorder, progress) -> int:
    rounds, done = 0, 0
    while True:
        idx = np.flatnonzero(b.alive)
        if idx.size == 0:
            if progress is not None and b.periods > done:
                progress(b.periods - done)             # the last periods (and any stalled trajectory's rest)
            return rounds
        rounds += 1
        event, new_p, eta, vel = decide(b, idx)
        b.stall[idx] += 1
        if event.any():
            _events(b, rec, idx[event], eta[event], vel[event])
        a = idx[~event]
        b.p[a] = new_p[~event]
        edge = a[b.p[a] >= b.T[a] - b.tp[a]]
        if edge.size:
            rec.add(b.pieces(edge, b.p[edge]))
            eta_s, vel_s = strobe(b, edge)
            rec.boundary(edge, b.period[edge], b.state[edge], eta_s, vel_s)
        stalled = idx[b.stall[idx] > MAX_STALL]
        b.status[stalled], b.alive[stalled] = STALLED, False
        if progress is not None and b.alive.any():
            slow = int(b.period[b.alive].min())
            if slow > done:
                progress(slow - done)
                done = slow


def _events(b: Batch, rec: _Recorder, e, eta, vel) -> None:
    """Account the segments that end in an event, switch, and count zero-length segments."""
    zero_len = b.p[e] == 0.0
    rec.add(b.pieces(e, b.p[e]))
    time = b.period[e] * b.T[e] + b.tp[e] + b.p[e]
    period = b.period[e].copy()
    kind, loss = switch(b, e, eta, vel)
    rec.events(e, period, time, kind, loss)
    b.zero[e] = np.where(zero_len, b.zero[e] + 1, 0)
    b.stall[e] = 0
    chat = e[b.zero[e] > MAX_ZERO]
    b.status[chat], b.alive[chat] = CHATTER, False
