"""Periodic responses for given ``(T^I, T^II, phi)`` (paper Sec. 2.3, FORMULATION §4).

Starting in state I at ``t = 0`` with modal state ``z = (eta^I, etadot^I)``,
one forcing period is the affine map ``z(T) = A z(0) + c(phi)``: state I flow
over ``T^I``, the I -> II switch, state II flow over ``T^II`` and the plastic
impact (Eq. (10)).  Periodicity gives ``(Id - A) z0 = c(phi)`` with
``c(phi) = cos(phi) c_c + sin(phi) c_s``, so the switch residuals

``e1 = -R(T^I-) = a1 cos(phi) + b1 sin(phi)``  (reaction vanishes, Eq. (4)),
``e2 = x_c(T-)  = a2 cos(phi) + b2 sin(phi)``  (gap closes, Eq. (5)),

vanish together iff ``D = a1 b2 - a2 b1 = 0``; then ``phi`` is exact.  Every
function here is batched over arrays of ``(T^I, T^II)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .flow import forced_coeffs
from .system import Problem

__all__ = ["Coefficients", "coefficients", "phase", "states"]


@dataclass(frozen=True)
class Coefficients:
    """Residual coefficients at a batch of ``(T1, T2)`` points, shape ``(B,)`` each.

    ``Z`` (shape ``(B, 2 n1, 2)``) holds the periodic initial state for
    ``cos(phi) = 1, sin(phi) = 0`` (column 0) and the reverse (column 1).
    ``sign`` is the sign of ``det(Id - A)``: ``D * sign`` has no sign change
    at the poles of ``D`` (where ``Id - A`` is singular).
    """

    T1: np.ndarray
    T2: np.ndarray
    a1: np.ndarray
    b1: np.ndarray
    a2: np.ndarray
    b2: np.ndarray
    sign: np.ndarray
    Z: np.ndarray
    e1_scale: np.ndarray
    e2_scale: np.ndarray

    @property
    def D(self) -> np.ndarray:
        """``D = a1 b2 - a2 b1`` (zero on periodic paths, poles where Id - A is singular)."""
        return self.a1 * self.b2 - self.a2 * self.b1

    @property
    def F(self) -> np.ndarray:
        """``D * sign(det(Id - A))``: changes sign at the zeros of ``D`` only."""
        return self.D * self.sign

    @property
    def G(self) -> np.ndarray:
        """``F / (a1^2 + b1^2 + a2^2 + b2^2)``: bounded by 1/2, same sign as ``F``, smooth at its zeros.

        The scan and the root refinement use ``G``: near a pole ``D`` is huge
        but ``G`` stays bounded (it touches 0 there without a sign change).
        """
        r = self.a1 ** 2 + self.b1 ** 2 + self.a2 ** 2 + self.b2 ** 2
        return np.divide(self.F, r, out=np.zeros_like(r), where=r > 0)


def _flow_mats(w, T):
    """cos, sin/w, -w sin of the free flow over ``T`` for modes ``w``: shapes (B, n)."""
    wt = w[None, :] * T[:, None]
    co, si = np.cos(wt), np.sin(wt)
    return co, si / w, -w * si


def _solve(IA: np.ndarray, c: np.ndarray):
    """Batched solve of the periodicity system and ``sign(det)``.

    An exactly singular ``Id - A`` (a free periodic motion of the two-state
    system with period ``T``) gets the least-squares solution and sign 0,
    so that it can never pass as a zero of ``D`` silently.
    """
    sign, logdet = np.linalg.slogdet(IA)
    ok = (sign != 0) & np.isfinite(logdet)
    Z = np.empty(c.shape)
    if ok.all():
        return np.linalg.solve(IA, c), sign
    if ok.any():
        Z[ok] = np.linalg.solve(IA[ok], c[ok])
    for i in np.flatnonzero(~ok):
        Z[i] = np.linalg.lstsq(IA[i], c[i], rcond=None)[0]
    return Z, np.where(ok, sign, 0.0)


def coefficients(prob: Problem, T1, T2) -> Coefficients:
    """Residual coefficients ``a1, b1, a2, b2`` at each ``(T1, T2)``.

    Parameters
    ----------
    prob : Problem
    T1, T2 : array_like, shape (B,)
        Times spent in state I and state II.
    """
    s = prob.system
    T1 = np.atleast_1d(np.asarray(T1, float))
    T2 = np.atleast_1d(np.asarray(T2, float))
    T = T1 + T2
    W = 2 * np.pi / T
    n1 = s.w1.size
    co1, sw1, ws1 = _flow_mats(s.w1, T1)
    co2, sw2, ws2 = _flow_mats(s.w2, T2)
    g1 = forced_coeffs(s.w1[None], prob.f1[None], W[:, None], 0.0, T1[:, None])
    g2 = forced_coeffs(s.w2[None], prob.f2[None], W[:, None], T1[:, None], T2[:, None])
    P12, P21, Q21 = s.P12, s.P21, s.Q21
    # S12 Phi1, as blocks over (eta, v) of state I -> rows eta2 and v2
    Xe = np.concatenate([P12[None] * co1[:, None, :], P12[None] * sw1[:, None, :]], axis=2)
    Xv = np.concatenate([P12[None] * ws1[:, None, :], P12[None] * co1[:, None, :]], axis=2)
    Ye = co2[:, :, None] * Xe + sw2[:, :, None] * Xv
    Yv = ws2[:, :, None] * Xe + co2[:, :, None] * Xv
    A = np.concatenate([P21 @ Ye, Q21 @ Yv], axis=1)
    # forced part, for cos(phi) and sin(phi)
    ge1 = np.stack([g1[0], g1[1]], axis=-1)            # (B, n1, 2)
    gv1 = np.stack([g1[2], g1[3]], axis=-1)
    he = np.einsum("ij,bjk->bik", P12, ge1)
    hv = np.einsum("ij,bjk->bik", P12, gv1)
    ge2 = co2[..., None] * he + sw2[..., None] * hv + np.stack([g2[0], g2[1]], axis=-1)
    gv2 = ws2[..., None] * he + co2[..., None] * hv + np.stack([g2[2], g2[3]], axis=-1)
    c = np.concatenate([np.einsum("ij,bjk->bik", P21, ge2), np.einsum("ij,bjk->bik", Q21, gv2)], axis=1)
    IA = np.eye(2 * n1)[None] - A
    Z, sign = _solve(IA, c)
    # state at the end of state I, and at the end of state II
    e0, v0 = Z[:, :n1], Z[:, n1:]
    eI = co1[..., None] * e0 + sw1[..., None] * v0 + ge1
    vI = ws1[..., None] * e0 + co1[..., None] * v0 + gv1
    fc = np.stack([np.cos(W * T1), np.sin(W * T1)], axis=-1)       # cos(W T1 - phi) coefficients
    e1 = -(np.einsum("j,bjk->bk", s.r_eta, eI) + prob.r_q * fc)
    eII = (co2[..., None] * np.einsum("ij,bjk->bik", P12, eI) + sw2[..., None] * np.einsum("ij,bjk->bik", P12, vI)
           + np.stack([g2[0], g2[1]], axis=-1))
    e2 = np.einsum("j,bjk->bk", s.gap_row, eII)
    sc1 = np.linalg.norm(s.r_eta) * np.linalg.norm(eI, axis=1).max(axis=1) + abs(prob.r_q)
    sc2 = np.abs(s.gap_row).max() * np.linalg.norm(eII, axis=1).max(axis=1)
    return Coefficients(T1, T2, e1[:, 0], e1[:, 1], e2[:, 0], e2[:, 1], sign, Z, sc1, sc2)


def phase(co: Coefficients) -> np.ndarray:
    """The exact phase in ``[0, pi)`` that zeroes the residuals where ``D = 0``.

    ``(cos phi, sin phi)`` is the null vector of ``[[a1, b1], [a2, b2]]``
    taken from its larger row; the other root is ``phi + pi`` (the negated
    response).
    """
    r1 = np.hypot(co.a1, co.b1)
    r2 = np.hypot(co.a2, co.b2)
    use1 = r1 >= r2
    c = np.where(use1, co.b1, co.b2)
    s = -np.where(use1, co.a1, co.a2)
    return np.mod(np.arctan2(s, c), np.pi)


def states(co: Coefficients, phi) -> tuple[np.ndarray, np.ndarray]:
    """Periodic initial modal state ``(eta^I(0), etadot^I(0))`` at phases ``phi``.

    Returns
    -------
    eta0, v0 : ndarray, shape (B, n1)
    """
    phi = np.asarray(phi, float)
    z = co.Z[..., 0] * np.cos(phi)[:, None] + co.Z[..., 1] * np.sin(phi)[:, None]
    n1 = z.shape[1] // 2
    return z[:, :n1], z[:, n1:]


def residuals(co: Coefficients, phi) -> tuple[np.ndarray, np.ndarray]:
    """Switch residuals ``e1, e2`` at phases ``phi`` and their relative sizes."""
    phi = np.asarray(phi, float)
    c, s = np.cos(phi), np.sin(phi)
    e1 = co.a1 * c + co.b1 * s
    e2 = co.a2 * c + co.b2 * s
    return e1, e2
