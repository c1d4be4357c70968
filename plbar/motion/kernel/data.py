"""The arrays the kernel works on: a few flat arrays in small tuples, with named columns.

Small tuples of plain arrays keep the compiled code small (and its first compile short);
the column names below are the only way the kernel and :mod:`plbar.motion.run` index them.

* model ``md = (modal, margin, maps, vc_row, S, truncated, e)`` (``e`` the coefficient of restitution):
  ``modal[W | F | C, state]`` the
  frequencies, modal loads and margin weights, ``margin[RQ | SIZE, state]``, ``maps[OPEN | IMPACT_POS |
  IMPACT_VEL | OPEN_VEL]`` the switch maps (:class:`plbar.motion.Padded`);
* damping: None (undamped: no damped code is compiled) or ``damping[state, ZETA | CV]``;
* trajectories ``tr = (tf, ti, z, tot)``: ``tf[b, T | OMEGA | PHI | TP | P]``, ``ti[b, PERIOD | STATE | ZEROS |
  STALL | STATUS | ROUNDS | NEED | EVENTS | SHORT]``, the modal state ``z[b, 0 | 1]`` (``eta, eta'``) at the start of
  the current segment and the totals ``tot[b, WORK | LOSSES | VISC]``; a call may stop anywhere (a block of
  periods done, or no room to record an event: ``NEED``) and the next one goes on;
* records ``rc = (per, ev, sx, sv, ss)``: per recorded period ``per[b, r, IMPACTS | OPENINGS | LOSS]``, the
  recorded events ``ev[b, i, TIME | KIND | LOSS]`` (``ti[b, EVENTS]`` of them), the modal states at the
  recorded boundaries ``sx, sv`` and their states ``ss``;
* accounts: None (a replay of the switches: no accounting code is compiled) or ``acc[b, r, D_EQ | D_W |
  WORK_REC | STUCK_T | AMP | VISC_REC]``.
"""

from __future__ import annotations

import numpy as np

from ..model import IMPACT, OPENS, REBOUND, STICK   # noqa: F401 (the event kinds, here by their kernel names)

__all__ = ["accounts", "damping", "grow_events", "model", "records", "trajectories"]

W, F, C = 0, 1, 2
RQ, SIZE = 0, 1
OPEN, IMPACT_POS, IMPACT_VEL, OPEN_VEL = 0, 1, 2, 3
ZETA, CV = 0, 1
T, OMEGA, PHI, TP, P = 0, 1, 2, 3, 4
PERIOD, STATE, ZEROS, STALL, STATUS, ROUNDS, NEED, EVENTS, SHORT = 0, 1, 2, 3, 4, 5, 6, 7, 8
IMPACTS, OPENINGS, LOSS = 0, 1, 2
TIME, KIND = 0, 1
WORK, LOSSES, VISC = 0, 1, 2
D_EQ, D_W, WORK_REC, STUCK_T, AMP, VISC_REC = 0, 1, 2, 3, 4, 5


def _f64(a):
    return np.ascontiguousarray(a, dtype=np.float64)


def model(pad) -> tuple:
    """The kernel's view of a :class:`plbar.motion.Padded`."""
    return (_f64(np.stack([pad.w, pad.f, pad.c])), _f64(np.stack([pad.rq, pad.size])),
            _f64(np.stack([pad.open_map, pad.impact_pos, pad.impact_vel,
                                pad.open_map if pad.open_vel is None else pad.open_vel])), _f64(pad.vc_row),
            float(0.0 if pad.truncated else pad.S), bool(pad.truncated), float(pad.restitution))


def damping(pad):
    """``damping[state, ZETA | CV]``, or None for an undamped system."""
    return None if pad.zeta is None else _f64(np.stack([pad.zeta, pad.cv], axis=1))


SPLIT_MIN = 12   #: systems with fewer modes never split (their fastest mode is not much faster than the rest)


def large(pad):
    """Not None for a system of :data:`SPLIT_MIN` modes or more (the split model, :mod:`.split`)."""
    return np.ones(1) if pad.m >= SPLIT_MIN else None


def trajectories(T, phi, state, eta, vel) -> tuple:
    """Trajectories at the start of their first forcing period."""
    B = T.size
    tf = np.zeros((B, 5))
    tf[:, 0], tf[:, 1], tf[:, 2] = T, 2 * np.pi / T, phi
    ti = np.zeros((B, 9), np.int64)
    ti[:, 1] = state
    return tf, ti, _f64(np.stack([np.asarray(eta, float), np.asarray(vel, float)], axis=1)), np.zeros((B, 3))


def records(B: int, m: int, R: int, capacity: int) -> tuple:
    """Empty records for ``B`` trajectories, ``R`` periods recorded, room for ``capacity`` events each."""
    return (np.zeros((B, R, 3)), np.zeros((B, capacity, 3)), np.zeros((B, R + 1, m)), np.zeros((B, R + 1, m)),
            np.zeros((B, R + 1), np.int64))


def accounts(B: int, R: int, on: bool):
    """Empty per-period accounts, or None (no accounts)."""
    return np.zeros((B, R, 6)) if on else None


def grow_events(rc: tuple) -> tuple:
    """The same records with twice the room for events."""
    ev = rc[1]
    out = np.zeros((ev.shape[0], 2 * ev.shape[1], 3))
    out[:, :ev.shape[1]] = ev
    return rc[:1] + (out,) + rc[2:]
