"""Baselines for the plbar speed benchmark (issue "Speed").

Two ways of getting periodic responses *without* plbar's exact phase
elimination and closed-form path machinery:

* :class:`Shooting` -- what a user with only SciPy would write: event-driven
  ``solve_ivp`` integration of the two-state system in physical coordinates
  over one period (reaction zero in state I, gap closing in state II, plastic
  impact ``M_rr v_r+ = (M v-)_r``), wrapped in ``scipy.optimize.root`` over
  the periodic initial state and the forcing phase at a fixed period ``T``.

* :func:`scan3d` -- the paper's method (Sec. 2.3 / 4.1): scan the 3D space
  ``(T^I, T^II, phi)`` on a ``200 x 200 x 50`` grid, solve the periodicity
  system ``(Id - A) z0 = c(phi)`` at every triplet (vectorised, batched LAPACK
  solves), evaluate both switch residuals ``e1, e2`` at every triplet, keep
  the triplets where both zero surfaces pass within half a grid cell, and
  filter the candidates by time-history sampling (admissibility).

Only the modal data are computed with plain SciPy here (``eigh``); none of
plbar's solver code (``plbar.periodic``, ``plbar.flow``, ``plbar.paths``,
``plbar.admissible``) is used, so the baselines are independent checks too.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
from scipy.integrate import solve_ivp
from scipy.optimize import root

__all__ = ["Shooting", "ShootingResult", "Modal", "modal", "scan3d", "Scan3D", "branch_coverage"]


# ----------------------------------------------------------------------------------------------
# Physical-coordinate event-driven shooting
# ----------------------------------------------------------------------------------------------


@dataclass
class ShootingResult:
    success: bool
    message: str
    x0: np.ndarray          # x_r(0), physical, state I
    v0: np.ndarray          # v_r(0)
    phi: float
    T: float
    T1: float               # time of the I -> II switch (event)
    t_impact: float         # time of the gap closing (event), = T on a periodic orbit
    residual: float         # relative periodicity residual  max|z(T) - z(0)| / max|z(0)|, and |t_imp - T| / T
    dPL: float
    xi: float
    nfev: int               # one-period integrations done by the root finder
    time: float             # wall time of the root solve (s)


class Shooting:
    """Event-driven one-period map of the two-state system (physical coordinates).

    Parameters
    ----------
    M, K : ndarray (n, n)
        Free-DOF mass and stiffness, contact DOF last.
    q : ndarray (n,)
        Load amplitude, ``q(t) = q cos(2 pi t / T - phi)``.
    method, rtol, atol : solve_ivp settings (tight by default).
    """

    def __init__(self, M, K, q, method="DOP853", rtol=1e-12, atol=1e-14):
        self.M, self.K, self.q = (np.asarray(a, float) for a in (M, K, q))
        n = self.M.shape[0]
        self.n = n
        self.Mrr, self.Krr = self.M[:-1, :-1], self.K[:-1, :-1]
        self.MinvI = np.linalg.inv(self.Mrr)
        self.MinvII = np.linalg.inv(self.M)
        self.AI = -self.MinvI @ self.Krr
        self.AII = -self.MinvII @ self.K
        self.bI = self.MinvI @ self.q[:-1]
        self.bII = self.MinvII @ self.q
        self.method, self.rtol, self.atol = method, rtol, atol
        # sum_j w_j etadot_j^2 = v^T C v with etadot = V^T M v  (Eq. (21) integrand)
        w1, V1 = sla.eigh(self.Krr, self.Mrr)
        w2, V2 = sla.eigh(self.K, self.M)
        B1 = self.Mrr @ V1
        B2 = self.M @ V2
        self.CI = B1 @ np.diag(np.sqrt(w1)) @ B1.T
        self.CII = B2 @ np.diag(np.sqrt(w2)) @ B2.T

    # right-hand sides: y = (x, v, s) with s the running  int v^T C v dt
    def _rhs_I(self, t, y, W, phi):
        m = self.n - 1
        x, v = y[:m], y[m:2 * m]
        a = self.AI @ x + self.bI * np.cos(W * t - phi)
        return np.concatenate([v, a, [v @ self.CI @ v]])

    def _rhs_II(self, t, y, W, phi):
        m = self.n
        x, v = y[:m], y[m:2 * m]
        a = self.AII @ x + self.bII * np.cos(W * t - phi)
        return np.concatenate([v, a, [v @ self.CII @ v]])

    def reaction_margin(self, t, x_r, W, phi):
        """``-R`` in state I (``>= 0`` in compression), R = (M a + K x - q cos)_c."""
        c = np.cos(W * t - phi)
        a = self.AI @ x_r + self.bI * c
        return -(self.M[-1, :-1] @ a + self.K[-1, :-1] @ x_r - self.q[-1] * c)

    def period(self, x0, v0, phi, T, dense=False):
        """Integrate from the impact (t = 0, state I) through one switch of each kind.

        Returns ``(x_r+, v_r+, T1, t_imp, dPL, psi_sum, ok)`` after the impact.
        """
        W = 2 * np.pi / T
        m = self.n - 1
        kw = dict(method=self.method, rtol=self.rtol, atol=self.atol, dense_output=dense)
        t_guard = 1e-9 * T

        def ev_I(t, y, *args):
            return self.reaction_margin(t, y[:m], W, phi) if t > t_guard else 1.0
        ev_I.terminal, ev_I.direction = True, -1
        y0 = np.concatenate([x0, v0, [0.0]])
        sI = solve_ivp(self._rhs_I, (0.0, 2.0 * T), y0, events=ev_I, args=(W, phi), **kw)
        if sI.status != 1 or not sI.t_events[0].size:
            return None
        T1 = sI.t_events[0][0]
        yI = sI.y_events[0][0]
        # I -> II: embed with x_c = v_c = 0
        x = np.append(yI[:m], 0.0)
        v = np.append(yI[m:2 * m], 0.0)

        def ev_II(t, y, *args, T1=T1):
            return y[m] if t > T1 + t_guard else -1.0   # x_c (contact DOF is last)
        ev_II.terminal, ev_II.direction = True, 1
        sII = solve_ivp(self._rhs_II, (T1, T1 + 2.0 * T), np.concatenate([x, v, [yI[-1]]]), events=ev_II,
                        args=(W, phi), **kw)
        if sII.status != 1 or not sII.t_events[0].size:
            return None
        t_imp = sII.t_events[0][0]
        yE = sII.y_events[0][0]
        xE, vE = yE[:self.n], yE[self.n:2 * self.n]
        # plastic impact: M_rr v_r+ = (M v-)_r
        v_plus = self.MinvI @ (self.M @ vE)[:-1]
        dPL = 0.5 * vE @ self.M @ vE - 0.5 * v_plus @ self.Mrr @ v_plus
        out = (xE[:-1].copy(), v_plus, T1, t_imp, dPL, yE[-1], True)
        if dense:
            return out, sI, sII
        return out

    def residual(self, u, T, xs, vs):
        m = self.n - 1
        x0, v0, phi = u[:m] * xs, u[m:2 * m] * vs, u[-1]
        r = self.period(x0, v0, phi, T)
        if r is None:
            return np.full(2 * m + 1, 1e3)
        x1, v1, T1, t_imp = r[:4]
        return np.concatenate([(x1 - x0) / xs, (v1 - v0) / vs, [(t_imp - T) / T]])

    def solve(self, x0, v0, phi, T, xtol=1e-12) -> ShootingResult:
        """Periodic response at period ``T`` from the guess ``(x0, v0, phi)``.

        Unknowns: ``x_r(0), v_r(0)`` (state I just after the impact) and ``phi``;
        equations: periodicity of ``(x_r, v_r)`` across one period and
        ``t_impact = T``.  The switch conditions ``e1 = e2 = 0`` hold by the
        events.  MINPACK ``hybr`` with a finite-difference Jacobian.
        """
        xs = max(np.abs(x0).max(), 1e-300)
        vs = max(np.abs(v0).max(), 1e-300)
        u0 = np.concatenate([x0 / xs, v0 / vs, [phi]])
        count = [0]

        def fun(u):
            count[0] += 1
            return self.residual(u, T, xs, vs)
        t0 = time.perf_counter()
        sol = root(fun, u0, method="hybr", options=dict(xtol=xtol, eps=1e-10))
        el = time.perf_counter() - t0
        m = self.n - 1
        u = sol.x
        x, v, phi_s = u[:m] * xs, u[m:2 * m] * vs, float(u[-1])
        r = self.period(x, v, phi_s, T)
        if r is None:
            return ShootingResult(False, "no switch found at the solution", x, v, phi_s, T, np.nan, np.nan, np.inf,
                                  np.nan, np.nan, count[0], el)
        x1, v1, T1, t_imp, dPL, psum, _ = r
        res = max(np.abs(np.concatenate([x1 - x, v1 - v])).max() / max(np.abs(np.concatenate([x, v])).max(), 1e-300),
                  abs(t_imp - T) / T)
        xi = dPL / (2 * psum) if psum > 0 else 0.0
        return ShootingResult(bool(sol.success), str(sol.message), x, v, phi_s, T, T1, t_imp, res, dPL, xi,
                              count[0], el)


# ----------------------------------------------------------------------------------------------
# The paper's 3D scan of (T^I, T^II, phi)
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Modal:
    """Modal data of both states (plain SciPy), contact DOF last."""

    M: np.ndarray
    K: np.ndarray
    q: np.ndarray
    w1: np.ndarray
    V1: np.ndarray
    f1: np.ndarray
    w2: np.ndarray
    V2: np.ndarray
    f2: np.ndarray
    P12: np.ndarray
    P21: np.ndarray
    Q21: np.ndarray


def modal(M, K, q) -> Modal:
    M, K, q = (np.asarray(a, float) for a in (M, K, q))
    Mrr, Krr = M[:-1, :-1], K[:-1, :-1]
    l1, V1 = sla.eigh(Krr, Mrr)
    l2, V2 = sla.eigh(K, M)
    return Modal(M, K, q, np.sqrt(l1), V1, V1.T @ q[:-1], np.sqrt(l2), V2, V2.T @ q,
                 V2.T @ M[:, :-1] @ V1, V1.T @ Mrr @ V2[:-1, :], V1.T @ (M @ V2)[:-1, :])


def _particular(w, f, W, t, phi):
    """Particular modal solution (eta_p, etadot_p) = f/(w^2-W^2) (cos, -W sin)(W t - phi).

    Shapes: w, f (n,), W, t (B, 1, 1), phi (1, F, 1) -> (B, F, n) each.
    """
    g = f / (w * w - W * W)
    arg = W * t - phi
    return g * np.cos(arg), -g * W * np.sin(arg)


def _free(w, T, e, v):
    """Free modal flow over T: (B,1,n) rows applied to (B,F,n) states."""
    c, s = np.cos(w * T), np.sin(w * T)
    return c * e + s / w * v, -w * s * e + c * v


@dataclass
class Scan3D:
    t1: np.ndarray
    t2: np.ndarray
    ph: np.ndarray
    points: np.ndarray           # (P, 3) admissible (T1, T2, phi) candidates
    candidates: int               # after the residual filter, before admissibility
    e_rel: np.ndarray            # (P, 2) relative residuals at the kept points
    dPL: np.ndarray               # impact loss at the kept points
    timings: dict
    n_triplets: int


def scan3d(md: Modal, T1_range, T2_range, grid=(200, 200, 50), phi_range=(np.pi, 2 * np.pi),
           share_lu=True, chunk_rows=10, adm_samples=256, adm_tol=1e-2, cell=0.5) -> Scan3D:
    """The paper's 3D scan, vectorised.

    For every ``(T1, T2)`` the transfer matrix ``A`` is built once (it does
    not depend on ``phi``); for every triplet the forced part ``c(phi)`` is
    built from the particular solutions at that ``phi`` and the periodicity
    system ``(Id - A) z0 = c(phi)`` is solved -- with ``share_lu`` one LU per
    ``(T1, T2)`` and ``grid[2]`` right-hand sides (what a careful vectorised
    implementation does), otherwise one batched solve per triplet.  The
    linearity of ``z0`` in ``(cos phi, sin phi)`` is *not* exploited (the paper
    does not), so the work grows with the number of phases.

    Filter: the normalised residuals ``e1/s1, e2/s2`` are kept where each is
    within ``cell`` grid cells of its zero surface by the local linearisation
    ``|e| <= cell * sum_d |de/dd|`` (grid differences), i.e. both surfaces pass
    through the cell, so the candidates trace the 1D solution curves.  Then
    the admissibility (no premature switch, impact towards the wall) is
    checked by sampling the time history at ``adm_samples`` points per state,
    with a tolerance ``adm_tol`` relative to the response amplitude (grid
    points are O(h) off the curves, so the margins there are O(h) too).
    """
    t_start = time.perf_counter()
    n1g, n2g, npg = grid
    t1 = np.linspace(T1_range[0], T1_range[1], n1g + 1)[1:] if T1_range[0] == 0 else \
        np.linspace(*T1_range, n1g)
    t2 = np.linspace(T2_range[0], T2_range[1], n2g + 1)[1:] if T2_range[0] == 0 else \
        np.linspace(*T2_range, n2g)
    ph = np.linspace(phi_range[0], phi_range[1], npg)
    w1, w2, f1, f2 = md.w1, md.w2, md.f1, md.f2
    n1 = w1.size
    P12, P21, Q21 = md.P12, md.P21, md.Q21
    Kc, Mc, qc = md.K[-1, :-1], md.M[-1, :-1], md.q[-1]
    MinvI_K = np.linalg.solve(md.M[:-1, :-1], md.K[:-1, :-1])
    MinvI_q = np.linalg.solve(md.M[:-1, :-1], md.q[:-1])
    gap = md.V2[-1, :]
    E1 = np.empty((n1g, n2g, npg))
    E2 = np.empty((n1g, n2g, npg))
    t_solve = 0.0
    for i0 in range(0, n1g, chunk_rows):
        T1 = np.repeat(t1[i0:i0 + chunk_rows], n2g)
        T2 = np.tile(t2, min(chunk_rows, n1g - i0))
        B = T1.size
        T = T1 + T2
        W = (2 * np.pi / T)[:, None, None]
        T1b, Tb = T1[:, None, None], T[:, None, None]
        phb = ph[None, :, None]
        # transfer matrix A (phi independent): S21 Phi2(T2) S12 Phi1(T1)
        c1, s1 = np.cos(w1 * T1[:, None]), np.sin(w1 * T1[:, None])
        c2, s2 = np.cos(w2 * T2[:, None]), np.sin(w2 * T2[:, None])
        Phi1 = np.zeros((B, 2 * n1, 2 * n1))
        d = np.arange(n1)
        Phi1[:, d, d] = c1
        Phi1[:, d, n1 + d] = s1 / w1
        Phi1[:, n1 + d, d] = -w1 * s1
        Phi1[:, n1 + d, n1 + d] = c1
        n2 = n1 + 1
        e2d = np.arange(n2)
        Phi2 = np.zeros((B, 2 * n2, 2 * n2))
        Phi2[:, e2d, e2d] = c2
        Phi2[:, e2d, n2 + e2d] = s2 / w2
        Phi2[:, n2 + e2d, e2d] = -w2 * s2
        Phi2[:, n2 + e2d, n2 + e2d] = c2
        S12 = sla.block_diag(P12, P12)
        S21 = sla.block_diag(P21, Q21)
        A = S21 @ Phi2 @ S12 @ Phi1
        IA = np.eye(2 * n1) - A
        # forced part c(phi) for every phase: z(T) = A z0 + c
        pe0, pv0 = _particular(w1, f1, W, 0.0, phb)
        peI, pvI = _particular(w1, f1, W, T1b, phb)
        e, v = _free(w1[None, None], T1b, -pe0, -pv0)
        e, v = e + peI, v + pvI                                  # state I forced end, from rest
        es, vs = e @ P12.T, v @ P12.T                             # I -> II
        qe, qv = _particular(w2, f2, W, T1b, phb)
        qeT, qvT = _particular(w2, f2, W, Tb, phb)
        e, v = _free(w2[None, None], T2[:, None, None], es - qe, vs - qv)
        e, v = e + qeT, v + qvT
        C = np.concatenate([e @ P21.T, v @ Q21.T], axis=2)       # (B, F, 2 n1)
        ts = time.perf_counter()
        if share_lu:
            Z = np.linalg.solve(IA, np.swapaxes(C, 1, 2))         # (B, 2n1, F)
            Z = np.swapaxes(Z, 1, 2)
        else:
            Z = np.linalg.solve(np.broadcast_to(IA[:, None], (B, npg, 2 * n1, 2 * n1)), C[..., None])[..., 0]
        t_solve += time.perf_counter() - ts
        e0, v0 = Z[..., :n1], Z[..., n1:]
        # state I at T1^-: reaction residual e1 = -R
        e, v = _free(w1[None, None], T1b, e0 - pe0, v0 - pv0)
        eI, vI = e + peI, v + pvI
        xr = eI @ md.V1.T
        cf = np.cos(W * T1b - phb)[..., 0]
        a = -(xr @ MinvI_K.T) + MinvI_q * cf[..., None]
        R = xr @ Kc + a @ Mc - qc * cf
        s_1 = np.abs(Kc).sum() * np.abs(xr).max(-1) + np.abs(Mc).sum() * np.abs(a).max(-1) + abs(qc) * np.abs(cf)
        # state II at T^-: gap residual e2 = x_c
        e, v = _free(w2[None, None], T2[:, None, None], eI @ P12.T - qe, vI @ P12.T - qv)
        eE = e + qeT
        xc = eE @ gap
        s_2 = np.abs(eE @ md.V2.T).max(-1)
        E1[i0:i0 + chunk_rows] = (-R / s_1).reshape(-1, n2g, npg)
        E2[i0:i0 + chunk_rows] = (xc / s_2).reshape(-1, n2g, npg)
    t_res = time.perf_counter() - t_start
    # filter: both zero surfaces within `cell` cells (local linearisation on the grid)
    keep = np.ones(E1.shape, bool)
    for E in (E1, E2):
        g = np.gradient(E)
        slope = np.abs(g[0]) + np.abs(g[1]) + np.abs(g[2])
        keep &= np.isfinite(E) & (np.abs(E) <= cell * slope)
    I, J, K = np.nonzero(keep)
    cand = np.c_[t1[I], t2[J], ph[K]]
    t_filter = time.perf_counter() - t_start - t_res
    ok, dPL = _admissible(md, cand, adm_samples, adm_tol)
    t_adm = time.perf_counter() - t_start - t_res - t_filter
    pts = cand[ok]
    erel = np.c_[E1[I, J, K], E2[I, J, K]][ok]
    tm = dict(residuals=t_res, linear_solves=t_solve, filter=t_filter, admissibility=t_adm,
              total=time.perf_counter() - t_start)
    return Scan3D(t1, t2, ph, pts, int(cand.shape[0]), erel, dPL[ok], tm, n1g * n2g * npg)


def _periodic_state(md: Modal, P):
    """Periodic initial modal state ``z0`` at triplets ``P`` (C, 3): one solve per triplet."""
    w1, w2, f1, f2 = md.w1, md.w2, md.f1, md.f2
    n1 = w1.size
    T1, T2, phi = P[:, 0], P[:, 1], P[:, 2]
    T = T1 + T2
    W = (2 * np.pi / T)[:, None, None]
    phb = phi[:, None, None]
    S12 = sla.block_diag(md.P12, md.P12)
    S21 = sla.block_diag(md.P21, md.Q21)

    def phi_mat(w, T):
        n = w.size
        c, s = np.cos(w * T[:, None]), np.sin(w * T[:, None])
        F = np.zeros((T.size, 2 * n, 2 * n))
        d = np.arange(n)
        F[:, d, d], F[:, d, n + d], F[:, n + d, d], F[:, n + d, n + d] = c, s / w, -w * s, c
        return F
    A = S21 @ phi_mat(w2, T2) @ S12 @ phi_mat(w1, T1)
    T1b, Tb = T1[:, None, None], T[:, None, None]
    pe0, pv0 = _particular(w1, f1, W, 0.0, phb)
    peI, pvI = _particular(w1, f1, W, T1b, phb)
    e, v = _free(w1[None, None], T1b, -pe0, -pv0)
    e, v = e + peI, v + pvI
    qe, qv = _particular(w2, f2, W, T1b, phb)
    qeT, qvT = _particular(w2, f2, W, Tb, phb)
    e, v = _free(w2[None, None], T2[:, None, None], e @ md.P12.T - qe, v @ md.P12.T - qv)
    C = np.concatenate([(e + qeT) @ md.P21.T, (v + qvT) @ md.Q21.T], axis=2)[:, 0]
    return np.linalg.solve(np.eye(2 * n1) - A, C[..., None])[..., 0]


def _sample(md: Modal, P, Z, K):
    """Time history of the margins at ``K`` samples per state: ``-R`` on [0, T1], ``x_c, v_c`` on [T1, T]."""
    w1, w2, f1, f2 = md.w1, md.w2, md.f1, md.f2
    n1 = w1.size
    T1, T2, phi = P[:, 0], P[:, 1], P[:, 2]
    W = (2 * np.pi / (T1 + T2))[:, None, None]
    phb = phi[:, None, None]
    T1b = T1[:, None, None]
    u = np.linspace(0.0, 1.0, K)[None, :, None]
    e0, v0 = Z[:, None, :n1], Z[:, None, n1:]
    tau = T1b * u
    p0e, p0v = _particular(w1, f1, W, 0.0, phb)
    pe, pv = _particular(w1, f1, W, tau, phb)
    c, s = np.cos(w1 * tau), np.sin(w1 * tau)
    eI = c * (e0 - p0e) + s / w1 * (v0 - p0v) + pe
    xr = eI @ md.V1.T
    cf = np.cos(W * tau - phb)[..., 0]
    MiK = np.linalg.solve(md.M[:-1, :-1], md.K[:-1, :-1])
    Miq = np.linalg.solve(md.M[:-1, :-1], md.q[:-1])
    a = -(xr @ MiK.T) + Miq * cf[..., None]
    mR = -(xr @ md.K[-1, :-1] + a @ md.M[-1, :-1] - md.q[-1] * cf)          # -R >= 0
    eEnd = eI[:, -1:]
    vEnd = -w1 * s[:, -1:] * (e0 - p0e) + c[:, -1:] * (v0 - p0v) + pv[:, -1:]
    es, vs = eEnd @ md.P12.T, vEnd @ md.P12.T
    qe, qv = _particular(w2, f2, W, T1b, phb)
    tau2 = T2[:, None, None] * u
    pe2, pv2 = _particular(w2, f2, W, T1b + tau2, phb)
    c2, s2 = np.cos(w2 * tau2), np.sin(w2 * tau2)
    eII = c2 * (es - qe) + s2 / w2 * (vs - qv) + pe2
    vII = -w2 * s2 * (es - qe) + c2 * (vs - qv) + pv2
    return mR, eII @ md.V2[-1], vII @ md.V2[-1], vII[:, -1]


def _admissible(md: Modal, P, K=256, tol=1e-2, K0=33, chunk=4096):
    """Time-history sampling admissibility of triplets ``P`` (C, 3) and their impact loss.

    Two passes, as any sensible implementation would do: ``K0`` samples per
    state reject the gross violations, ``K`` samples check the survivors.
    """
    C = P.shape[0]
    ok = np.zeros(C, bool)
    dPL = np.zeros(C)
    for i in range(0, C, chunk):
        Pc = P[i:i + chunk]
        Z = _periodic_state(md, Pc)
        live = np.arange(Pc.shape[0])
        for k, t in ((K0, 5 * tol), (K, tol)):
            mR, xc, vc, vE = _sample(md, Pc[live], Z[live], k)
            good = (mR.min(1) >= -t * np.abs(mR).max(1)) & ((-xc).min(1) >= -t * np.abs(xc).max(1)) \
                & (vc[:, -1] > tol * np.abs(vc).max(1))
            live = live[good]
            if live.size == 0:
                break
        if live.size:
            vplus = vE[good] @ md.Q21.T
            dPL[i + live] = 0.5 * (vE[good] ** 2).sum(1) - 0.5 * (vplus ** 2).sum(1)
            ok[i + live] = True
    return ok, dPL


def branch_coverage(branches, pts, h, phi_range=(np.pi, 2 * np.pi), near=1.5):
    """Compare a 3D-scan point cloud with plbar's branches.

    Coordinates are scaled by the grid steps ``h = (h1, h2, hphi)`` (cells).
    Returns per branch (only branches whose phase lies in ``phi_range``): the
    number of plbar points, of cloud points whose nearest branch is this one
    (within ``near`` cells), the coverage (fraction of the branch polyline,
    densified 10x, with a cloud point within ``near`` cells), the median
    distance of those cloud points to the branch (cells), and the number of
    cloud points not near any branch.
    """
    from scipy.spatial import cKDTree

    h = np.asarray(h, float)
    rows, dens, owner = [], [], []
    for b in branches:
        ph = np.mod(b.phi, 2 * np.pi)
        if not np.all((ph >= phi_range[0] - 1e-9) & (ph <= phi_range[1] + 1e-9)):
            continue
        P = np.c_[b.T1, b.T2, ph] / h
        if len(P) > 1:
            s = np.linspace(0, 1, 11)[:-1]
            D = np.concatenate([(P[:-1, None] + s[None, :, None] * (P[1:, None] - P[:-1, None])).reshape(-1, 3),
                                P[-1:]])
        else:
            D = P
        dens.append(D)
        owner.append(np.full(len(D), len(rows)))
        rows.append(dict(branch=int(b.id), plbar_points=len(b), T=[float(b.T.min()), float(b.T.max())]))
    if not rows:
        return rows, int(len(pts))
    Dall = np.concatenate(dens)
    own = np.concatenate(owner)
    Q = pts / h
    tree = cKDTree(Dall)
    dist, idx = tree.query(Q) if len(Q) else (np.zeros(0), np.zeros(0, int))
    cloud_tree = cKDTree(Q) if len(Q) else None
    for k, r in enumerate(rows):
        mine = (own[idx] == k) & (dist <= near) if len(Q) else np.zeros(0, bool)
        r["scan_points"] = int(mine.sum())
        r["median_dist_cells"] = float(np.median(dist[mine])) if mine.any() else None
        if cloud_tree is not None:
            dd, _ = cloud_tree.query(dens[k])
            r["coverage"] = float(np.mean(dd <= near))
        else:
            r["coverage"] = 0.0
    stray = int(np.sum(dist > near)) if len(Q) else 0
    return rows, stray
