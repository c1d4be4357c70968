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
from ..model.statics import rest_state

__all__ = ["CHATTER", "FREE", "IMPACT", "OK", "OPENS", "REBOUND", "STALLED", "STICK", "STUCK", "Padded", "padded",
           "energy_consistent"]

STUCK = 0   #: row of state I (contact held) in the padded arrays
FREE = 1    #: row of state II (gap open)
OK, CHATTER, STALLED = 0, 1, 2   #: trajectory status: running or done, stopped by a chattering contact, stalled
#: the simulator's event kinds (``Run.events["kind"]``): the gap opens; a plastic impact; a rebound; rebounds that
#: accumulate (chattering) and end stuck, recorded at their accumulation time.  Here, not in the kernel, so that
#: a reader of the events needs no numba.
OPENS, IMPACT, REBOUND, STICK = 1, 2, 3, 4


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
    open_map, open_vel : ndarray, shape (m, m)
        I -> II switch of positions and of velocities (``x^II = E x^I``): the system's ``P12``, each made
        energy-consistent (:func:`energy_consistent`), rounded to double.
    impact_pos, impact_vel : ndarray, shape (m, m)
        II -> I switch: positions kept (``P21``), momenta of the DOFs other than the contact kept (``Q21``,
        Eq. (10)); both energy-consistent (:func:`energy_consistent`).
    vc_row : ndarray, shape (m,)
        ``v_c = vc_row . etadot^II`` (contact velocity in state II).
    S : float
        Impact mass ``M_cc - M_cr M_rr^-1 M_rc`` (as ``1 / (M^-1)_cc`` from the modes, the same to round-off): the
        impact loses ``S v_c^2 / 2`` (Eq. (14));
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
    restitution : float
        The contact's coefficient of restitution (:class:`plbar.model.Problem`; the kernel's rebounds).
    size : ndarray, shape (2,)
        The margin's own size in each state, ``sum_j |c_j f_j| / w_j^2 + |rq| + |g0|`` (the static response to
        the load's amplitude, and the gap's constant): the floor of its round-off level (a bar at rest has no
        size of its own).
    g0 : ndarray, shape (2,)
        The margin's constant in each state (:attr:`plbar.model.Statics.margin`: ``-R_I`` in state I, the gap
        ``d`` in state II); zeros at ``d = 0``.
    offsets : ndarray, shape (2, m)
        What a switch adds to the mapped positions: row 0 at an opening (``open_offset``), row 1 at an impact
        (``impact_offset``, :class:`plbar.model.Statics`); zeros at ``d = 0``.
    xs : ndarray, shape (2, n)
        Each state's static equilibrium: the physical positions are ``V[s] eta + xs[s]``.
    es : ndarray, shape (2,)
        Each state's static energy: the mechanical energy is the modal one plus ``es[s]`` (less ``g . eta``).
    g : ndarray, shape (2, m)
        Constant modal accelerations: a constant load's on the rigid-body modes of state II
        (:attr:`plbar.model.Statics.accel`); zeros elsewhere (every definite free state).
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
    open_vel: np.ndarray | None = None
    restitution: float = 0.0
    g0: np.ndarray | None = None
    offsets: np.ndarray | None = None
    xs: np.ndarray | None = None
    es: np.ndarray | None = None
    g: np.ndarray | None = None

    def __post_init__(self):
        m, n = self.m, self.n
        for name, shape in (("g0", (2,)), ("offsets", (2, m)), ("xs", (2, n)), ("es", (2,)), ("g", (2, m))):
            if getattr(self, name) is None:
                object.__setattr__(self, name, np.zeros(shape))   # no gap: every constant 0

    @property
    def rest_state(self) -> int:
        """The state of the static equilibrium (:func:`plbar.model.statics.rest_state`)."""
        return rest_state(self.g0, bool(np.any(self.g)))

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


L = np.longdouble   #: extended precision, in which the switch maps are made energy-consistent


def _congruent(A, G, H):
    """``A C`` with ``C^T (A^T G A) C = H`` to extended precision, ``C = I + O(error)`` (all in ``longdouble``).

    ``A^T G A = H + Delta`` with ``Delta`` of the order of the round-off of the modes: ``C = I - H^-1 Delta / 2``
    leaves an error of order ``Delta^2``, far below the rounding of ``longdouble``.  ``H^-1 Delta`` is solved in
    double (it is of the order of ``Delta``: its rounding is of the order of ``Delta eps``)."""
    A, G, H = (np.asarray(a).astype(L) for a in (A, G, H))
    D = A.T @ G @ A - H
    X = np.linalg.solve(np.asarray(H, float), np.asarray(D, float))
    return A @ (np.eye(A.shape[1], dtype=L) - L(0.5) * X.astype(L))


def _orthonormal(u):
    """An orthonormal basis ``N`` (columns) of the complement of the unit vector ``u``, in ``longdouble``: two
    passes of Gram-Schmidt against ``u`` and each other, from double's SVD."""
    Y = np.linalg.svd(np.asarray(u, float)[None, :])[2][1:].T.astype(L)
    for _ in range(2):
        for k in range(Y.shape[1]):
            y = Y[:, k] - u * (u @ Y[:, k])
            for j in range(k):
                y = y - Y[:, j] * (Y[:, j] @ y)
            Y[:, k] = y / np.sqrt(y @ y)
    return Y


def energy_consistent(s) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
    """The switch maps of the system ``s`` corrected so that the switches keep the modal energies to extended
    precision: ``(open_pos, open_vel, impact_pos, impact_vel, S)``, the maps in ``numpy.longdouble``.

    The maps ``P12``, ``P21``, ``Q21`` come from the modes, which hold their identities (orthonormality,
    ``V^T K V = w^2``) to a few units of round-off; an opening then changes the potential energy by
    ``eta^T (P12^T W2 P12 - W1) eta / 2`` (``W = diag(w^2)``), about 1e-15 of the energy, an impact its kinetic
    energy by a few 1e-15 more than ``S v_c^2 / 2``, and a settled motion repeats those errors every period:
    over 1,000 periods the energy budget drifted by 1e-12 of the work where the load does little work (issue 28).
    The maps are made to hold their identities in extended precision and then rounded to double (the kernel's
    maps): rounded, they hold them to the rounding of their entries, 1e-16 - 6e-16, which measured over 1,000
    periods moves the budget by less than 1e-13 of the work (the rest of that drift was the impacts' reset of
    ``x_c``, :func:`plbar.motion.kernel.locate.land`).  Each map is corrected by a congruence
    ``C = I + O(1e-15)`` (:func:`_congruent`), with ``u = r / |r|`` the contact's direction in state II
    (``x_c = r . eta``) and ``N`` an orthonormal basis of its complement (:func:`_orthonormal`):

    * ``open_pos^T W2 open_pos = W1`` and ``open_vel^T open_vel = I`` (an opening keeps both energies);
    * ``(impact_pos N)^T W1 (impact_pos N) = N^T W2 N`` (the impact keeps the potential energy of its positions,
      ``x_c = 0``), unchanged across ``N``;
    * ``(impact_vel N)^T (impact_vel N) = I``, ``impact_vel u = 0`` and ``S = 1 / |r|^2`` (the impact mass, the
      same number to round-off: ``|r|^2 = (M^-1)_cc``): the kinetic energy after an impact is the one before less
      ``S v_c^2 / 2`` (Eq. (14)).
    """
    W1, W2 = np.diag(s.w1 ** 2), np.diag(s.w2 ** 2)
    m1, m2 = s.w1.size, s.w2.size
    open_pos = _congruent(s.P12, W2, W1)
    open_vel = _congruent(s.P12, np.eye(m2), np.eye(m1))
    r = np.asarray(s.gap_row, float).astype(L)
    rr = r @ r
    S = float(s.impact_mass)
    if m1 != m2 - 1 or not rr > 0 or abs(S * float(rr) - 1.0) > 1e-10:
        return open_pos, open_vel, np.asarray(s.P21, float).astype(L), np.asarray(s.Q21, float).astype(L), S
    u = r / np.sqrt(rr)
    N = _orthonormal(u)                                         # x_c = 0
    P21, Q21 = np.asarray(s.P21, float).astype(L), np.asarray(s.Q21, float).astype(L)
    A = P21 @ N
    impact_pos = P21 + (_congruent(A, W1, N.T @ W2.astype(L) @ N) - A) @ N.T
    B = Q21 @ N
    impact_vel = Q21 + (_congruent(B, np.eye(m1), np.eye(m1)) - B) @ N.T - np.outer(Q21 @ u, u)
    return open_pos, open_vel, impact_pos, impact_vel, float(L(1) / rr)


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
    if s.truncated:
        S, maps = float("nan"), (s.P12, s.P12, s.P21, s.Q21)
    else:
        *maps, S = energy_consistent(s)
    open_pos, open_vel, impact_pos, impact_vel = (np.asarray(a, float) for a in maps)
    st = prob.statics
    g0 = np.asarray(st.margin, float)
    g = np.zeros((2, m))
    if st.accel is not None:
        g[1, :m2] = st.accel
    # a rigid-body mode (w = 0) has no static response: its share of the size is its forced one at w = 1
    size = np.sum(np.abs(c * (np.abs(f) + np.abs(g))) / np.where(w > 0, w * w, 1.0), axis=1) + np.abs(rq) + np.abs(g0)
    offsets = np.vstack([_pad(st.open_offset, (m,)), _pad(st.impact_offset, (m,))])
    damped = bool(getattr(s, "damped", False))
    zeta = np.vstack([_pad(s.zeta1, (m,)), _pad(s.zeta2, (m,))]) if damped else None
    cv = np.vstack([_pad(-np.asarray(s.r_v, float), (m,)), np.zeros(m)]) if damped else None
    return Padded(w, f, c, rq, _pad(open_pos, (m, m)), _pad(impact_pos, (m, m)), _pad(impact_vel, (m, m)),
                  _pad(s.gap_row, (m,)), S, V, bool(s.truncated), size, zeta, cv, _pad(open_vel, (m, m)),
                  float(getattr(prob, "restitution", 0.0)), g0, offsets, np.vstack([st.x1, st.x2]),
                  np.asarray(st.energy, float), g)
