"""The extremes of the load quadratic forms: the worst load distribution and the best point force per element.

``xi_eq(q) = (b . q)^2 / (2 q^T G q)`` (:mod:`plbar.studies.loads.forms`): its
largest value over every ``q`` is the largest generalised eigenvalue
``b^T G^+ b / 2`` (:func:`worst`); for a point force moving over an element,
``q(s)`` are the shape functions and ``xi_eq`` is a ratio of polynomials in the
local coordinate, maximised exactly (:func:`element_max`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.polynomial import polynomial as P

from ...errors import InputError
from ...util.blas import single_thread_blas

__all__ = ["Worst", "ElementMax", "PointLoads", "element_max", "worst", "RCOND"]

RCOND = 1e-12       #: relative eigenvalue cutoff of the scaled Gram matrix (its numerical null space)


@dataclass(frozen=True)
class Worst:
    """Largest ``xi_eq`` over every load distribution, per path point.

    Attributes
    ----------
    xi : ndarray, shape (P,)
        ``b^T G^+ b / 2`` (the largest generalised eigenvalue).
    q : ndarray, shape (P, n)
        The maximising load ``q* = G^+ b``, unit 2-norm, signed so that ``b . q* >= 0``.
    rank : ndarray of int, shape (P,)
        Numerical rank of ``G`` (``n`` unless a direction fell under :data:`RCOND`).
    b_in_null : ndarray, shape (P,)
        Share of ``b`` in the dropped null space (0 if ``null(G)`` is inside ``null(b^T)``).
    """

    xi: np.ndarray
    q: np.ndarray
    rank: np.ndarray
    b_in_null: np.ndarray


@dataclass(frozen=True)
class ElementMax:
    """Exact maximum of ``xi_eq`` of a unit point force over each element, per path point.

    ``xi``, ``s``: shape (P, E); ``left``, ``right``: element ends (E,), sorted by position.
    """

    xi: np.ndarray
    s: np.ndarray
    left: np.ndarray
    right: np.ndarray

    def best(self):
        """Best single position over the whole bar: ``xi`` (P,) and ``s`` (P,)."""
        j = np.argmax(self.xi, axis=1)
        r = np.arange(self.xi.shape[0])
        return self.xi[r, j], self.s[r, j]


@dataclass(frozen=True)
class _Elements:
    """Element-local shape functions of the free DOFs: ``N_e(t) = C[e] @ (1, t, t^2, ...)``.

    ``dofs`` (E, k): free DOF of each local function (``n`` for the clamped DOF: a dummy
    with zero coefficients); ``C`` (E, k, deg+1) ascending powers; ``left, right`` (E,).
    """

    dofs: np.ndarray
    C: np.ndarray
    left: np.ndarray
    right: np.ndarray

    def locate(self, s):
        """Element index and local coordinate ``t`` in ``[0, 1]`` of positions ``s`` (S,)."""
        s = np.asarray(s, float)
        L = self.right[-1]
        if np.any((s < self.left[0] - 1e-12 * L) | (s > L * (1 + 1e-12))) or not np.all(np.isfinite(s)):
            raise InputError(f"load positions must lie on the bar [0, {L:g}]")
        e = np.clip(np.searchsorted(self.left, s, side="right") - 1, 0, self.left.size - 1)
        t = np.clip((s - self.left[e]) / (self.right[e] - self.left[e]), 0.0, 1.0)
        return e, t

    def values(self, e, t):
        """Shape-function values ``(S, k)`` at local coordinates ``t`` of elements ``e``."""
        return _polyval(self.C[e], t[:, None, None])[..., 0]


def _elements(asm) -> _Elements:
    """Element-local polynomial shape functions from the scikit-fem basis (any Lagrange degree)."""
    basis = asm.basis
    elem, mesh = basis.elem, basis.mesh
    deg = int(elem.maxdeg)
    n = asm.n
    fidx = np.full(basis.N, n)
    fidx[asm.free] = np.arange(n)
    dofs = fidx[basis.element_dofs].T                                   # (E, k)
    tt = 0.5 - 0.5 * np.cos(np.pi * np.arange(deg + 1) / max(deg, 1))   # Chebyshev-Lobatto on [0, 1]
    vals = np.array([elem.lbasis(tt[None, :], i)[0] for i in range(dofs.shape[1])])   # (k, deg+1)
    C = np.linalg.solve(np.vander(tt, deg + 1, increasing=True), vals.T).T           # (k, deg+1)
    C = np.where(np.abs(C) < 1e-14 * np.abs(C).max(), 0.0, C)
    C = np.broadcast_to(C, (dofs.shape[0],) + C.shape).copy()
    C[dofs == n] = 0.0
    x = mesh.p[0]
    left, right = x[mesh.t[0]], x[mesh.t[1]]
    if np.any(right <= left):
        raise InputError("the mesh has an element with non-increasing vertex order; cannot map load positions")
    order = np.argsort(left)
    return _Elements(dofs[order], C[order], left[order], right[order])


class PointLoads:
    """Unit point forces anywhere on the bar for the load forms (needs the assembled bar, ``self.asm``)."""

    def _elems(self) -> _Elements:
        if self.asm is None:
            raise InputError("point loads need the assembled bar: build the load forms from Paths or Orbits "
                             "whose Problem carries its Assembled (plbar.problem / Case.problem)")
        cache = self.__dict__.get("_elements_cache")
        if cache is None:
            cache = _elements(self.asm)
            object.__setattr__(self, "_elements_cache", cache)
        return cache

    def point_vectors(self, s):
        """Load vectors of unit point forces at positions ``s`` (S,): shape (S, n) (shape-function values)."""
        el = self._elems()
        e, t = el.locate(np.atleast_1d(s))
        Q = np.zeros((e.size, self.n + 1))
        np.add.at(Q, (np.arange(e.size)[:, None], el.dofs[e]), el.values(e, t))
        return Q[:, :-1]


# -- polynomials in the local coordinate (numpy.polynomial; ascending coefficients on the last axis) ----------
def _polyval(c, t):
    """``c`` (..., d+1) at ``t`` (..., K) -> (..., K) (Horner, :func:`numpy.polynomial.polynomial.polyval`)."""
    return P.polyval(t, np.moveaxis(c, -1, 0)[..., None], tensor=False)


def _padded(c, size: int) -> np.ndarray:
    """A coefficient series (trimmed by numpy.polynomial) padded with zeros to ``size`` coefficients."""
    return np.pad(c, (0, size - len(c)))


def _shape_products(C) -> tuple[np.ndarray, np.ndarray]:
    """Per element shape: ``N_i N_j`` (k, k, 2p+1) and ``2 N_k' N_i N_j - N_k (N_i N_j)'`` (k, k, k, 3p).

    The numerator of ``d xi / dt`` is ``2 a' d - a d'`` with ``a = b_k N_k`` and
    ``d = G_ij N_i N_j``: the polynomial arithmetic is done once per element
    shape (numpy.polynomial); path points only contract it with ``b`` and ``G``.
    """
    k, p = C.shape[0], C.shape[1] - 1
    NN = np.array([[_padded(P.polymul(C[i], C[j]), 2 * p + 1) for j in range(k)] for i in range(k)])
    T = np.zeros((k, k, k, max(3 * p, 1)))
    for m in range(k):
        for i in range(k):
            for j in range(k):
                r = P.polysub(2 * P.polymul(P.polyder(C[m]), NN[i, j]), P.polymul(C[m], P.polyder(NN[i, j])))
                T[m, i, j] = _padded(r[:T.shape[-1]], T.shape[-1])
    return NN, T


def _roots01(c, tol: float = 1e-14):
    """Real roots in ``[0, 1]`` of polynomials ``c`` (..., d+1); nan pads (..., d).

    Grouped by effective degree (leading coefficients below ``tol`` times the largest are
    dropped), the eigenvalues of the companion matrices of
    :func:`numpy.polynomial.polynomial.polycompanion`, batched (``polyroots`` takes one
    polynomial at a time: 5x (degree 5) to 20x (degree 2) slower over the path points), then two Newton
    steps on the full polynomial.
    """
    shp, d = c.shape[:-1], c.shape[-1] - 1
    cf = c.reshape(-1, d + 1)
    out = np.full((cf.shape[0], max(d, 1)), np.nan)
    scale = np.abs(cf).max(axis=1)
    big = np.abs(cf) > tol * scale[:, None]
    deg = np.where(big.any(axis=1), d - np.argmax(big[:, ::-1], axis=1), 0)
    for k in range(1, d + 1):
        rows = np.flatnonzero(deg == k)
        if rows.size == 0:
            continue
        comp = np.zeros((rows.size, k, k))                  # polycompanion: ones below the diagonal,
        comp[:, 1:, :-1] = np.eye(k - 1)                    # -c[:-1] / c[-1] in the last column
        comp[:, :, -1] = -cf[rows, :k] / cf[rows, k:k + 1]
        z = np.linalg.eigvals(comp)
        ok = (np.abs(z.imag) <= 1e-7 * (1 + np.abs(z.real))) & (z.real > -1e-7) & (z.real < 1 + 1e-7)
        out[rows, :k] = np.where(ok, np.clip(z.real, 0.0, 1.0), np.nan)
    dc = P.polyder(cf, axis=-1)
    for _ in range(2):
        f, fp = _polyval(cf, out), _polyval(dc, out)
        step = np.divide(f, fp, out=np.zeros_like(f), where=np.isfinite(fp) & (fp != 0))
        out = np.where(np.isfinite(out), np.clip(out - step, 0.0, 1.0), np.nan)
    return out.reshape(shp + (out.shape[-1],))


# -- construction -----------------------------------------------------------------------------------


def element_max(lf) -> ElementMax:
    """Exact maximum of ``xi_eq(s)`` over each element (a ratio of polynomials in the local coordinate).

    ``xi(t) = a(t)^2 / (2 d(t))`` with ``a = b . N(t)`` and ``d = N^T G N``; the interior
    extrema are the real roots in ``[0, 1]`` of ``2 a' d - a d'`` (degree ``3 p - 1``:
    2 for P1, 5 for P2), found as companion-matrix eigenvalues and polished by Newton.
    """
    el = lf._elems()
    bp, Gp = lf._local()
    C, d = el.C.copy(), el.dofs
    # an element at the clamp: every free shape function vanishes at t = 0, so a = t a~ and
    # d = t^2 d~; divide out (xi at t = 0 is then the limit of a force approaching the clamp)
    clamp = np.all(C[:, :, 0] == 0, axis=1)
    C[clamp] = np.concatenate([C[clamp, :, 1:], np.zeros(C[clamp, :, :1].shape)], axis=-1)
    shapes, inv = np.unique(C.reshape(C.shape[0], -1), axis=0, return_inverse=True)
    prods = [_shape_products(c.reshape(C.shape[1:])) for c in shapes]
    NN = np.array([q[0] for q in prods])[inv.ravel()]                         # (E, k, k, 2p+1)
    T = np.array([q[1] for q in prods])[inv.ravel()]                          # (E, k, k, k, 3p)
    bk = bp[:, d]                                                            # (P, E, k)
    Ge = Gp[:, d[:, :, None], d[:, None, :]]                                 # (P, E, k, k)
    a = np.einsum("pek,ekd->ped", bk, C)                                     # (P, E, p+1)
    dd = np.einsum("peij,eijd->ped", Ge, NN)                                 # (P, E, 2p+1)
    r = np.einsum("pem,peij,emijd->ped", bk, Ge, T, optimize=True)           # 2 a' d - a d'
    # candidates: the right end first (ties go to the node, not to the clamp), the roots, the left end
    t = np.concatenate([np.ones(a.shape[:2] + (1,)), _roots01(r), np.zeros(a.shape[:2] + (1,))], axis=-1)
    num = _polyval(a, t) ** 2
    den = _polyval(dd, t)
    xi = np.divide(num, 2 * den, out=np.zeros_like(num), where=(den > 0) & np.isfinite(t))
    j = np.argmax(xi, axis=-1)
    xi_max = np.take_along_axis(xi, j[..., None], -1)[..., 0]
    t_max = np.take_along_axis(t, j[..., None], -1)[..., 0]
    return ElementMax(xi_max, el.left + t_max * (el.right - el.left), el.left, el.right)


def worst(lf, rcond: float = RCOND) -> Worst:
    """Largest ``xi_eq`` over every load and its shape: ``b^T G^+ b / 2`` at ``q* = G^+ b``.

    Computed in the coordinates ``c`` where ``b`` is along ``e_a``: the pseudo-inverse of
    the symmetrically scaled ``Gamma`` drops eigenvalues below ``rcond`` times the largest.
    """
    Gam = lf.Gamma
    dsc = np.sqrt(np.einsum("pii->pi", Gam))
    dsc = np.where(dsc > 0, dsc, 1.0)
    with single_thread_blas:
        lam, U = np.linalg.eigh(Gam / (dsc[:, :, None] * dsc[:, None, :]))
    keep = lam > rcond * lam[:, -1:]
    inv = np.where(keep, 1.0 / np.where(keep, lam, 1.0), 0.0)
    ea = U[:, -1, :] / dsc[:, -1:]                         # e_a in the eigenbasis (scaled)
    cstar = np.einsum("pij,pj->pi", U, inv * ea) / dsc       # Gamma^+ e_a
    xi = 0.5 * lf.dPL(lf.q_ref) * cstar[:, -1]          # (b . q_ref)^2 = Delta_PL(q_ref)
    q = np.einsum("pij,pj->pi", lf.B, cstar)
    nq = np.linalg.norm(q, axis=1, keepdims=True)
    q = q / np.where(nq > 0, nq, 1.0)
    q = q * np.where(np.einsum("pi,pi->p", lf.b, q) < 0, -1.0, 1.0)[:, None]
    null = np.sqrt(np.sum(np.where(keep, 0.0, U[:, -1, :]) ** 2, axis=1))
    return Worst(xi, q, keep.sum(axis=1), null)
