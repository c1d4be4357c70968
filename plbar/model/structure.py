"""A two-state structure: the one record of a model that every solver takes (FORMULATION §2, generalised).

The structure obeys ``M x'' + C x' + K x = q cos(W t - phi) + r lambda`` with one unilateral contact on the
contact coordinate ``u = r . x``: the stop allows ``u <= d`` only (``d`` the gap, 0 in the paper) and pushes
(``lambda <= 0``, the reaction ``R = -lambda >= 0``) while ``u = d``.  ``r`` is any row: one DOF (the paper's
bar end, ``r = e_c``), or the difference of two DOFs (two bodies that close a joint, the faces of a crack).
Nothing in it is bar-specific: the builders (:func:`plbar.model.bar_structure` for the FE bar and the paper's
chain, or a user's own matrices) make it, and :func:`plbar.problem` turns it into the two-state modal problem.

The solvers work in the **contact coordinates** ``y`` of :func:`contact_coordinates`: the DOFs other than the
one ``c`` of largest ``|r_c|``, in their order, then ``u = r . x`` last.  ``x = B y`` with ``B`` unit
triangular up to that permutation, so ``B^T M B``, ``B^T K B`` are SPD again and the contact is the last
coordinate (the form of Eqs. (2)-(10)).  The contact impulse acts on ``u`` alone in these coordinates
(``B^T r = e_u``), so the plastic impact keeps the generalised momenta of every other coordinate (Eq. (10))
and the state with the contact held is the first ``n - 1`` coordinates; energies, ``Delta_PL`` and ``xi_eq``
are the same in any coordinates.  For a contact row ``e_{n-1}`` (the bar) ``B = I``: nothing is transformed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..util.check import show
from ..util.reprs import build, rng
from .damping import check_rayleigh
from .matrices import check_matrices
from .statics import check_gap

__all__ = ["Coordinates", "Structure", "check_restitution", "contact_coordinates"]


def check_restitution(e) -> float:
    """A validated coefficient of restitution: a finite number in ``[0, 1]``."""
    bad = f"restitution = {e!r} must be a number in [0, 1] (0: plastic impact, the paper; 1: elastic)"
    if isinstance(e, (bool, str, bytes)):
        raise InputError(bad)
    try:
        v = float(e)
    except (TypeError, ValueError):
        raise InputError(bad) from None
    if not 0.0 <= v <= 1.0:
        raise InputError(bad)
    return v


def _vector(name: str, v, n: int) -> np.ndarray:
    try:
        a = np.asarray(v, float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a vector of {n} numbers, got {show(v)}") from None
    if a.shape != (n,):
        raise InputError(f"{name} must have one entry per DOF, shape ({n},), got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} has non-finite entries (nan or inf)")
    return a


@dataclass(frozen=True, eq=False)
class Structure:
    """What every solver needs of a two-state structure, and nothing of where it came from.

    Parameters
    ----------
    M, K : array_like or scipy.sparse matrix, shape (n, n)
        Mass and stiffness over the free DOFs: finite, symmetric (to a relative ``1e-8``), ``M`` positive
        definite; the stiffness with the contact held must be positive definite, and free positive
        semi-definite (a free body, a cracked bar's floating part: its rigid-body modes move with ``w = 0``;
        checked where the modes are computed).  Stored dense (the modal solvers are dense).
    contact : array_like, shape (n,)
        The contact row ``r``: the contact coordinate is ``u = r . x``, held at ``u <= 0`` by the stop.
    q : array_like, shape (n,)
        The load amplitude vector (the force ``q cos(W t - phi)``, Eq. (1)); finite.  Zero is allowed (a free
        motion from a given start, a body thrown at the stop): the simulators take it; the periodic solvers find
        no forced response in it.
    rayleigh : (float, float), optional
        Inherent Rayleigh damping ``C = alpha M + beta K`` (FORMULATION §8); None: undamped (the paper).
    restitution : float
        Newton's coefficient ``e`` of the contact, in ``[0, 1]``; 0, the paper's plastic impact.
    x : array_like, shape (n,), optional
        A position per DOF, for output (default ``1..n``).
    origin : object, optional
        What built the structure (:class:`plbar.model.BarOrigin` for a bar), for descriptions and the bar's own
        studies; no solver reads it.
    gap : float
        The stop's position ``d`` on the contact coordinate: the stop holds ``u <= d`` (FORMULATION §9); ``d > 0``
        a clearance, ``d < 0`` an interference (a preload), 0 (the default) the paper.
    q_s : array_like, shape (n,), optional
        A constant load beside the harmonic one (gravity, a prestress: FORMULATION §9, affine terms): the structure
        obeys ``M x'' + C x' + K x = q cos(W t - phi) + q_s + r lambda``.  None (the default): none.

    Two structures are equal only if they are the same object (arrays have no hash); :attr:`fingerprint`
    identifies the content.
    """

    M: np.ndarray
    K: np.ndarray
    contact: np.ndarray
    q: np.ndarray
    rayleigh: tuple[float, float] | None = None
    restitution: float = 0.0
    x: np.ndarray | None = None
    origin: object = None
    gap: float = 0.0
    q_s: np.ndarray | None = None

    def __post_init__(self):
        n = np.shape(self.M)[0] if np.ndim(self.M) == 2 or hasattr(self.M, "toarray") else 0
        x = np.arange(1.0, n + 1.0) if self.x is None else self.x
        M, K, x = check_matrices(self.M, self.K, x)
        n = M.shape[0]
        if n < 1:
            raise InputError(f"the structure needs at least 1 free DOF, got {n}")
        r = _vector("contact", self.contact, n)
        if not np.any(r):
            raise InputError("contact = 0: the contact row must have a non-zero entry (u = r . x)")
        q = _vector("q", self.q, n)
        q_s = None if self.q_s is None else _vector("q_s", self.q_s, n)
        for name, v in (("M", M), ("K", K), ("contact", r), ("q", q), ("x", x),
                        ("rayleigh", check_rayleigh(self.rayleigh)),
                        ("restitution", check_restitution(self.restitution)), ("gap", check_gap(self.gap)),
                        ("q_s", q_s if q_s is not None and np.any(q_s) else None)):
            object.__setattr__(self, name, v)      # the validated, converted inputs; no other state

    @property
    def n(self) -> int:
        """Number of free DOFs."""
        return self.M.shape[0]

    @property
    def damped(self) -> bool:
        """True with Rayleigh damping."""
        return self.rayleigh is not None

    def __repr__(self) -> str:
        items = {"n": self.n, "contact": _describe_row(self.contact), "q": rng(self.q)}
        if self.rayleigh is not None:
            items["rayleigh"] = self.rayleigh
        if self.restitution:
            items["restitution"] = self.restitution
        if self.gap:
            items["gap"] = self.gap
        if self.q_s is not None:
            items["q_s"] = rng(self.q_s)
        if self.origin is not None:
            items["origin"] = type(self.origin).__name__
        return build("Structure", items)

    @property
    def fingerprint(self) -> str:
        """A digest of what the solvers read (matrices, contact row, load, damping, restitution, gap, constant
        load)."""
        import hashlib

        h = hashlib.sha256()
        for a in (self.M, self.K, self.contact, self.q):
            h.update(np.ascontiguousarray(a, float).tobytes())
        h.update(repr((self.rayleigh, self.restitution) + ((self.gap,) if self.gap else ())).encode())
        if self.q_s is not None:
            h.update(b"q_s" + np.ascontiguousarray(self.q_s, float).tobytes())
        return h.hexdigest()[:16]

    def physical(self, y: np.ndarray) -> np.ndarray:
        """DOF vectors ``x = B y`` (last axis) from the solvers' contact coordinates (:func:`contact_coordinates`)."""
        return np.asarray(y, float) @ _basis(self)[0].T


def _describe_row(r: np.ndarray) -> str:
    nz = np.flatnonzero(r)
    return " + ".join(f"{r[i]:g} x[{i}]" for i in nz[:4]) + (" + ..." if nz.size > 4 else "")


@dataclass(frozen=True)
class Coordinates:
    """A structure in its contact coordinates ``y`` (contact coordinate last, ``x = B y``).

    Attributes
    ----------
    M, K : ndarray, shape (n, n)
        ``B^T M B``, ``B^T K B``.
    q : ndarray, shape (n,)
        ``B^T q``, the generalised load.
    q_s : ndarray, shape (n,) or None
        ``B^T q_s``, the generalised constant load (None: none).
    x : ndarray, shape (n,)
        The positions of the coordinates (the contact coordinate at the position of DOF ``c``).
    B : ndarray, shape (n, n)
        ``x = B y``; the identity for a contact row ``e_{n-1}``.
    identity : bool
        True if ``B = I`` (nothing was transformed).
    """

    M: np.ndarray
    K: np.ndarray
    q: np.ndarray
    x: np.ndarray
    B: np.ndarray
    identity: bool
    q_s: np.ndarray | None = None


def contact_coordinates(s: Structure) -> Coordinates:
    """The structure ``s`` in coordinates whose last one is the contact coordinate ``u = r . x``.

    With ``c`` the DOF of largest ``|r_c|`` (the last of equals) and ``o`` the others in their order,
    ``y = (x_o, r . x)``: ``x_o = y_o`` and ``x_c = (u - r_o . y_o) / r_c``.  Exact (no arithmetic) when ``r``
    is a multiple of one unit vector up to the scale of ``u``, and the identity for ``r = e_{n-1}``.
    """
    B, c, o = _basis(s)
    r = s.contact
    if c == s.n - 1 and r[c] == 1.0 and not np.any(r[o]):
        return Coordinates(s.M, s.K, s.q, s.x, B, True, s.q_s)
    x = np.concatenate([s.x[o], s.x[c:c + 1]])
    return Coordinates(B.T @ s.M @ B, B.T @ s.K @ B, B.T @ s.q, x, B, False,
                       None if s.q_s is None else B.T @ s.q_s)


def _basis(s: Structure) -> tuple[np.ndarray, int, np.ndarray]:
    """``B`` of :func:`contact_coordinates` (``x = B y``), the DOF ``c`` the contact coordinate replaces, the others."""
    r, n = s.contact, s.n
    c = int(n - 1 - np.argmax(np.abs(r)[::-1]))
    o = np.array([i for i in range(n) if i != c], int)
    B = np.zeros((n, n))
    B[o, np.arange(n - 1)] = 1.0
    B[c, :-1] = -r[o] / r[c]
    B[c, -1] = 1.0 / r[c]
    return B, c, o
