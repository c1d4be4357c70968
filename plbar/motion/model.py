"""The two-state system laid out for a batch of trajectories in either state (padded modal arrays).

Trajectories of one survey share the model and differ in their forcing
period and in the state they are in.  Every per-state array is padded to the
same number of modal coordinates ``m = max(m1, m2)`` (state I has one DOF
fewer), with padded modes that have unit frequency, no load, no margin
weight and stay at zero, so that a batch indexes them by its state vector.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Problem

__all__ = ["CHATTER", "FREE", "OK", "STALLED", "STUCK", "Padded", "padded"]

STUCK = 0   #: row of state I (contact held) in the padded arrays
FREE = 1    #: row of state II (gap open)
OK, CHATTER, STALLED = 0, 1, 2   #: trajectory status: running or done, stopped by a chattering contact, stalled


@dataclass(frozen=True)
class Padded:
    """Per-state modal data, padded to ``m`` coordinates (rows ``STUCK``, ``FREE``).

    Attributes
    ----------
    w, f : ndarray, shape (2, m)
        Circular frequencies and modal load amplitudes (Eq. (3)).
    c : ndarray, shape (2, m)
        Margin weights: the admissibility margin of the state is
        ``g = c . eta + rq cos(W t - phi)``: ``-R`` in state I (Eq. (4)),
        ``-x_c`` in state II (Eq. (5)); ``g >= 0`` while the state holds.
    rq : ndarray, shape (2,)
        Load term of the margin (``-r_q`` in state I, 0 in state II).
    open_map : ndarray, shape (m, m)
        I -> II switch of positions and velocities (``x^II = E x^I``).
    impact_pos, impact_vel : ndarray, shape (m, m)
        II -> I switch: positions kept, momenta of the DOFs other than the contact kept (Eq. (10)).
    vc_row : ndarray, shape (m,)
        ``v_c = vc_row . etadot^II`` (contact velocity in state II).
    S : float
        Impact mass ``M_cc - M_cr M_rr^-1 M_rc``: the impact loses ``S v_c^2 / 2`` (Eq. (14));
        ``nan`` for a truncated system, whose loss is the modal kinetic energy difference.
    V : ndarray, shape (2, n, m)
        Modes as physical maps ``x = V[s] eta`` (contact DOF last; 0 in state I).
    truncated : bool
        True for a modally truncated system (the loss is then the modal one, see
        :class:`plbar.errors.TruncationWarning`).
    zeta, cv : ndarray, shape (2, m), or None
        Inherent (Rayleigh) damping: the modal ratios of each state, and the margin's weights on the
        modal velocities (``-r_v`` in state I: the damper's share of the reaction; 0 in state II);
        None without damping (the undamped code path, bit for bit).
    size : ndarray, shape (2,)
        The margin's own size in each state, ``sum_j |c_j f_j| / w_j^2 + |rq|`` (the static response to
        the load's amplitude): the floor of its round-off level (a bar at rest has no size of its own).
    """

    w: np.ndarray
    f: np.ndarray
    c: np.ndarray
    rq: np.ndarray
    open_map: np.ndarray
    impact_pos: np.ndarray
    impact_vel: np.ndarray
    vc_row: np.ndarray
    S: float
    V: np.ndarray
    truncated: bool
    size: np.ndarray
    zeta: np.ndarray | None = None
    cv: np.ndarray | None = None

    @property
    def m(self) -> int:
        """Padded number of modal coordinates."""
        return self.w.shape[1]

    @property
    def n(self) -> int:
        """Number of free DOFs (contact last)."""
        return self.V.shape[1]


def _pad(a: np.ndarray, shape, fill: float = 0.0) -> np.ndarray:
    out = np.full(shape, fill)
    out[tuple(slice(0, k) for k in a.shape)] = a
    return out


def padded(prob: Problem) -> Padded:
    """The padded per-state data of ``prob`` (modes, margins, switch maps)."""
    s = prob.system
    m1, m2, n = s.w1.size, s.w2.size, s.n
    m = max(m1, m2)
    w = np.vstack([_pad(s.w1, (m,), 1.0), _pad(s.w2, (m,), 1.0)])
    f = np.vstack([_pad(prob.f1, (m,)), _pad(prob.f2, (m,))])
    c = np.vstack([_pad(-s.r_eta, (m,)), _pad(-s.gap_row, (m,))])
    rq = np.array([-prob.r_q, 0.0])
    V = np.zeros((2, n, m))
    V[0, :-1, :m1] = s.V1
    V[1, :, :m2] = s.V2
    S = float("nan") if s.truncated else s.impact_mass
    size = np.sum(np.abs(c * f) / (w * w), axis=1) + np.abs(rq)
    damped = bool(getattr(s, "damped", False))
    zeta = np.vstack([_pad(s.zeta1, (m,)), _pad(s.zeta2, (m,))]) if damped else None
    cv = np.vstack([_pad(-np.asarray(s.r_v, float), (m,)), np.zeros(m)]) if damped else None
    return Padded(w, f, c, rq, _pad(s.P12, (m, m)), _pad(s.P21, (m, m)), _pad(s.Q21, (m, m)), _pad(s.gap_row, (m,)),
                  S, V, bool(s.truncated), size, zeta, cv)
