"""The arrays the kernel works on: a few flat arrays in small named records, with named columns.

Small records of plain arrays (NamedTuples: numba passes them as typed tuples) keep the compiled code small (and
its first compile short); the fields and the column names below are the only way the kernel and
:mod:`plbar.motion.run` reach them.

* :class:`Model` (``md``, :func:`model`): ``md.modal[W | F | C | G, state]`` the frequencies, modal loads, margin
  weights and constant accelerations (a constant load's on a rigid-body mode), ``md.margin[RQ | SIZE | G0,
  state]``, ``md.maps[OPEN | IMPACT_POS | IMPACT_VEL | OPEN_VEL]`` the switch maps and ``md.offsets[OPEN_OFF |
  IMPACT_OFF]`` what they add (a gap's; :class:`plbar.motion.Padded`), the contact row, the impact mass, whether
  truncated, the restitution;
* damping: None (undamped: no damped code is compiled) or ``damping[state, ZETA | CV]``;
* :class:`Trajectories` (``tr``): ``tr.tf[b, T | OMEGA | PHI | TP | P]``, ``tr.ti[b, PERIOD | STATE | ZEROS |
  STALL | STATUS | ROUNDS | NEED | EVENTS | SHORT]``, the modal state ``tr.z[b, 0 | 1]`` (``eta, eta'``) at the
  start of the current segment and the totals ``tr.tot[b, WORK | LOSSES | VISC]``; a call may stop anywhere (a
  block of periods done, or no room to record an event: ``NEED``) and the next one goes on;
* :class:`Records` (``rc``): per recorded period ``rc.per[b, r, IMPACTS | OPENINGS | LOSS]``, the recorded events
  ``rc.ev[b, i, TIME | KIND | LOSS]`` (``ti[b, EVENTS]`` of them), the modal states at the recorded boundaries
  ``rc.sx, rc.sv`` and their states ``rc.ss``, from the forcing period ``rc.first`` on;
* accounts: None (a replay of the switches: no accounting code is compiled) or ``acc[b, r, D_EQ | D_W |
  WORK_REC | STUCK_T | AMP | VISC_REC]``;
* inside the kernel, :class:`Current` (one trajectory's working copies of its rows) and :class:`Work` (the work
  space of one thread), both made by the entry point;
* the scalars the kernel's functions pass each other, in small records (numba passes them by value, as it would
  the scalars): :class:`Forcing` (the load's rotations over a segment), :class:`Segment` (that forcing, the
  segment's start and the load's phase), :class:`Half` (the forcing's half angle at a point), :class:`Mode` and
  :class:`ModeState` (one modal oscillator and its state); for the Taylor model of the margin
  :class:`Modes` and :class:`Damping` (a state's modes, as arrays), :class:`LoadTerm` (the load's term in the
  margin at a point) and :class:`Scaled` (one mode in the model's units).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..model import IMPACT, OPENS, REBOUND, STICK   # noqa: F401 (the event kinds, here by their kernel names)

__all__ = ["Current", "Damping", "Forcing", "Half", "LoadTerm", "Mode", "ModeState", "Model", "Modes", "Records",
           "Scaled", "Segment", "Trajectories", "Work", "accounts", "damping", "grow_events", "model", "records",
           "trajectories"]

W, F, C, G = 0, 1, 2, 3
RQ, SIZE, G0 = 0, 1, 2
OPEN_OFF, IMPACT_OFF = 0, 1
OPEN, IMPACT_POS, IMPACT_VEL, OPEN_VEL = 0, 1, 2, 3
ZETA, CV = 0, 1
T, OMEGA, PHI, TP, P = 0, 1, 2, 3, 4
PERIOD, STATE, ZEROS, STALL, STATUS, ROUNDS, NEED, EVENTS, SHORT = 0, 1, 2, 3, 4, 5, 6, 7, 8
IMPACTS, OPENINGS, LOSS = 0, 1, 2
TIME, KIND = 0, 1
WORK, LOSSES, VISC = 0, 1, 2
D_EQ, D_W, WORK_REC, STUCK_T, AMP, VISC_REC = 0, 1, 2, 3, 4, 5


class Model(NamedTuple):
    """The simulator's model as the kernel takes it (:func:`model`, from a :class:`plbar.motion.Padded`).

    Attributes
    ----------
    modal : ndarray, shape (4, 2, m)
        ``modal[W | F | C | G, state, j]``: frequencies, modal loads, margin weights, constant accelerations (a
        constant load on a rigid-body mode of state II, :attr:`plbar.model.Statics.accel`; 0 elsewhere).
    margin : ndarray, shape (3, 2)
        ``margin[RQ | SIZE | G0, state]``: the margin's load term, its own size and its constant (a gap's,
        :class:`plbar.model.Statics`; 0 without one).
    maps : ndarray, shape (4, m, m)
        ``maps[OPEN | IMPACT_POS | IMPACT_VEL | OPEN_VEL]``: the switch maps.
    offsets : ndarray, shape (2, m)
        ``offsets[OPEN_OFF | IMPACT_OFF]``: what an opening and an impact add to the mapped positions (a gap's
        static equilibria; 0 without one).
    vc_row : ndarray, shape (m,)
        The contact velocity's row in state II.
    S : float
        The impact mass (0 for a truncated system).
    truncated : bool
        A truncated system (its impact loses the modal kinetic energy difference).
    restitution : float
        The coefficient of restitution ``e``.
    """

    modal: np.ndarray
    margin: np.ndarray
    maps: np.ndarray
    offsets: np.ndarray
    vc_row: np.ndarray
    S: float
    truncated: bool
    restitution: float


class Trajectories(NamedTuple):
    """Resumable trajectory states (:func:`trajectories`): ``tf[b, T | ...]``, ``ti[b, PERIOD | ...]``, the modal
    state ``z[b, 0 | 1]`` at the start of the current segment, the totals ``tot[b, WORK | LOSSES | VISC]``."""

    tf: np.ndarray
    ti: np.ndarray
    z: np.ndarray
    tot: np.ndarray


class Records(NamedTuple):
    """What is recorded (:func:`records`): per period ``per[b, r, IMPACTS | OPENINGS | LOSS]``, the events
    ``ev[b, i, TIME | KIND | LOSS]``, the boundary states ``sx, sv`` (``(B, R + 1, m)``) and their states ``ss``,
    from the forcing period ``first`` on (``r = 0`` is that period)."""

    per: np.ndarray
    ev: np.ndarray
    sx: np.ndarray
    sv: np.ndarray
    ss: np.ndarray
    first: int


class Current(NamedTuple):
    """The trajectory being advanced: its row ``b``, the first recorded period ``first``, and working copies of its
    rows of :class:`Trajectories` (``f``, ``s``, ``z0``, ``tot``), written back when it stops."""

    b: int
    first: int
    f: np.ndarray
    s: np.ndarray
    z0: np.ndarray
    tot: np.ndarray


class Work(NamedTuple):
    """One thread's work space (allocated by the entry point: the kernel's functions allocate nothing).

    ``e, v``: the modal state at the current point; ``e2, v2``: the state after a switch; ``amp``: the fast modes'
    free amplitudes (:mod:`.split`); ``rows``: four rows for :func:`.pieces.amplitude`; ``d, scale``: the Taylor
    model's coefficients and their sizes; ``taylor``: its work space; ``P, fast``: the particular solutions and the
    first fast mode of each state (:func:`.split.particular`).
    """

    e: np.ndarray
    v: np.ndarray
    e2: np.ndarray
    v2: np.ndarray
    amp: np.ndarray
    rows: np.ndarray
    d: np.ndarray
    scale: np.ndarray
    taylor: np.ndarray
    P: np.ndarray
    fast: np.ndarray


class Forcing(NamedTuple):
    """The load ``f cos(W t - phi)`` over a segment that starts at ``ts``, as the closed-form flows take it: ``W``,
    ``c0, s0 = cos, sin(W ts)`` and ``cphi, sphi = cos, sin(phi)``.  The flows are linear in ``(cphi, sphi)``: zeros
    give the free flow, ``(-sin phi, cos phi)`` the derivative in ``phi``."""

    W: float
    c0: float
    s0: float
    cphi: float
    sphi: float


class Segment(NamedTuple):
    """A segment's :class:`Forcing` ``ld``, its start ``ts`` and the load's phase ``phi``: the load at ``u`` into it is
    ``cos(W (ts + u) - phi)``.  The flows take ``ld`` alone: they need neither ``ts`` nor ``phi``, and every scalar
    passed to the undamped flow weighs in LLVM's choice to inline it into the event loop (4 % slower where it
    does)."""

    ld: Forcing
    ts: float
    phi: float


class Half(NamedTuple):
    """The forcing's share of the undamped flow at ``u`` into a segment (:func:`.closed.half`):
    ``cW, sW = cos, sin(W u / 2)`` and ``sWu = sin(W u)``."""

    cW: float
    sW: float
    sWu: float


class Mode(NamedTuple):
    """One modal oscillator ``eta'' + 2 zeta w eta' + w^2 eta = f cos(W t - phi) + g``: ``w``, ``f``, ``zeta`` (0
    undamped) and ``g``, a constant acceleration (a constant load on a rigid-body mode, ``w = 0``; 0 elsewhere)."""

    w: float
    f: float
    zeta: float
    g: float


class ModeState(NamedTuple):
    """One mode's state: ``eta`` and ``v = eta'``."""

    eta: float
    v: float


class Modes(NamedTuple):
    """A state's modes as the Taylor model of its margin takes them (:func:`.certify.taylor`): the frequencies ``w``,
    the modal loads ``f``, the margin's weights ``c`` and the constant accelerations ``g`` (arrays of one length)."""

    w: np.ndarray
    f: np.ndarray
    c: np.ndarray
    g: np.ndarray


class Damping(NamedTuple):
    """The damping of :class:`Modes`: the ratios ``zeta`` and the margin's weights on the velocities ``cv``."""

    zeta: np.ndarray
    cv: np.ndarray


class LoadTerm(NamedTuple):
    """The load at a point ``t`` and its term in the margin, ``rq cos(W t - phi) + rs sin(W t - phi) + g0``:
    ``W``, ``ca, sa = cos, sin(W t - phi)``, ``rq``, ``rs`` and the margin's constant ``g0`` (a gap's)."""

    W: float
    ca: float
    sa: float
    rq: float
    rs: float
    g0: float


class Scaled(NamedTuple):
    """One mode in the units of a Taylor model (``Om``, :func:`.certify.taylor`): the margin's weights ``c`` and
    ``cv`` (times ``Om``), ``w / Om``, ``f / Om^2``, ``damp = 2 zeta w / Om``, ``eta``, ``v = eta' / Om``, the
    bounds ``b0, b1`` of ``|eta|`` and ``|eta'| / Om`` over the step and ``g / Om^2`` (a constant acceleration)."""

    c: float
    cv: float
    w: float
    f: float
    damp: float
    eta: float
    v: float
    b0: float
    b1: float
    g: float


def _f64(a):
    return np.ascontiguousarray(a, dtype=np.float64)


def model(pad) -> Model:
    """The kernel's view of a :class:`plbar.motion.Padded`."""
    maps = [pad.open_map, pad.impact_pos, pad.impact_vel, pad.open_map if pad.open_vel is None else pad.open_vel]
    return Model(_f64(np.stack([pad.w, pad.f, pad.c, pad.g])), _f64(np.stack([pad.rq, pad.size, pad.g0])),
                 _f64(np.stack(maps)), _f64(pad.offsets), _f64(pad.vc_row), float(0.0 if pad.truncated else pad.S),
                 bool(pad.truncated), float(pad.restitution))


def damping(pad):
    """``damping[state, ZETA | CV]``, or None for an undamped system."""
    return None if pad.zeta is None else _f64(np.stack([pad.zeta, pad.cv], axis=1))


SPLIT_MIN = 12   #: systems with fewer modes never split (their fastest mode is not much faster than the rest)


def large(pad):
    """Not None for a system of :data:`SPLIT_MIN` modes or more (the split model, :mod:`.split`)."""
    return np.ones(1) if pad.m >= SPLIT_MIN else None


def trajectories(T, phi, state, eta, vel) -> Trajectories:
    """Trajectories at the start of their first forcing period."""
    B = T.size
    tf = np.zeros((B, 5))
    tf[:, 0], tf[:, 1], tf[:, 2] = T, 2 * np.pi / T, phi
    ti = np.zeros((B, 9), np.int64)
    ti[:, 1] = state
    return Trajectories(tf, ti, _f64(np.stack([np.asarray(eta, float), np.asarray(vel, float)], axis=1)),
                        np.zeros((B, 3)))


def records(B: int, m: int, R: int, capacity: int, first: int) -> Records:
    """Empty records for ``B`` trajectories, ``R`` periods recorded from period ``first`` on, room for ``capacity``
    events each."""
    return Records(np.zeros((B, R, 3)), np.zeros((B, capacity, 3)), np.zeros((B, R + 1, m)),
                   np.zeros((B, R + 1, m)), np.zeros((B, R + 1), np.int64), int(first))


def accounts(B: int, R: int, on: bool):
    """Empty per-period accounts, or None (no accounts)."""
    return np.zeros((B, R, 6)) if on else None


def grow_events(rc: Records) -> Records:
    """The same records with twice the room for events."""
    ev = rc.ev
    out = np.zeros((ev.shape[0], 2 * ev.shape[1], 3))
    out[:, :ev.shape[1]] = ev
    return rc._replace(ev=out)
