"""The batched event-driven simulator: many forcing periods advanced together, exactly (FORMULATION §§2-3, §8).

Every trajectory of a batch has its own forcing period ``T`` and phase
``phi`` (the load is ``q cos(W t - phi)``, ``W = 2 pi / T``) and the same bar.
All of them advance together, one numpy round at a time: each round
evaluates every trajectory's closed-form segment (:func:`plbar.response.segment`,
exact at resonance) at its current point and either steps on by a
*certified* distance, over which its margin cannot cross zero
(:mod:`.events`), or switches: the gap opens (``x^II = E x^I``) or the
bar comes back to the wall in a plastic impact that keeps the momenta of
the DOFs other than the contact and loses ``S v_c^2 / 2`` (Eq. (14)).
Every forcing period boundary ``t0 + k T`` is a stroboscopic sample and
restarts the segment there, so that no segment spans a period and the
forcing phase stays within one period (no loss of digits over 1,000
periods).

The parts of segments between these points (*pieces*) are accounted in
bulk (:mod:`.accounting`).  Nothing here is shared with :func:`plbar.simulate`
but the model: the two are independent checks of each other.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..response import segment
from .accounting import Pieces
from .events import decide_step
from .margin import taylor
from .model import FREE, STUCK, Padded

__all__ = ["Batch", "OK", "CHATTER", "STALLED", "TINY", "MAX_ZERO", "MAX_STALL"]

OK, CHATTER, STALLED = 0, 1, 2   #: trajectory status
TINY = 1e-12        #: step (in periods) where no derivative decides, and the snap of a step onto a period boundary
MAX_ZERO = 50       #: consecutive zero-length segments before a trajectory is stopped as chattering
MAX_STALL = 5000    #: rounds without an event or a period boundary before a trajectory is stopped as stalled
CAP = 0.25          #: longest step, in forcing periods (the remainder bound is taken over it)
ORDER = 8           #: order of the Taylor model of the margin
DEEP_MAX = 40       #: highest order of the deep model (where no derivative up to ORDER is significant)


@dataclass
class Batch:
    """Mutable state of a batch of trajectories (internal to :func:`plbar.motion.run`).

    Times: ``period`` is the 0-based forcing period a trajectory is in, ``tp``
    the start of its current segment within that period and ``p`` how far the
    segment is certified free of crossings.  Absolute time is
    ``t0 + period T + tp + p``; the forcing phase uses ``phi_eff = phi - W t0``.
    """

    pad: Padded
    T: np.ndarray
    phi: np.ndarray
    periods: int
    state: np.ndarray
    eta: np.ndarray
    vel: np.ndarray
    period: np.ndarray = field(init=False)
    tp: np.ndarray = field(init=False)
    p: np.ndarray = field(init=False)
    zero: np.ndarray = field(init=False)
    stall: np.ndarray = field(init=False)
    status: np.ndarray = field(init=False)
    alive: np.ndarray = field(init=False)

    def __post_init__(self):
        B = self.T.size
        self.W = 2 * np.pi / self.T
        self.period = np.zeros(B, int)
        self.tp, self.p = np.zeros(B), np.zeros(B)
        self.zero, self.stall = np.zeros(B, int), np.zeros(B, int)
        self.status = np.full(B, OK)
        self.alive = np.ones(B, bool)

    def flow(self, idx, u):
        """Modal ``eta, etadot`` of trajectories ``idx`` at local times ``u`` of their current segments."""
        st = self.state[idx]
        ph = self.phi[idx][:, None]
        zeta = None if self.pad.zeta is None else self.pad.zeta[st]
        return segment(self.pad.w[st], self.pad.f[st], self.W[idx][:, None], self.tp[idx][:, None], u[:, None],
                       self.eta[idx], self.vel[idx], np.cos(ph), np.sin(ph), zeta=zeta)

    def pieces(self, idx, tau) -> Pieces:
        """The current segments of ``idx`` up to ``tau``, as pieces."""
        return Pieces(idx.copy(), self.period[idx].copy(), self.state[idx].copy(), self.tp[idx].copy(),
                      np.asarray(tau, float).copy(), self.eta[idx].copy(), self.vel[idx].copy())


def _certify(b: Batch, idx, eta, vel, K: int):
    """``(event, step)`` of trajectories ``idx`` from a Taylor model of order ``K`` (:mod:`.events`)."""
    pad = b.pad
    st = b.state[idx]
    t = b.tp[idx] + b.p[idx]
    cap = np.minimum(CAP * b.T[idx], np.maximum(b.T[idx] - t, 0.0))
    zeta, cv = (None, None) if pad.zeta is None else (pad.zeta[st], pad.cv[st])
    d, rem, scale, Om = taylor(pad.c[st], pad.rq[st], pad.w[st], pad.f[st], eta, vel, b.W[idx], t, b.phi[idx],
                               cap, K, zeta, cv)
    event, v, found = decide_step(d, rem, scale, Om * cap, pad.size[st])
    return event, np.where(found, v / Om, -1.0)


def decide(b: Batch, idx):
    """One round for trajectories ``idx``: ``(event, new_p, eta, vel)`` at their current points.

    A Taylor model of order :data:`ORDER` decides; where no derivative up to it
    is significant (a bar started at rest, loaded far from its contact) one of
    order ``min(2 m + 4, DEEP_MAX)`` does; where that fails too, a tiny step.
    """
    eta, vel = b.flow(idx, b.p[idx])
    event, step = _certify(b, idx, eta, vel, ORDER)
    deep = np.flatnonzero(step < 0)
    if deep.size:
        ev, stp = _certify(b, idx[deep], eta[deep], vel[deep], min(2 * b.pad.m + 4, DEEP_MAX))
        event[deep], step[deep] = ev, stp
    step = np.where(step > 0, step, TINY * b.T[idx])
    new_p = b.p[idx] + step
    end = b.T[idx] - b.tp[idx]
    new_p = np.where(new_p >= end - TINY * b.T[idx], end, new_p)
    return event, new_p, eta, vel


def switch(b: Batch, idx, eta, vel):
    """Apply the event of trajectories ``idx`` at their current points; returns ``(kind, loss)``.

    kind 1: the gap opens (I -> II, ``x^II = E x^I``); kind 2: plastic impact (II -> I, Eq. (10)),
    loss ``S v_c^2 / 2`` (Eq. (14)); for a truncated system the modal kinetic energy difference.
    """
    pad = b.pad
    st = b.state[idx]
    kind = np.where(st == STUCK, 1, 2)
    loss = np.zeros(idx.size)
    opening = st == STUCK
    new_e = np.where(opening[:, None], eta @ pad.open_map.T, eta @ pad.impact_pos.T)
    new_v = np.where(opening[:, None], vel @ pad.open_map.T, vel @ pad.impact_vel.T)
    imp = ~opening
    if pad.truncated:
        loss[imp] = 0.5 * (np.sum(vel[imp] ** 2, axis=1) - np.sum(new_v[imp] ** 2, axis=1))
    else:
        loss[imp] = 0.5 * pad.S * (vel[imp] @ pad.vc_row) ** 2
    b.tp[idx] += b.p[idx]
    b.p[idx] = 0.0
    b.eta[idx], b.vel[idx] = new_e, new_v
    b.state[idx] = np.where(opening, FREE, STUCK)
    return kind, loss


def strobe(b: Batch, idx):
    """Restart the segments of ``idx`` at their period boundary (state carried over exactly)."""
    eta, vel = b.flow(idx, b.T[idx] - b.tp[idx])
    b.eta[idx], b.vel[idx] = eta, vel
    b.period[idx] += 1
    b.tp[idx] = 0.0
    b.p[idx] = 0.0
    b.stall[idx] = 0
    done = b.period[idx] >= b.periods
    b.alive[idx[done]] = False
    return eta, vel


def energy(pad: Padded, state, eta, vel) -> np.ndarray:
    """Mechanical energy ``sum (etadot^2 + w^2 eta^2) / 2`` (Eqs. (12)-(13)) of rows in ``state``."""
    w = pad.w[state]
    return 0.5 * np.sum(vel * vel + (w * eta) ** 2, axis=-1)
