"""The static part of each state's motion: a gap or an interference at the stop, a constant load (FORMULATION §9,
affine terms).

With the stop at ``u = d`` (``gap``; the contact coordinate is last, ``u <= d``) and a constant load ``q_s``
(gravity, a prestress) each state moves about its own static equilibrium, and the motion about it is the paper's
flow (Eqs. (1)-(3)) unchanged:

* state II (free): ``K x_II = q_s``, the opening ``o = d - u``;
* state I (held): ``u = d`` and ``K_rr x_r + K_rc d = q_s,r``, so ``x_I = (K_rr^-1 (q_s,r - K_rc d), d)``, with
  the reaction ``R_I = (K x_I - q_s)_c``; without a constant load ``R_I = d (K_cc - K_cr K_rr^-1 K_rc)`` (the
  Schur complement of ``K_rr``: the stiffness the stop sees).

A state's modal coordinates are those of ``x - x_state``.  Everything that is linear in them stays as it is: the
flows, their derivatives (hence Newton's Jacobians and the Floquet multipliers), the velocities, the impact loss
(Eq. (14)), ``Psi`` (Eq. (20)) and ``xi_eq`` (Eq. (22)).  What changes is affine and constant:

* the margins gain constants: ``-R`` in state I gains ``-R_I``, ``-u`` in state II gains ``d``;
* a switch maps the positions as before and adds a constant (:attr:`Statics.open_offset`,
  :attr:`Statics.impact_offset`): ``eta_to = P eta_from + L_to (x_from - x_to)`` with ``L_to`` the projection
  the map ``P`` is made of (``V2^T M`` on opening, ``V1^T M_rr`` on the held DOFs at an impact);
* the modal energy ``sum (eta'^2 + w^2 eta^2) / 2`` is the mechanical energy ``v^T M v / 2 + x^T K x / 2 - q_s^T x``
  (the constant load's potential included) less the state's static energy ``x_s^T K x_s / 2 - q_s^T x_s``: with
  ``x = x_s + y``, the cross term ``y^T (K x_s - q_s)`` is 0 in state II and ``R_I y_c = 0`` in state I.

A free state with rigid-body modes (a free body, a cracked bar's floating part) has no equilibrium under a constant
load that pushes its rigid motion: its elastic part has one (``x2``, with no rigid-body part), and each rigid mode
accelerates uniformly, ``eta_r'' = g_r = v_r^T q_s`` (:attr:`Statics.accel`: the flows gain ``g u^2 / 2``, the
velocities ``g u``); the mechanical energy is then the modal one plus ``x2``'s static energy less ``g . eta``
(the cross term ``y^T (K x2 - q_s) = -g . eta``).

At ``d = 0`` without a constant load every constant is 0: the paper's system, bit for bit (a constant 0 added
changes no double).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from ..util.check import finite

__all__ = ["Statics", "check_gap", "rest_state", "statics"]


def check_gap(d) -> float:
    """A validated gap: a finite number (``> 0`` a clearance, ``< 0`` an interference, 0 the paper)."""
    return finite("gap", d, "a finite number (> 0 a clearance at the stop, < 0 an interference, 0 the paper)")


@dataclass(frozen=True)
class Statics:
    """The static equilibria of the two states and the constants they add (module docstring).

    Attributes
    ----------
    gap : float
        ``d``: the stop holds ``u <= d``.
    q_s : ndarray, shape (n,) or None
        The constant load in contact coordinates (None: none).
    x1, x2 : ndarray, shape (n,)
        The static equilibria of state I (``x1[-1] = d``) and state II (``K x2 = q_s``), in contact coordinates.
    reaction : float
        ``R_I``, the reaction of state I at its equilibrium (``< 0``: the stop pushes, as it must to hold it).
    energy : ndarray, shape (2,)
        ``x_s^T K x_s / 2 - q_s^T x_s`` of the two equilibria (state I, state II): the mechanical energy (the
        constant load's potential included) less the modal one.
    margin : ndarray, shape (2,)
        The margins' constants ``(-R_I, d)`` (``-R`` in state I, the opening ``d - u`` in state II).
    open_offset : ndarray, shape (m2,)
        Added to ``P12 eta^I`` at an opening: ``V2^T M (x1 - x2)``.
    impact_offset : ndarray, shape (m1,)
        Added to ``P21 eta^II`` at an impact: ``V1^T M_rr (x2 - x1)_r``.
    accel : ndarray, shape (m2,) or None
        The constant modal accelerations ``g_r = v_r^T q_s`` of state II's rigid-body modes (0 on its elastic
        modes); None where the constant load pushes no rigid motion (every definite free state).
    """

    gap: float
    q_s: np.ndarray | None
    x1: np.ndarray
    x2: np.ndarray
    reaction: float
    energy: np.ndarray
    margin: np.ndarray
    open_offset: np.ndarray
    impact_offset: np.ndarray
    accel: np.ndarray | None = None

    @property
    def zero(self) -> bool:
        """True at ``d = 0`` without a constant load: the paper's system, every constant 0."""
        return self.gap == 0.0 and self.q_s is None

    @property
    def rest_state(self) -> int:
        """The state of the static equilibrium (:func:`rest_state`)."""
        return rest_state(self.margin, self.accel is not None)


def rest_state(margin, pushed: bool = False) -> int:
    """The state of the static equilibrium from the margins' constants ``(-R_I, d - u_II)``: 1 (state II, free)
    where the opening at rest is positive (a clearance), else 0 (state I, held: no gap, at the stop with no
    reaction; an interference).  ``pushed``: a constant load moves a rigid-body motion of state II, which then has
    no equilibrium: the body rests on the stop (0) where the stop holds it (``-R_I >= 0``), else it has no rest
    at all and starts free (1)."""
    if pushed:
        return 0 if margin[0] >= 0.0 else 1
    return 1 if margin[1] > 0.0 else 0


def _free_equilibrium(system, q_s: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """``x2`` with ``K x2 = q_s`` (a solve where ``K`` is definite) and the rigid modes' accelerations (None: none).

    Where the free state has rigid-body modes (a free body) the elastic part's equilibrium: least squares, less its
    rigid-body part (any equilibrium would do); the load's share on the rigid modes, ``g_r = v_r^T q_s``, moves
    them with a constant acceleration (:attr:`Statics.accel`; zeros elsewhere, None where every ``g_r`` is
    round-off)."""
    if not system.rigid:
        return sla.solve(system.K, q_s, assume_a="pos"), None
    rigid = system.w2 == 0.0
    Z = system.V2[:, rigid]                        # the rigid-body modes (the lowest: kept by a truncation)
    g = Z.T @ q_s
    pushed = np.any(np.abs(g) > 1e-12 * np.sum(np.abs(q_s)) * np.max(np.abs(Z)))
    q_e = q_s - system.M @ (Z @ g) if pushed else q_s          # what the elastic part holds
    x = np.linalg.lstsq(system.K, q_e, rcond=None)[0]
    x = x - Z @ (Z.T @ (system.M @ x))
    if not pushed:
        return x, None
    accel = np.zeros(system.w2.size)
    accel[rigid] = g
    return x, accel


def statics(system, gap: float = 0.0, q_s=None) -> Statics:
    """The :class:`Statics` of a :class:`plbar.model.TwoStateSystem` with its stop at ``u = gap`` and the constant
    load ``q_s`` (in the system's coordinates; None or zeros: none)."""
    d = check_gap(gap)
    M, K, V1, V2 = system.M, system.K, system.V1, system.V2
    n = M.shape[0]
    q_s = None if q_s is None or not np.any(q_s) else np.asarray(q_s, float)
    x1, x2 = np.zeros(n), np.zeros(n)
    accel = None
    if q_s is not None:
        x2, accel = _free_equilibrium(system, q_s)
    if d != 0.0 or q_s is not None:
        rhs = -K[:-1, -1] * d + (q_s[:-1] if q_s is not None else 0.0)
        x1[:-1] = sla.solve(K[:-1, :-1], rhs, assume_a="pos") if n > 1 else 0.0
        x1[-1] = d
    qs = np.zeros(n) if q_s is None else q_s
    reaction = float(K[-1] @ x1 - qs[-1])
    energy = np.array([0.5 * float(x1 @ K @ x1) - float(qs @ x1), 0.5 * float(x2 @ K @ x2) - float(qs @ x2)])
    dx = x1 - x2
    return Statics(d, q_s, x1, x2, reaction, energy, np.array([-reaction, d - x2[-1]]), V2.T @ (M @ dx),
                   V1.T @ (M[:-1, :-1] @ -dx[:-1]), accel)
