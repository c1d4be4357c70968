"""Floquet multipliers of the periodic responses (FORMULATION §7).

The stroboscopic map over one forcing period, taken in state I just after
the impact (``t = 0+``), is linearised exactly in the state I coordinates
``z = (x_r, v_r)`` (physical displacements and velocities of the DOFs other
than the contact, dimension ``2 (n - 1)``):

``Phi = S_imp  Phi_II(T^II)  S_open  Phi_I(T^I)``,

* ``Phi_I``, ``Phi_II``: the segment flows, exact (closed-form modal
  harmonic flows, paper Sec. 2.2: ``[[cos w t, sin w t / w], [-w sin w t, cos w t]]``
  per mode, mapped to physical coordinates with ``x = V eta``,
  ``eta = V^T M x``); the load does not enter the linearisation;
* ``S_open`` (``2n x 2(n-1)``): saltation matrix of the gap opening at
  ``T^I``, event function ``h = -R(x_r, t)`` (explicitly time dependent
  through the load), reset ``y = E z`` (``x_c = v_c = 0``, FORMULATION §3),

  ``S_open = E + (f_II(E z) - E f_I(z)) dh^T / (dh . f_I(z) + dh/dt)``;

  at a switch with ``R = 0`` the accelerations of both states agree, so
  ``S_open = E`` up to the residual of ``R(T^I)``;
* ``S_imp`` (``2(n-1) x 2n``): saltation matrix of the plastic impact at
  ``T``, event function ``h = x_c``, reset ``g(y) = (x_r, M_rr^{-1} (M v)_r)``,

  ``S_imp = Dg + (f_I(g(y)) - Dg f_II(y)) e_{x_c}^T / v_c``.

The impact removes one direction of the state II space: ``S_imp`` has a
one-dimensional kernel (the velocity combination that only moves the
contact DOF, ``G dv = 0``).  That direction is in general not in the image
of ``Phi_II S_open Phi_I`` (a ``2(n-1)``-dimensional subspace of the
``2n``-dimensional state II space), so ``Phi`` itself is generically of full
rank and no multiplier is forced to zero; small ones do appear near grazing
impacts.  Multipliers are invariant under the choice of coordinates (modal
or physical) and of the section's phase.

With Rayleigh damping (FORMULATION §8) the flows are the damped ones, the
accelerations carry ``-C v``, and the opening's event ``h = -R`` depends on the
velocities too (``R = rho . x_r + rho_v . v_r + r_q cos``, ``rho_v = C_cr -
M_cr M_rr^{-1} C_rr``; modally ``r_eta . eta + r_v . eta'``), so its gradient and
rate include the damper term.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..util.batch import Batch
from ..util.reprs import build, count, rng

from ..errors import InputError
from .flow import flow_matrix

__all__ = ["Stability", "monodromy", "monodromy_modal", "multipliers", "stability", "periodic_state", "TOL"]

TOL = 1e-9  #: default stability margin: stable iff max |mu| < 1 - tol
CHUNK_ELEMENTS = 2e7  #: matrices of the monodromy are built for this many elements at a time


def periodic_state(orbits):
    """Physical state I start ``(x_r, v_r)`` of each orbit at ``t = 0+``: (P, n-1) each."""
    V1 = orbits.prob.system.V1
    return orbits.eta0 @ V1.T, orbits.v0 @ V1.T


def _flow_matrix(w, V, B, tau, zeta=None):
    """Physical free flow over ``tau`` (P,): ``(P, 2m, 2m)`` acting on ``(x, v)``.

    ``x = V eta``, ``eta = B x`` (``B = V^T M``); per mode
    ``[[cos, sin / w], [-w sin, cos]]`` (Appendix 1 without the load), or the
    damped flow with ``zeta``.
    """
    p11, p12, p21, p22 = flow_matrix(w[None, :], np.asarray(tau, float)[:, None], zeta)
    m = w.size
    P = p11.shape[0]
    A = np.zeros((P, 2 * m, 2 * m))
    VB = lambda d: np.einsum("ij,pj,jk->pik", V, d, B)  # noqa: E731
    A[:, :m, :m] = VB(p11)
    A[:, :m, m:] = VB(p12)
    A[:, m:, :m] = VB(p21)
    A[:, m:, m:] = VB(p22)
    return A


def _accel_I(M, K, q, xr, cf, C=None, vr=None):
    """State I accelerations ``M_rr^{-1} (q_r cos - K_rr x_r - C_rr v_r)``; xr (P, m), cf (P,)."""
    rhs = q[None, :-1] * cf[:, None] - xr @ K[:-1, :-1].T
    if C is not None:
        rhs = rhs - vr @ C[:-1, :-1].T
    return np.linalg.solve(M[:-1, :-1], rhs.T).T


def _accel_II(M, K, q, x, cf, C=None, v=None):
    """State II accelerations ``M^{-1} (q cos - K x - C v)``; x (P, n)."""
    rhs = q[None, :] * cf[:, None] - x @ K.T
    if C is not None:
        rhs = rhs - v @ C.T
    return np.linalg.solve(M, rhs.T).T


def _saltation_open(M, K, q, xr, vr, t, W, phi, C=None):
    """``S_open`` (P, 2n, 2m) at the gap opening with state I ``xr, vr`` (P, m) at times ``t``."""
    P, m = xr.shape
    n = m + 1
    H = np.linalg.solve(M[:-1, :-1].T, M[-1, :-1])            # M_cr M_rr^{-1} as a vector
    rho = K[-1, :-1] - H @ K[:-1, :-1]                          # R = rho . x_r + r_q cos(W t - phi)
    mrho_v = np.zeros(m) if C is None else H @ C[:-1, :-1] - C[-1, :-1]   # -rho_v, R = ... + rho_v . v_r
    r_q = H @ q[:-1] - q[-1]
    arg = W * t - phi
    cf = np.cos(arg)
    E = np.zeros((2 * n, 2 * m))
    E[:m, :m] = np.eye(m)
    E[n:n + m, m:] = np.eye(m)
    dh = np.concatenate([-rho, mrho_v])                        # gradient of h = -R in z = (x_r, v_r)
    h_t = r_q * W * np.sin(arg)                                 # dh/dt at fixed z
    aI = _accel_I(M, K, q, xr, cf, C, vr)
    fI = np.concatenate([vr, aI], axis=1)                       # (P, 2m)
    x = np.concatenate([xr, np.zeros((P, 1))], axis=1)
    v = np.concatenate([vr, np.zeros((P, 1))], axis=1)
    fII = np.concatenate([v, _accel_II(M, K, q, x, cf, C, v)], axis=1)  # (P, 2n)
    jump = fII - fI @ E.T
    hdot = fI @ dh + h_t
    return E[None] + jump[:, :, None] * dh[None, None, :] / hdot[:, None, None]


def _saltation_impact(M, K, q, x, v, t, W, phi, C=None):
    """``S_imp`` (P, 2m, 2n) at the plastic impact with state II ``x, v`` (P, n) at times ``t``."""
    P, n = x.shape
    m = n - 1
    G = np.linalg.solve(M[:-1, :-1], M[:-1, :])                # v_r^+ = G v^-
    Dg = np.zeros((2 * m, 2 * n))
    Dg[:m, :m] = np.eye(m)
    Dg[m:, n:] = G
    cf = np.cos(W * t - phi)
    fII = np.concatenate([v, _accel_II(M, K, q, x, cf, C, v)], axis=1)
    xr, vr = x[:, :m], v @ G.T
    fI = np.concatenate([vr, _accel_I(M, K, q, xr, cf, C, vr)], axis=1)
    vc = v[:, -1]
    S = np.repeat(Dg[None], P, axis=0)
    S[:, :, m] += (fI - fII @ Dg.T) / vc[:, None]              # column of x_c (event gradient e_{x_c})
    return S


def monodromy(orbits) -> np.ndarray:
    """Exact Jacobian of the one-period stroboscopic map at each orbit.

    Parameters
    ----------
    orbits : Orbits
        ``P`` periodic responses (:class:`plbar.orbit.Orbits`).

    Returns
    -------
    ndarray, shape (P, 2(n-1), 2(n-1))
        ``d z(T^+) / d z(0^+)`` in ``z = (x_r, v_r)``; compare with finite
        differences of :func:`plbar.simulate.period_map`.
    """
    prob = orbits.prob
    s = prob.system
    M, K, q = np.asarray(s.M, float), np.asarray(s.K, float), np.asarray(prob.q, float)
    if len(orbits) == 0:
        m = s.n - 1
        return np.zeros((0, 2 * m, 2 * m))
    T1, T2, phi = orbits.T1, orbits.T2, orbits.phi
    T = T1 + T2
    W = 2 * np.pi / T
    B1, B2 = s.V1.T @ M[:-1, :-1], s.V2.T @ M
    C = s.C if s.damped else None
    F1 = _flow_matrix(s.w1, s.V1, B1, T1, s.zeta[0])
    F2 = _flow_matrix(s.w2, s.V2, B2, T2, s.zeta[1])
    eI, vI = orbits.state_I(T1[:, None])
    xr, vr = eI[:, 0] @ s.V1.T, vI[:, 0] @ s.V1.T
    S_open = _saltation_open(M, K, q, xr, vr, T1, W, phi, C)
    eII, vII = orbits.end()
    S_imp = _saltation_impact(M, K, q, eII @ s.V2.T, vII @ s.V2.T, T, W, phi, C)
    return S_imp @ F2 @ S_open @ F1


def _modal_flow(w, tau, zeta=None):
    """Modal free flow over ``tau`` (P,): ``(P, 2m, 2m)`` with 2 x 2 blocks per mode on ``(eta, etadot)``."""
    p11, p12, p21, p22 = flow_matrix(w[None, :], np.asarray(tau, float)[:, None], zeta)
    P, m = p11.shape
    A = np.zeros((P, 2 * m, 2 * m))
    i = np.arange(m)
    A[:, i, i] = p11
    A[:, i, m + i] = p12
    A[:, m + i, i] = p21
    A[:, m + i, m + i] = p22
    return A


def monodromy_modal(orbits) -> np.ndarray:
    """The Jacobian of the one-period map in the modal coordinates of state I, ``(eta^I, etadot^I)``.

    Similar to :func:`monodromy` (same multipliers) for the full model,
    ``2 m1`` square for a modally truncated one (``plbar.problem(..., modes=m)``),
    where it is the linearisation of the truncated (Galerkin) dynamics.
    The saltation matrices are those of the module docstring written with
    the modal switch maps: ``E = diag(P12, P12)`` at the opening (event
    ``h = -R = -(r_eta . eta - ... )``), ``Dg = diag(P21, Q21)`` at the
    impact (event ``h = x_c = gap_row . eta^II``).

    Returns
    -------
    ndarray, shape (P, 2 m1, 2 m1)
    """
    prob = orbits.prob
    s = prob.system
    m1 = s.w1.size
    P = len(orbits)
    if P == 0:
        return np.zeros((0, 2 * m1, 2 * m1))
    T1, T2 = orbits.T1, orbits.T2
    F1 = _modal_flow(s.w1, T1, s.zeta[0])
    F2 = _modal_flow(s.w2, T2, s.zeta[1])
    return _modal_impact(orbits) @ F2 @ _modal_open(orbits) @ F1


def _modal_accel(w, zeta, f, eta, v, cf):
    """Modal accelerations ``-w^2 eta - 2 zeta w eta' + f cos`` (``zeta`` None: undamped); (P, m)."""
    a = -w ** 2 * eta + f * cf[:, None]
    return a if zeta is None else a - 2 * zeta * w * v


def _modal_open(orbits) -> np.ndarray:
    """``S_open`` (P, 2 m2, 2 m1) in modal coordinates: ``E + jump dh^T / hdot`` (event ``h = -R``)."""
    prob = orbits.prob
    s = prob.system
    m1, m2 = s.w1.size, s.w2.size
    z1, z2 = s.zeta
    W = orbits.W
    eI, vI = orbits.state_I(orbits.T1[:, None])
    e1, v1 = eI[:, 0], vI[:, 0]
    arg = W * orbits.T1 - orbits.phi
    cf = np.cos(arg)
    E = np.zeros((2 * m2, 2 * m1))
    E[:m2, :m1] = s.P12
    E[m2:, m1:] = s.P12
    aI = _modal_accel(s.w1, z1, prob.f1, e1, v1, cf)
    jump = np.zeros((len(orbits), 2 * m2))
    jump[:, m2:] = _modal_accel(s.w2, z2, prob.f2, e1 @ s.P12.T, v1 @ s.P12.T, cf) - aI @ s.P12.T
    # h = -R = -(r_eta . eta + r_v . eta' + r_q cos(W t - phi))  (r_v = 0 without damping)
    dh = np.concatenate([-np.asarray(s.r_eta, float), -np.asarray(s.r_v, float)])
    hdot = -(v1 @ s.r_eta) + prob.r_q * W * np.sin(arg)
    if z1 is not None:
        hdot = hdot - aI @ s.r_v
    return E[None] + jump[:, :, None] * dh[None, None, :] / hdot[:, None, None]


def _modal_impact(orbits) -> np.ndarray:
    """``S_imp`` (P, 2 m1, 2 m2) in modal coordinates: ``Dg + (f_I(g(y)) - Dg f_II(y)) e_xc^T / v_c``."""
    prob = orbits.prob
    s = prob.system
    m1, m2 = s.w1.size, s.w2.size
    z1, z2 = s.zeta
    e2, v2 = orbits.end()
    cfT = np.cos(orbits.W * orbits.T - orbits.phi)
    Dg = np.zeros((2 * m1, 2 * m2))
    Dg[:m1, :m2] = s.P21
    Dg[m1:, m2:] = s.Q21
    eP, vP = e2 @ s.P21.T, v2 @ s.Q21.T
    fI = np.concatenate([vP, _modal_accel(s.w1, z1, prob.f1, eP, vP, cfT)], axis=1)
    fII = np.concatenate([v2, _modal_accel(s.w2, z2, prob.f2, e2, v2, cfT)], axis=1)
    vc = v2 @ s.gap_row
    S_imp = np.repeat(Dg[None], len(orbits), axis=0)
    S_imp[:, :, :m2] += ((fI - fII @ Dg.T) / vc[:, None])[:, :, None] * np.asarray(s.gap_row, float)[None, None, :]
    return S_imp


def multipliers(orbits) -> np.ndarray:
    """Floquet multipliers of each orbit, sorted by decreasing modulus.

    Returns
    -------
    ndarray of complex, shape (P, 2 m1)
        Eigenvalues of :func:`monodromy_modal` (those of :func:`monodromy`
        for the full model; ``m1 = n - 1`` unless the modes are truncated).
    """
    m = orbits.prob.system.w1.size + orbits.prob.system.w2.size
    step = max(1, int(CHUNK_ELEMENTS // (8 * m * m)))      # memory: a few (points, 2m, 2m) matrices per chunk
    P = len(orbits)
    if P <= step:
        mu = np.linalg.eigvals(monodromy_modal(orbits)).astype(complex)
    else:
        mu = np.concatenate([np.linalg.eigvals(monodromy_modal(orbits.take(np.arange(i, min(i + step, P)))))
                             .astype(complex) for i in range(0, P, step)])
    order = np.argsort(-np.abs(mu), axis=1, kind="stable")
    return np.take_along_axis(mu, order, axis=1)


@dataclass(frozen=True)
class Stability(Batch):
    """Stability of ``P`` periodic orbits.

    Attributes
    ----------
    multipliers : ndarray of complex, shape (P, 2(n-1))
        Floquet multipliers, sorted by decreasing modulus.
    max_abs : ndarray, shape (P,)
        Spectral radius ``max |mu|``.
    stable : ndarray of bool, shape (P,)
        ``max_abs < 1 - tol``: every perturbation decays (asymptotic
        stability of the stroboscopic map).
    unstable : ndarray of bool, shape (P,)
        ``max_abs > 1 + tol``: some perturbation grows.  Orbits with
        ``|max_abs - 1| <= tol`` are neither (marginal: a multiplier on the
        unit circle within the tolerance, e.g. at a fold or a flip).
    tol : float
        The margin used.  The multipliers are exact up to the round-off
        of the flows (about ``1e-12`` relative), far below the default.
    """

    _shared = ("tol",)

    multipliers: np.ndarray
    max_abs: np.ndarray
    stable: np.ndarray
    unstable: np.ndarray
    tol: float

    def __repr__(self) -> str:
        return build("Stability", {"P": self.max_abs.size, "multipliers": f"{self.multipliers.shape}",
                                   "max_abs": rng(self.max_abs), "stable": count(self.stable),
                                   "unstable": count(self.unstable), "tol": self.tol})


def stability(orbits, tol: float = TOL) -> Stability:
    """Floquet multipliers and the stability verdict of each orbit (FORMULATION §7).

    Parameters
    ----------
    orbits : Orbits
    tol : float
        Margin around the unit circle, ``0 <= tol < 1`` (default ``1e-9``).
    """
    try:
        tol = float(tol)
    except (TypeError, ValueError):
        raise InputError(f"tol = {tol!r} is not a number; it must lie in [0, 1)") from None
    if not (0.0 <= tol < 1.0):
        raise InputError(f"tol = {tol!r} is not allowed; it must lie in [0, 1)")
    mu = multipliers(orbits)
    r = np.abs(mu).max(axis=1) if mu.shape[1] else np.zeros(len(orbits))
    return Stability(mu, r, r < 1 - tol, r > 1 + tol, tol)
