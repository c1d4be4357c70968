"""The one-period map at given ``(T^I, T^II)`` and the ONE scan function ``G`` (paper Sec. 2.3, FORMULATION §4).

Starting in state I at ``t = 0`` with modal state ``z = (eta^I, etadot^I)``,
one forcing period is the affine map ``z(T) = A z(0) + c(phi)``: state I flow
over ``T^I``, the I -> II switch, state II flow over ``T^II`` and the plastic
impact (Eq. (10)).  Periodicity gives ``(Id - A) z0 = c(phi)`` with
``c(phi) = cos(phi) c_c + sin(phi) c_s``, so the switch residuals

``e1 = -R(T^I-) = a1 cos(phi) + b1 sin(phi)``  (reaction vanishes, Eq. (4)),
``e2 = x_c(T-)  = a2 cos(phi) + b2 sin(phi)``  (gap closes, Eq. (5)),

vanish together iff ``D = a1 b2 - a2 b1 = 0``; then ``phi`` is exact.  Every
function here is batched over arrays of ``(T^I, T^II)``.

With Rayleigh damping (FORMULATION §8) the flows are the damped ones and the
reaction has its damper part, ``R = r_eta . eta + r_v . eta' + r_q cos(W t - phi)``;
the map stays affine in ``z`` and ``c(phi)`` linear in ``cos(phi), sin(phi)``, so
the phase elimination is unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Problem
from ..util.blas import serial_blas_for
from ..util.reprs import build, rng
from .flow import free_flow, kernels

__all__ = ["PeriodMap", "period_map", "Coefficients", "coefficients", "scan_function", "G", "phase", "states",
           "LAPACK_LOOP_DIM", "bytes_per_point"]


def scan_function(a1, b1, a2, b2, sign=1.0):
    """``G = sign (a1 b2 - a2 b1) / (a1^2 + b1^2 + a2^2 + b2^2)`` (0 where every coefficient vanishes).

    ``D = a1 b2 - a2 b1`` is zero on the periodic paths and has poles where
    ``Id - A`` is singular; with ``sign = sign(det(Id - A))``, ``G`` changes sign
    at the zeros of ``D`` only, is bounded by 1/2 and smooth at its zeros
    (FORMULATION §4).  With ``sign = 1`` it is smooth through the poles too,
    where it also vanishes.  This is the function the scan, the root refinement,
    the continuation and :func:`plbar.find_response` all use.
    """
    r = a1 * a1 + b1 * b1 + a2 * a2 + b2 * b2
    return np.divide((a1 * b2 - a2 * b1) * sign, r, out=np.zeros(np.shape(r)), where=r > 0)


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
    def G(self) -> np.ndarray:
        """:func:`scan_function` of these coefficients."""
        return scan_function(self.a1, self.b1, self.a2, self.b2, self.sign)

    def __repr__(self) -> str:
        return build("Coefficients", {"B": np.size(self.T1), "T1": rng(self.T1), "T2": rng(self.T2),
                                      "G": rng(self.G), "Z": f"{np.shape(self.Z)}"})


@dataclass(frozen=True)
class PeriodMap:
    """The one-period map evaluated at a batch of ``B`` points ``(T1, T2)``.

    Attributes
    ----------
    T1, T2 : ndarray, shape (B,)
    e1, e2 : ndarray, shape (B, 2)
        ``(a1, b1)`` and ``(a2, b2)``: the cos/sin parts of the switch residuals.
    Z : ndarray, shape (B, 2 n1, 2)
        Periodic initial states for the cos and sin parts of the phase.
    sign : ndarray, shape (B,) or None
        ``sign(det(Id - A))`` (0 where singular); None if not asked for.
    IA : ndarray, shape (B, 2 n1, 2 n1) or None
        ``Id - A``, kept when ``sign`` was not computed (to take the few signs needed later).
    sc1, sc2 : ndarray, shape (B,) or None
        Scales of ``e1``, ``e2`` (reaction and contact displacement amplitudes); None if not asked for.
    """

    T1: np.ndarray
    T2: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    Z: np.ndarray
    sign: np.ndarray | None = None
    IA: np.ndarray | None = None
    sc1: np.ndarray | None = None
    sc2: np.ndarray | None = None

    @property
    def G(self) -> np.ndarray:
        """:func:`scan_function` (with ``sign(det)`` if it was computed, else unsigned)."""
        return scan_function(self.e1[:, 0], self.e1[:, 1], self.e2[:, 0], self.e2[:, 1],
                             1.0 if self.sign is None else self.sign)

    def __repr__(self) -> str:
        return build("PeriodMap", {"B": np.size(self.T1), "T1": rng(self.T1), "T2": rng(self.T2),
                                   "G": rng(self.G), "Z": f"{np.shape(self.Z)}",
                                   "sign": self.sign is not None, "IA": self.IA is not None,
                                   "scales": self.sc1 is not None})

    def coefficients(self) -> Coefficients:
        return Coefficients(self.T1, self.T2, self.e1[:, 0], self.e1[:, 1], self.e2[:, 0], self.e2[:, 1],
                            self.sign, self.Z, self.sc1, self.sc2)


LAPACK_LOOP_DIM = 24   #: from this size of ``Id - A`` on, one LAPACK LU per point (getrf + getrs)


class _Consts:
    """Per-problem constants of :func:`coefficients` (computed once, cached on the Problem)."""

    def __init__(self, prob: Problem):
        s = prob.system
        self.m1, self.m2 = s.w1.size, s.w2.size
        self.w = np.concatenate([s.w1, s.w2])
        self.f1 = np.asarray(prob.f1, float)
        self.f2 = np.asarray(prob.f2, float)
        self.P12T = np.ascontiguousarray(s.P12.T)       # (m1, m2)
        self.P21T = np.ascontiguousarray(s.P21.T)       # (m2, m1)
        self.Q21T = np.ascontiguousarray(s.Q21.T)
        self.UT = self.P12T
        self.r_eta = np.asarray(s.r_eta, float)
        self.r_v = np.asarray(s.r_v, float)
        self.zeta = None if not s.damped else np.concatenate([s.zeta1, s.zeta2])
        self.gap_row = np.asarray(s.gap_row, float)
        self.r_q = float(prob.r_q)
        self.nr = float(np.linalg.norm(s.r_eta))
        self.nrv = float(np.linalg.norm(s.r_v))
        self.ng = float(np.abs(s.gap_row).max())
        self.eye = np.eye(2 * self.m1)
        self.f = np.concatenate([self.f1, self.f2])
        self.is1 = np.arange(self.m1 + self.m2) < self.m1
        self.PP = np.ascontiguousarray(np.hstack([s.P12, s.P12]))          # (m2, 2 m1)
        self.J = np.stack([s.P21, s.Q21])[None]                            # (1, 2, m1, m2)
        self.JT = np.stack([self.P21T, self.Q21T])[None]                   # (1, 2, m2, m1)
        # bytes of the largest temporaries per point (used to size batches)
        self.bytes_per_point = 8 * (6 * (2 * self.m1) * self.m2 + 3 * (2 * self.m1) ** 2 + 16 * (self.m1 + self.m2))


def _consts(prob: Problem) -> _Consts:
    """The constants of ``prob``, computed once."""
    return prob.cached("periodic", _Consts)


def bytes_per_point(prob: Problem) -> int:
    """Bytes of the largest temporaries of :func:`period_map` per point (to size batches)."""
    return _consts(prob).bytes_per_point


def _solve_lapack(IA: np.ndarray, c: np.ndarray):
    """One LU per point (LAPACK getrf + getrs); ``sign(det)`` from the LU."""
    from scipy.linalg.lapack import dgetrf, dgetrs

    B, n = IA.shape[:2]
    Z = np.empty(c.shape)
    sign = np.empty(B)
    ar = np.arange(1, n + 1)
    bad = []
    for i in range(B):
        lu, piv, info = dgetrf(IA[i])
        d = np.diagonal(lu)
        if info != 0 or not np.all(np.isfinite(d)):
            bad.append(i)
            continue
        neg = np.count_nonzero(d < 0) + np.count_nonzero(piv + 1 != ar)
        sign[i] = -1.0 if neg % 2 else 1.0
        Z[i] = dgetrs(lu, piv, c[i])[0]
    for i in bad:
        Z[i] = np.linalg.lstsq(IA[i], c[i], rcond=None)[0]
        sign[i] = 0.0
    return Z, sign


def _solve(IA: np.ndarray, c: np.ndarray):
    """Batched solve of the periodicity system and ``sign(det)``.

    An exactly singular ``Id - A`` (a free periodic motion of the two-state
    system with period ``T``) gets the least-squares solution and sign 0,
    so that it can never pass as a zero of ``D`` silently.  Small systems use
    numpy's batched ``slogdet`` and ``solve``; from ``LAPACK_LOOP_DIM`` on, one
    LAPACK LU per point serves both.
    """
    if IA.shape[-1] >= LAPACK_LOOP_DIM:
        return _solve_lapack(IA, c)
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


def _blocks(k: _Consts, T1: np.ndarray, T2: np.ndarray) -> dict:
    """``Id - A``, ``c`` and the flow pieces the residuals need, from stacked blocks.

    The number of numpy calls does not depend on the system size (small
    batches are dominated by call overhead): with ``p, q`` over (displacement,
    velocity) and ``c`` over the phase parts (``cos phi``, ``sin phi``),

    * ``X[b, q] = P12 * R1[b, q]`` (state I flow then the I -> II switch),
    * ``Y[b, p] = sum_q R2[b, p, q] X[b, q]`` (state II flow),
    * ``A[b, p] = J_p Y[b, p]`` with ``J = (P21, Q21)`` (plastic impact).
    """
    m1, m2 = k.m1, k.m2
    n = 2 * m1
    B = T1.size
    W = 2 * np.pi / (T1 + T2)
    Wc = W[:, None]
    tau = np.where(k.is1, T1[:, None], T2[:, None])              # (B, m)
    if k.zeta is None:
        co, si_w, mwsi, si = free_flow(k.w, tau)
        C, S, Cp = kernels(k.w, Wc, tau, si)
        flows = [co, si_w, mwsi, co]
    else:                                                         # damped modes (FORMULATION §8)
        flows = list(free_flow(k.w, tau, k.zeta))
        C, S, Cp = kernels(k.w, Wc, tau, zeta=k.zeta)
    # flows as stacked rows: R[b, p, q, j] = [[cos, sin/w], [-w sin, cos]] (undamped)
    R = np.array(flows).reshape(2, 2, B, m1 + m2).transpose(2, 0, 1, 3)
    R1, R2 = R[..., :m1], R[..., m1:]
    X = k.PP * R1.reshape(B, 2, 1, n)
    Y = R2[:, :, 0, :, None] * X[:, None, 0] + R2[:, :, 1, :, None] * X[:, None, 1]
    IA = k.eye - np.matmul(k.J, Y).reshape(B, n, n)
    # forced parts F[b, p, c, j]: p = displacement/velocity, c = cos(phi)/sin(phi) part
    F = (k.f * np.array([C, S, Cp, Wc * C])).reshape(2, 2, B, m1 + m2).transpose(2, 0, 1, 3)
    g1 = F[..., :m1]                                                # state I from t = 0
    c0, s0 = np.cos(W * T1), np.sin(W * T1)
    rot = np.array([c0, -s0, s0, c0]).T.reshape(B, 1, 2, 2)
    g2 = np.matmul(rot, F[..., m1:])                                # state II from t = T1 (phase shifted)
    h = np.matmul(g1, k.UT)                                         # (B, 2, 2, m2)
    ge = R2[:, :, :1] * h[:, None, 0] + R2[:, :, 1:] * h[:, None, 1] + g2   # forced state at T-, (B, 2, 2, m2)
    cT = np.matmul(ge, k.JT)                                        # (B, 2, 2, m1): rows p, columns c
    c = cT.transpose(0, 1, 3, 2).reshape(B, n, 2)
    return dict(IA=IA, c=c, R1=R1, R2=R2, g1=g1, g2=g2, c0=c0, s0=s0)


def _residuals(k: _Consts, Z: np.ndarray, b: dict):
    """Switch residual coefficients ``e1, e2`` (B, 2) and the states they come from (Eqs. (4)-(5))."""
    B, m1 = Z.shape[0], k.m1
    R1, R2 = b["R1"], b["R2"]
    Zr = Z.reshape(B, 2, m1, 2).transpose(0, 1, 3, 2)              # (B, q, c, m1)
    zI = R1[:, :, :1] * Zr[:, None, 0] + R1[:, :, 1:] * Zr[:, None, 1] + b["g1"]   # state I at T1
    eI = zI[:, 0]
    e1 = -(eI @ k.r_eta) if k.zeta is None else -(eI @ k.r_eta + zI[:, 1] @ k.r_v)
    e1[:, 0] -= k.r_q * b["c0"]
    e1[:, 1] -= k.r_q * b["s0"]
    hI = np.matmul(zI, k.UT)
    eII = R2[:, 0, :1] * hI[:, 0] + R2[:, 0, 1:] * hI[:, 1] + b["g2"][:, 0]       # state II displacement at T-
    return e1, eII @ k.gap_row, eI, eII, zI


def period_map(prob: Problem, T1, T2, *, signs: bool = True, scales: bool = True) -> PeriodMap:
    """The one-period map at each ``(T1, T2)``: residual coefficients and periodic states.

    Parameters
    ----------
    prob : Problem
    T1, T2 : array_like, shape (B,)
        Times spent in state I and state II.
    signs : bool
        Compute ``sign(det(Id - A))`` (else ``Id - A`` is kept in the result).
    scales : bool
        Compute the residual scales ``sc1, sc2``.
    """
    T1 = np.atleast_1d(np.asarray(T1, float))
    T2 = np.atleast_1d(np.asarray(T2, float))
    k = _consts(prob)
    m = prob.system.w1.size + prob.system.w2.size
    with serial_blas_for(T1.size * m * m):
        b = _blocks(k, T1, T2)
        if signs:
            Z, sign = _solve(b["IA"], b["c"])
        else:
            Z, sign = np.linalg.solve(b["IA"], b["c"]), None
        e1, e2, eI, eII, zI = _residuals(k, Z, b)
    sc1 = sc2 = None
    if scales:
        sc1 = k.nr * np.sqrt(np.einsum("bkj,bkj->bk", eI, eI)).max(axis=1) + abs(k.r_q)
        if k.zeta is not None:                                       # the damper part of the reaction
            sc1 = sc1 + k.nrv * np.sqrt(np.einsum("bkj,bkj->bk", zI[:, 1], zI[:, 1])).max(axis=1)
        sc2 = k.ng * np.sqrt(np.einsum("bkj,bkj->bk", eII, eII)).max(axis=1)
    return PeriodMap(T1, T2, e1, e2, Z, sign, None if signs else b["IA"], sc1, sc2)


def coefficients(prob: Problem, T1, T2) -> Coefficients:
    """Residual coefficients ``a1, b1, a2, b2`` at each ``(T1, T2)`` (with signs, states and scales)."""
    return period_map(prob, T1, T2).coefficients()


def G(prob: Problem, T1, T2) -> np.ndarray:
    """:func:`scan_function` at ``(T1, T2)`` (arrays of equal shape; the result has that shape)."""
    shape = np.shape(T1)
    return period_map(prob, np.ravel(T1), np.ravel(T2), scales=False).G.reshape(shape)


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
