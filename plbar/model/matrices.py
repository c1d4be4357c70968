"""Checks of user-given free-DOF matrices (:func:`plbar.two_state`).

Each failure is one :class:`plbar.errors.InputError` line naming the matrix and
what is wrong with it, instead of a numpy or LAPACK error from deep inside the
eigensolver.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sps

from ..errors import InputError

__all__ = ["SYMMETRY_RTOL", "check_matrices"]

#: largest ``max|A - A^T| / max|A|`` accepted as symmetric (assembly round-off is ~1e-16)
SYMMETRY_RTOL = 1e-8


def _square(name: str, A) -> np.ndarray:
    """``A`` as a finite, square float array, or raise."""
    if sps.issparse(A):
        A = A.toarray()
    try:
        A = np.asarray(A, float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a square array of numbers, got {type(A).__name__}") from None
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise InputError(f"{name} must be a square matrix (n, n), got shape {A.shape}")
    bad = int(np.size(A) - np.count_nonzero(np.isfinite(A)))
    if bad:
        raise InputError(f"{name} has {bad} non-finite {'entry' if bad == 1 else 'entries'} (nan or inf)")
    return A


def _symmetric(name: str, A: np.ndarray) -> np.ndarray:
    """``A`` symmetrised if it is symmetric to :data:`SYMMETRY_RTOL`, else raise."""
    scale = float(np.max(np.abs(A))) if A.size else 0.0
    asym = float(np.max(np.abs(A - A.T))) if A.size else 0.0
    if asym > SYMMETRY_RTOL * scale:
        raise InputError(f"{name} is not symmetric: max|{name} - {name}^T| / max|{name}| = {asym / scale:.3g} "
                         f"(allowed {SYMMETRY_RTOL:g})")
    return A if asym == 0.0 else 0.5 * (A + A.T)


def _positive_definite(what: str, A: np.ndarray) -> None:
    """Raise unless the symmetric ``A`` is positive definite."""
    try:
        sla.cholesky(A, lower=True)
    except sla.LinAlgError:
        lam = float(sla.eigvalsh(A)[0])
        raise InputError(f"the {what} matrix is not positive definite (smallest eigenvalue {lam:.3g})") from None


def check_matrices(M, K, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(M, K, x)`` checked and as float arrays: square, same shape, finite, symmetric; ``M`` positive definite.

    Matrices symmetric to round-off (:data:`SYMMETRY_RTOL`) are symmetrised; exactly
    symmetric ones are returned as they are.  The stiffness of each state is checked
    where its modes are computed (:func:`plbar.model.system.two_state`).
    """
    M = _symmetric("M", _square("M", M))
    K = _symmetric("K", _square("K", K))
    if M.shape != K.shape:
        raise InputError(f"M and K must have the same shape, got {M.shape} and {K.shape}")
    n = M.shape[0]
    try:
        x = np.asarray(x, float)
    except (TypeError, ValueError):
        raise InputError(f"x must be an array of {n} DOF positions, got {type(x).__name__}") from None
    if x.shape != (n,):
        raise InputError(f"x must hold one position per DOF, shape ({n},), got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise InputError("x (the DOF positions) has non-finite entries (nan or inf)")
    if n >= 1:
        _positive_definite("mass", M)
    return M, K, x
