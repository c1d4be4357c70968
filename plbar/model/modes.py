"""The modes of one contact state: natural frequencies and mass-normalised mode shapes, and which are kept.

:func:`state_modes` solves ``K v = w^2 M v`` (``V^T M V = I``, each mode's largest component positive).  A stiffness
that is not definite is refused, unless the state may move as a rigid body (``rigid=True``: the free state of a
free body, the floating part of a cracked bar), whose rigid-body modes then have ``w = 0`` exactly and span the
null space of ``K`` (FORMULATION §9, free bodies): their flow is ``eta0 + v0 t`` plus the forced part, the limit
``w -> 0`` of every closed form.  :func:`kept_modes` reads a modal truncation.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..errors import InputError

__all__ = ["SINGULAR_RTOL", "floats", "kept_modes", "state_modes"]

#: a stiffness whose smallest eigenvalue is below this times the largest is singular (rigid-body motion)
SINGULAR_RTOL = 1e-13


def state_modes(K: np.ndarray, M: np.ndarray, what: str, m: int | None = None,
                rigid: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Natural circular frequencies and mass-normalised modes, sign-fixed (the lowest ``m``, or all).

    A state with no DOF (a single mass held at the stop) has no mode: empty arrays.  ``rigid``: a semi-definite
    ``K`` is allowed, its rigid-body modes (eigenvalues within round-off of 0) get ``w = 0`` exactly and are
    re-orthonormalised in ``M`` over that null space; a stiffness with a negative eigenvalue is still refused."""
    if K.shape[0] == 0:
        return np.zeros(0), np.zeros((0, 0))
    if m is None or m >= K.shape[0]:
        lam, V = sla.eigh(K, M)
    else:
        lam, V = sla.eigh(K, M, subset_by_index=[0, m - 1])
    # a singular K gives lam[0] ~ +-eps lam_max; max(K_ii / M_ii) <= lam_max (Rayleigh quotients of unit vectors)
    top = float(np.max(np.diag(K) / np.diag(M)))
    if rigid and lam[0] <= SINGULAR_RTOL * top:
        return _with_rigid(K, M, lam, V, top, what)
    if lam[0] <= SINGULAR_RTOL * top:
        raise InputError(f"the {what} stiffness matrix is not positive definite (smallest eigenvalue {lam[0]:.3g} "
                         f"of K v = lam M v, against {top:.3g} or more: is the bar held against rigid-body motion?)")
    return np.sqrt(lam), _signed(V)


def _signed(V: np.ndarray) -> np.ndarray:
    """Each column with its largest component positive."""
    k = np.argmax(np.abs(V), axis=0)
    return V * np.sign(V[k, np.arange(V.shape[1])])


def _with_rigid(K, M, lam, V, top, what):
    """:func:`state_modes` of a semi-definite ``K``: ``w = 0`` on the null space (:data:`SINGULAR_RTOL`).

    The null space is recomputed from ``K`` itself (an SVD, which separates it to round-off of ``|K|``) and made
    ``M``-orthonormal, so the rigid modes hold ``K v = 0`` to round-off of the stiffness, not of ``eigh``'s
    eigenvalue gap."""
    if lam[0] < -1e-8 * top:
        raise InputError(f"the {what} stiffness matrix is indefinite (eigenvalue {lam[0]:.3g} of K v = lam M v)")
    r = int(np.sum(lam <= SINGULAR_RTOL * top))
    _, sv, Vt = np.linalg.svd(K)
    Z = Vt[-r:].T                                   # the null space of K (smallest singular values)
    G = Z.T @ M @ Z
    Z = Z @ np.linalg.inv(np.linalg.cholesky(G)).T  # M-orthonormal: Z^T M Z = I
    # the elastic modes M-orthogonal to the rigid ones (eigh's are, to round-off); keep them as eigh gave them
    E = V[:, r:] - Z @ (Z.T @ M @ V[:, r:])
    w = np.concatenate([np.zeros(r), np.sqrt(lam[r:])])
    return w, _signed(np.hstack([Z, E]))


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


def floats(w: np.ndarray, V: np.ndarray) -> bool:
    """True if a rigid-body mode (``w = 0``) of the free state moves the contact coordinate (the last row of ``V``):
    a cracked bar's floating part, a body thrown at the stop.  Then **no periodic motion has a contact**.

    Over one period of a periodic motion the momentum ``p = v^T M x'`` of a rigid mode ``v`` (``K v = 0``, and
    ``C v = 0``: Rayleigh ``alpha = 0``, the only damping taken with rigid modes) returns to its value, and
    ``p' = v^T q cos(W t - phi) + v^T q_s + v_c lam``: the harmonic force integrates to 0 over the period, so
    without a constant load on the rigid motion (``v^T q_s = 0``) ``v_c int lam dt = 0`` while ``lam <= 0`` (the stop
    only pushes, impulses included): the contact force and every impulse vanish.  Every contact pushes the floating
    part away, and nothing brings it back on average.  With one (gravity pressing a dropped body or a crack shut,
    :attr:`plbar.model.Statics.accel`) the same balance says that the mean contact force over a period is
    ``-v^T q_s / v_c``: the load on the rigid motion, all of it carried by the stop.
    """
    k = int(np.sum(w == 0.0))
    if not k:
        return False
    R = V[:, :k]
    return bool(np.any(np.abs(R[-1]) > 1e-9 * np.abs(R).max(axis=0)))
