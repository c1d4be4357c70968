"""The two-state modal system (paper Sec. 2.2, FORMULATION §§2-3).

State I (stuck): the contact DOF ``c`` is held, ``M^I = M_rr``, ``K^I = K_rr``.
State II (free): all DOFs, ``M^II = M``, ``K^II = K``.  Modes are mass
normalised (``V^T M V = I``, Eq. (2)); the switch matrices project between the
modal spaces (Eqs. (8)-(10)), with the plastic impact conserving the
generalised momenta of the DOFs other than ``c``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from .bar import Assembled, Bar, assemble
from .errors import InputError
from .load import Load

__all__ = ["TwoStateSystem", "Problem", "two_state", "problem"]


def _modes(K: np.ndarray, M: np.ndarray, what: str) -> tuple[np.ndarray, np.ndarray]:
    """Natural circular frequencies and mass-normalised modes, sign-fixed."""
    lam, V = sla.eigh(K, M)
    if lam[0] <= 0:
        raise InputError(f"the {what} stiffness matrix is not positive definite (smallest eigenvalue {lam[0]:.3g})")
    k = np.argmax(np.abs(V), axis=0)
    V = V * np.sign(V[k, np.arange(V.shape[1])])
    return np.sqrt(lam), V


@dataclass(frozen=True)
class TwoStateSystem:
    """Modal data of both states and the switch maps.

    Attributes
    ----------
    M, K : ndarray, shape (n, n)
        Free-DOF matrices (contact DOF last).
    x : ndarray, shape (n,)
        DOF positions.
    w1, V1 : ndarray, shapes (n-1,), (n-1, n-1)
        State I circular frequencies and modes.
    w2, V2 : ndarray, shapes (n,), (n, n)
        State II circular frequencies and modes.
    P12 : ndarray, shape (n, n-1)
        I -> II modal switch (gap opens), positions and velocities alike.
    P21, Q21 : ndarray, shape (n-1, n)
        II -> I modal switch of positions and velocities (plastic impact).
    r_eta : ndarray, shape (n-1,)
        Contact reaction in state I per modal coordinate (without the load
        term), ``R = r_eta . eta + r_q cos(w t - phi)``.
    MV1_c : ndarray, shape (n-1,)
        ``M_cr V1``, used for the load term of the reaction.
    gap_row : ndarray, shape (n,)
        ``x_c = gap_row . eta^II`` (row ``c`` of ``V2``).
    """

    M: np.ndarray
    K: np.ndarray
    x: np.ndarray
    w1: np.ndarray
    V1: np.ndarray
    w2: np.ndarray
    V2: np.ndarray
    P12: np.ndarray
    P21: np.ndarray
    Q21: np.ndarray
    r_eta: np.ndarray
    MV1_c: np.ndarray
    gap_row: np.ndarray
    lumped: bool

    @property
    def n(self) -> int:
        return self.x.size

    @property
    def T0(self) -> tuple[float, float]:
        """Fundamental periods ``(T0^I, T0^II)``."""
        return 2 * np.pi / self.w1[0], 2 * np.pi / self.w2[0]

    def embed(self, xr: np.ndarray) -> np.ndarray:
        """State I physical vector(s) ``(..., n-1)`` to full DOFs ``(..., n)`` with ``x_c = 0``."""
        out = np.zeros(xr.shape[:-1] + (self.n,))
        out[..., :-1] = xr
        return out


def two_state(M: np.ndarray, K: np.ndarray, x: np.ndarray) -> TwoStateSystem:
    """Build the two-state modal system from free-DOF matrices (contact last).

    Parameters
    ----------
    M, K : ndarray, shape (n, n)
        Mass and stiffness over the free DOFs, the contact DOF last.
    x : ndarray, shape (n,)
        DOF positions (for output only).
    """
    M = np.asarray(M, float)
    K = np.asarray(K, float)
    n = M.shape[0]
    if n < 2:
        raise InputError(f"the system needs at least 2 free DOFs, got {n}")
    Mrr, Krr = M[:-1, :-1], K[:-1, :-1]
    w1, V1 = _modes(Krr, Mrr, "state I")
    w2, V2 = _modes(K, M, "state II")
    # I -> II: x^II = E x^I, eta^II = V2^T M E V1 eta^I (Eq. (8) with I, II exchanged)
    P12 = V2.T @ M[:, :-1] @ V1
    # II -> I positions: x_r = R x^II, eta^I = V1^T M_rr R V2 eta^II (Eq. (9))
    P21 = V1.T @ Mrr @ V2[:-1, :]
    # II -> I velocities: M_rr v_r^+ = (M v^-)_r  =>  etadot^I = V1^T (M V2)_r etadot^II
    Q21 = V1.T @ (M @ V2)[:-1, :]
    MV1_c = M[-1, :-1] @ V1
    r_eta = K[-1, :-1] @ V1 - MV1_c * w1**2
    lumped = bool(np.all(M[-1, :-1] == 0) and np.allclose(M[:-1, :-1], np.diag(np.diag(M[:-1, :-1]))))
    return TwoStateSystem(M, K, np.asarray(x, float), w1, V1, w2, V2, P12, P21, Q21, r_eta, MV1_c,
                          V2[-1, :].copy(), lumped)


@dataclass(frozen=True)
class Problem:
    """A two-state system with its load: everything the periodic solver needs.

    Attributes
    ----------
    system : TwoStateSystem
    q : ndarray, shape (n,)
        Load amplitude vector ``q0`` (Eq. (1)); ``q[:-1]`` acts in state I.
    f1, f2 : ndarray
        Modal forces of states I and II (Eq. (3)).
    r_q : float
        Load term of the state I reaction, ``M_cr V1 f1 - q_c``.
    bar, load, asm : optional
        Where the problem came from.
    """

    system: TwoStateSystem
    q: np.ndarray
    f1: np.ndarray
    f2: np.ndarray
    r_q: float
    bar: Bar | None = None
    load: Load | None = None
    asm: Assembled | None = None

    def with_load(self, load: Load) -> "Problem":
        """Same bar, another load (reuses the modes)."""
        return _with_q(self.system, load.vector(self.bar, self.asm), self.bar, load, self.asm)


def _with_q(sys: TwoStateSystem, q: np.ndarray, bar=None, load=None, asm=None) -> Problem:
    q = np.asarray(q, float)
    f1 = sys.V1.T @ q[:-1]
    f2 = sys.V2.T @ q
    r_q = float(sys.MV1_c @ f1 - q[-1])
    return Problem(sys, q, f1, f2, r_q, bar, load, asm)


def problem(bar: Bar, load: Load | None = None, q: np.ndarray | None = None) -> Problem:
    """Assemble ``bar``, build both states and attach the load.

    Parameters
    ----------
    bar : Bar
    load : Load, optional
        The harmonic load; or give the amplitude vector ``q`` directly.
    """
    a = assemble(bar)
    sys = two_state(a.M, a.K, a.x)
    if load is not None:
        qv = load.vector(bar, a)
    elif q is not None:
        qv = np.asarray(q, float)
        if qv.shape != (a.n,) or not np.all(np.isfinite(qv)) or not np.any(qv):
            raise InputError(f"load vector q must be finite, non-zero and of length {a.n}")
    else:
        raise InputError("give a load (plbar.point / plbar.node) or a load vector q")
    return _with_q(sys, qv, bar, load, a)
