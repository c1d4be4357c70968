"""The modes of one contact state: natural frequencies and mass-normalised mode shapes, and which are kept.

:func:`state_modes` solves ``K v = w^2 M v`` (``V^T M V = I``, each mode's largest component positive) and refuses a
stiffness that is not definite (a state with rigid-body motion); :func:`kept_modes` reads a modal truncation.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..errors import InputError

__all__ = ["SINGULAR_RTOL", "kept_modes", "state_modes"]

#: a stiffness whose smallest eigenvalue is below this times the largest is singular (rigid-body motion)
SINGULAR_RTOL = 1e-13


def state_modes(K: np.ndarray, M: np.ndarray, what: str, m: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Natural circular frequencies and mass-normalised modes, sign-fixed (the lowest ``m``, or all).

    A state with no DOF (a single mass held at the stop) has no mode: empty arrays."""
    if K.shape[0] == 0:
        return np.zeros(0), np.zeros((0, 0))
    if m is None or m >= K.shape[0]:
        lam, V = sla.eigh(K, M)
    else:
        lam, V = sla.eigh(K, M, subset_by_index=[0, m - 1])
    # a singular K gives lam[0] ~ +-eps lam_max; max(K_ii / M_ii) <= lam_max (Rayleigh quotients of unit vectors)
    top = float(np.max(np.diag(K) / np.diag(M)))
    if lam[0] <= SINGULAR_RTOL * top:
        raise InputError(f"the {what} stiffness matrix is not positive definite (smallest eigenvalue {lam[0]:.3g} "
                         f"of K v = lam M v, against {top:.3g} or more: is the bar held against rigid-body motion?)")
    k = np.argmax(np.abs(V), axis=0)
    V = V * np.sign(V[k, np.arange(V.shape[1])])
    return np.sqrt(lam), V


def kept_modes(modes, n: int) -> tuple[int | None, int | None]:
    """``modes`` (None, an int for both states or a pair ``(m1, m2)``) as kept mode counts."""
    if modes is None:
        return None, None
    try:
        m1, m2 = (modes, modes) if np.ndim(modes) == 0 else tuple(modes)
        m1, m2 = int(m1), int(m2)
    except (TypeError, ValueError):
        raise InputError(f"modes = {modes!r} must be a positive integer or a pair (state I, state II)") from None
    if m1 < 1 or m2 < 1:
        raise InputError(f"modes = {modes!r} must be positive")
    return (None if m1 >= n - 1 else m1), (None if m2 >= n else m2)
