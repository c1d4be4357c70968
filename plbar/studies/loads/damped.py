"""Load studies with Rayleigh damping (issue 21): the load structure through the complex contact response.

With ``C = alpha M + beta K`` the state II receptance is complex, ``H = (K - W^2 M + i W C)^-1``,
and so is the contact response ``h(q) = (H q)_c``.  Split the motion as ``x = x_p + y`` with the
steady state ``x_p = Re(H q e^{i(W t - phi)})`` of the free bar: ``y`` obeys the unforced equations
with the reaction as its only force, the contact constraint ``y_c = -x_p,c`` in state I, the gap
``x_p,c + y_c`` and the same impact law, so it depends on the load only through
``x_p,c = |h| cos(W t - phi + arg h)`` (``docs/load_structure.md`` §9).  Hence, for every load with
``h(q) != 0``:

* the paths in ``(T^I, T^II)`` are those of the reference load (and so are admissibility and
  stability), at the phase ``phi(q) = phi_ref + arg(h(q) / h(q_ref))`` (not just mod ``pi``);
* ``Delta_PL(q) = |h(q) / h(q_ref)|^2 Delta_PL(q_ref)`` (rank two: ``Re h`` and ``Im h``);
* per unit ``rho = |h(q) / h(q_ref)|`` the velocities are ``x'_ref + Re(i W U e^{i(W t - phi_ref)})``
  with ``U = (h_ref / h(q)) H q - H q_ref`` (``U_c = 0``), so ``xi_eq(q) = Delta_PL(q_ref) / (2 c^T Gamma c)``
  with ``c = (Re U_r, Im U_r, 1)`` and the Gram matrix ``Gamma`` of the velocity histories.

``xi_eq`` is no longer a ratio of quadratic forms in ``q`` (``U`` depends on ``q / h(q)``), but for
loads ``q = s`` with ``p = e^{i theta} s`` it is: at fixed ``theta`` the worst load is an equality
constrained least-squares problem, and :meth:`DampedLoadForms.worst` scans ``theta`` in ``[0, pi)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...response import Orbits
from ...response.flow import gauss
from ...util.blas import single_thread_blas
from .extremes import ElementMax, PointLoads, Worst

__all__ = ["DampedLoadForms", "damped_forms", "THETA_GRID"]

HZERO_TOL = 1e-10         #: as :data:`plbar.studies.loads.forms.HZERO_TOL`
THETA_GRID = 72          #: phase angles of the worst-load scan over [0, pi) (then golden-section refinement)
QUAD_ELEMENTS = 4e6      #: largest (points x nodes x modes) array of one quadrature chunk


def _sigmas(W, phi, t0, t1):
    """``int W^2 sin^2``, ``int W^2 sin cos``, ``int W^2 cos^2`` of ``theta = W t - phi`` over ``[t0, t1]``."""
    a0, a1 = W * t0 - phi, W * t1 - phi
    half = 0.5 * (t1 - t0)
    s2 = (np.sin(2 * a1) - np.sin(2 * a0)) / (4 * W)
    return W ** 2 * (half - s2), W ** 2 * (np.cos(2 * a0) - np.cos(2 * a1)) / (4 * W), W ** 2 * (half + s2)


def _moments(orb: Orbits, state: int) -> np.ndarray:
    """``w_j int_alpha e^{i theta} etadot_ref,j dt`` per mode (P, m): composite Gauss-Legendre on the exact flow."""
    s = orb.prob.system
    w, z = (s.w1, s.zeta1) if state == 1 else (s.w2, s.zeta2)
    t0, span = (np.zeros_like(orb.T1), orb.T1) if state == 1 else (orb.T1, orb.T2)
    rate = float(np.max(np.where(z > 1, z * w + w * np.sqrt(np.maximum(z * z - 1, 0)), w)))
    k = (rate + orb.W.max()) * float(span.max())
    pieces = max(1, int(np.ceil(k / 100)))
    nq = 20 * int(np.ceil((0.6 * k / pieces + 60) / 20))
    x, wt = gauss(nq)
    u = ((np.arange(pieces)[:, None] + 0.5 * (x + 1)) / pieces).ravel()
    wts = np.tile(wt, pieces) / (2 * pieces)
    out = np.empty((len(orb), w.size), complex)
    step = max(1, int(QUAD_ELEMENTS // (u.size * w.size)))
    for a in range(0, len(orb), step):
        o = orb.take(slice(a, a + step))
        tau = span[a:a + step, None] * u
        _, v = o.state_I(tau) if state == 1 else o.state_II(tau)
        e = np.exp(1j * (o.W[:, None] * (t0[a:a + step, None] + tau) - o.phi[:, None]))
        out[a:a + step] = span[a:a + step, None] * np.einsum("pk,pkj->pj", wts * e, v)
    return out * w


def _gram(orb: Orbits, denom: np.ndarray) -> np.ndarray:
    """``Gamma`` (P, 2n-1, 2n-1) in the coordinates ``c = (Re u_r, Im u_r, 1)`` (module docstring)."""
    s = orb.prob.system
    A1 = s.V1.T @ s.M[:-1, :-1]
    A2 = s.V2.T @ s.M[:, :-1]
    S1, S2 = A1.T @ (s.w1[:, None] * A1), A2.T @ (s.w2[:, None] * A2)
    W, phi = orb.W, orb.phi
    sig1, sig2 = _sigmas(W, phi, 0.0, orb.T1), _sigmas(W, phi, orb.T1, orb.T)
    # the u-part's modal velocity is A (Re u s1 + Im u s2), s1 = -W sin(theta), s2 = -W cos(theta)
    m = -W[:, None] * (_moments(orb, 1) @ A1 + _moments(orb, 2) @ A2)      # int e^{i theta} ... -> -W (cos + i sin)
    g1, g2 = m.imag, m.real                                                 # with s1 and with s2
    r = s.n - 1
    Gam = np.empty((len(orb), 2 * r + 1, 2 * r + 1))
    for (i, j), k in (((0, 0), 0), ((0, 1), 1), ((1, 1), 2)):
        blk = sig1[k][:, None, None] * S1 + sig2[k][:, None, None] * S2
        Gam[:, i * r:(i + 1) * r, j * r:(j + 1) * r] = blk
        Gam[:, j * r:(j + 1) * r, i * r:(i + 1) * r] = np.swapaxes(blk, 1, 2)
    Gam[:, :r, -1] = Gam[:, -1, :r] = g1
    Gam[:, r:2 * r, -1] = Gam[:, -1, r:2 * r] = g2
    Gam[:, -1, -1] = denom
    return Gam


@dataclass(frozen=True, eq=False)
class DampedLoadForms(PointLoads):
    """Exact ``Delta_PL(q)`` and ``xi_eq(q)`` of any load at every path point of a damped bar.

    The same interface as :class:`plbar.studies.loads.forms.LoadForms` (``dPL, denom, xi, h,
    h_relative, no_path, point_vectors, point_loads, xi_point, element_max, worst, take``).

    Attributes
    ----------
    T1, T2, phi, branch, point : ndarray, shape (P,)
        The path points (``phi`` of the reference load; a load ``q`` has ``phi + arg(h(q) / h_ref)``).
    H : ndarray of complex, shape (P, n, n)
        ``(K - W^2 M + i W C)^-1``.
    Gamma : ndarray, shape (P, 2n - 1, 2n - 1)
        Gram matrix of the velocity histories in ``c = (Re U_r, Im U_r, 1)``.
    dPL_ref : ndarray, shape (P,)
    h_ref : ndarray of complex, shape (P,)
    q_ref, x : ndarray, shape (n,)
    """

    T1: np.ndarray
    T2: np.ndarray
    phi: np.ndarray
    branch: np.ndarray
    point: np.ndarray
    H: np.ndarray
    Gamma: np.ndarray
    dPL_ref: np.ndarray
    h_ref: np.ndarray
    q_ref: np.ndarray
    x: np.ndarray
    asm: object = None

    @property
    def T(self):
        return self.T1 + self.T2

    @property
    def n(self) -> int:
        return self.x.size

    def __len__(self) -> int:
        return self.T1.size

    def __repr__(self) -> str:
        return f"DampedLoadForms({len(self)} path points, n = {self.n})"

    def _split(self, q):
        """``h(q)`` (P, L) and the coordinates ``c`` (P, L, 2n - 1) of loads ``q`` (L, n)."""
        Q = np.atleast_2d(np.asarray(q, float))
        if Q.ndim != 2 or Q.shape[1] != self.n or not np.all(np.isfinite(Q)):
            raise InputError(f"load vectors must be finite, of shape (n,) or (L, n) with n = {self.n}; got "
                             f"{np.shape(q)}")
        HQ = np.einsum("pij,lj->pli", self.H, Q)
        hq = HQ[..., -1]
        ok = hq != 0
        kappa = np.where(ok, self.h_ref[:, None] / np.where(ok, hq, 1.0), 0.0)
        U = kappa[..., None] * HQ[..., :-1] - (self.H[:, :-1, :] @ self.q_ref)[:, None, :]
        c = np.concatenate([U.real, U.imag, np.ones(U.shape[:2] + (1,))], axis=-1)
        return hq, c, ok, np.ndim(q) == 1

    def _quad(self, c):
        return np.einsum("pli,pij,plj->pl", c, self.Gamma, c, optimize=True)

    def dPL(self, q):
        """``Delta_PL(q) = |h(q) / h_ref|^2 Delta_PL(q_ref)``; q (n,) -> (P,), (L, n) -> (P, L)."""
        hq, _, _, one = self._split(q)
        d = np.abs(hq / self.h_ref[:, None]) ** 2 * self.dPL_ref[:, None]
        return d[:, 0] if one else d

    def denom(self, q):
        """The bracket of Eq. (22) for load ``q``: ``|h(q) / h_ref|^2 c^T Gamma c``."""
        hq, c, _, one = self._split(q)
        d = np.abs(hq / self.h_ref[:, None]) ** 2 * self._quad(c)
        return d[:, 0] if one else d

    def xi(self, q):
        """``xi_eq(q) = Delta_PL(q_ref) / (2 c^T Gamma c)`` (Eq. (22)); 0 where ``h(q) = 0``."""
        _, c, ok, one = self._split(q)
        den = self._quad(c)
        num = np.broadcast_to(self.dPL_ref[:, None], den.shape)
        x = np.divide(num, 2 * den, out=np.zeros_like(den), where=ok & (den > 0))
        return x[:, 0] if one else x

    def h(self, q):
        """Complex contact response ``h(q) = (H q)_c``; q (n,) -> (P,), (L, n) -> (P, L)."""
        hq, _, _, one = self._split(q)
        return hq[:, 0] if one else hq

    def phase(self, q):
        """The forcing phase of load ``q`` at every path point: ``phi_ref + arg(h(q) / h_ref)`` in ``[0, 2 pi)``."""
        hq = self.h(q)
        ref = self.h_ref if np.ndim(hq) == 1 else self.h_ref[:, None]
        p = self.phi if np.ndim(hq) == 1 else self.phi[:, None]
        return np.mod(p + np.angle(hq / ref), 2 * np.pi)

    def h_relative(self, q):
        """``|h(q)| / (|H e_c| |q|)`` in ``[0, 1]``: 0 means no periodic path at that point."""
        Q = np.atleast_2d(np.asarray(q, float))
        Hc = self.H[:, -1, :]                                  # row c of the (symmetric) receptance
        nq = np.linalg.norm(Q, axis=1)
        r = np.abs(Hc @ Q.T) / (np.linalg.norm(Hc, axis=1)[:, None] * np.where(nq > 0, nq, 1.0))
        return r[:, 0] if np.ndim(q) == 1 else r

    def no_path(self, q, tol: float = HZERO_TOL):
        """True where ``h(q) = 0`` (relative ``tol``): the load has no periodic response there."""
        return self.h_relative(q) < tol

    # -- point forces ------------------------------------------------------------------------------
    def point_loads(self, s):
        """``xi_eq`` and ``Delta_PL`` of unit point forces at ``s`` (S,): each (P, S)."""
        Q = self.point_vectors(np.atleast_1d(np.asarray(s, float)))
        return self.xi(Q), self.dPL(Q)

    def xi_point(self, s):
        """``xi_eq`` of unit point forces at positions ``s`` (S,): shape (P, S)."""
        return self.point_loads(s)[0]

    def element_max(self, samples: int = 33, rounds: int = 40) -> ElementMax:
        """Largest ``xi_eq`` of a unit point force over each element: sampled, then golden-section refined.

        With damping ``xi_eq(s)`` is not a ratio of polynomials in ``s``; ``samples`` points per
        element locate the best one, ``rounds`` golden-section steps refine it to ``0.618^rounds``
        of the sample spacing.  A force at the clamp (``t = 0`` of the first element) is taken at
        ``t = 1e-9`` (the limit: ``xi_eq`` depends on the load's direction only).
        """
        el = self._elems()
        E = el.left.size
        t = np.linspace(1e-9, 1.0, samples)
        xi = np.stack([self._element_xi(np.full(E, tk)) for tk in t], axis=-1)          # (P, E, K)
        j = np.argmax(xi, axis=-1)
        h = t[1] - t[0]
        lo, hi = np.clip(t[j] - h, 1e-9, 1.0), np.clip(t[j] + h, 1e-9, 1.0)
        g = 0.5 * (np.sqrt(5.0) - 1.0)
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        fa, fb = self._element_xi(a), self._element_xi(b)
        for _ in range(rounds):
            left = fa >= fb
            hi, lo = np.where(left, b, hi), np.where(left, lo, a)
            a, b = np.where(left, hi - g * (hi - lo), b), np.where(left, a, lo + g * (hi - lo))
            new = self._element_xi(np.where(left, a, b))
            fb, fa = np.where(left, fa, new), np.where(left, new, fb)
        tb = np.where(fa >= fb, a, b)
        best = np.maximum(np.maximum(fa, fb), np.take_along_axis(xi, j[..., None], -1)[..., 0])
        tm = np.where(np.maximum(fa, fb) >= best, tb, t[j])
        return ElementMax(best, el.left + tm * (el.right - el.left), el.left, el.right)

    def _element_xi(self, t):
        """``xi_eq`` of a unit force at local coordinate ``t`` of every element: t (E,) or (P, E) -> (P, E)."""
        el = self._elems()
        P, E = len(self), el.left.size
        t = np.broadcast_to(t, (P, E))
        pw = t[..., None] ** np.arange(el.C.shape[-1])                           # (P, E, d+1)
        N = np.einsum("ekd,ped->pek", el.C, pw)                                  # (P, E, k)
        Hp = np.concatenate([self.H, np.zeros((P, self.n, 1))], axis=2)         # dummy clamped DOF n
        HQ = np.einsum("piek,pek->pei", Hp[:, :, el.dofs], N)                   # (P, E, n)
        hq = HQ[..., -1]
        ok = hq != 0
        kappa = np.where(ok, self.h_ref[:, None] / np.where(ok, hq, 1.0), 0.0)
        U = kappa[..., None] * HQ[..., :-1] - (self.H[:, :-1, :] @ self.q_ref)[:, None, :]
        c = np.concatenate([U.real, U.imag, np.ones(U.shape[:2] + (1,))], axis=-1)
        den = self._quad(c)
        return np.divide(np.broadcast_to(self.dPL_ref[:, None], den.shape), 2 * den, out=np.zeros_like(den),
                         where=ok & (den > 0))

    # -- the worst load ----------------------------------------------------------------------------
    def _theta_min(self, theta):
        """Smallest ``c^T Gamma c`` over real ``s`` with ``p = e^{i theta} s``, ``h(p) = h_ref``; (value, s) per
        point."""
        P, n = len(self), self.n
        e = np.exp(1j * np.asarray(theta, float))[:, None, None]
        Hr = e * self.H[:, :-1, :]                                   # (P, n-1, n): U_r = Hr s - H_r q_ref
        L = np.concatenate([Hr.real, Hr.imag, np.zeros((P, 1, n))], axis=1)
        u0 = self.H[:, :-1, :] @ self.q_ref
        c0 = np.concatenate([-u0.real, -u0.imag, np.ones((P, 1))], axis=1)
        hc = e[:, 0] * self.H[:, -1, :]                              # the contact row: h(p) = hc . s
        A = np.stack([hc.real, hc.imag], axis=1)                     # (P, 2, n)
        GL = self.Gamma @ L
        K = np.zeros((P, n + 2, n + 2))
        K[:, :n, :n] = 2 * np.swapaxes(L, 1, 2) @ GL
        K[:, :n, n:] = np.swapaxes(A, 1, 2)
        K[:, n:, :n] = A
        rhs = np.concatenate([-2 * np.einsum("pji,pj->pi", GL, c0),
                              np.stack([self.h_ref.real, self.h_ref.imag], axis=1)], axis=1)
        try:
            sol = np.linalg.solve(K, rhs[..., None])[..., 0]
        except np.linalg.LinAlgError:
            sol = np.stack([np.linalg.lstsq(K[i], rhs[i], rcond=None)[0] for i in range(P)])
        sv = sol[:, :n]
        c = np.einsum("pij,pj->pi", L, sv) + c0
        return np.einsum("pi,pij,pj->p", c, self.Gamma, c), sv

    def worst(self, grid: int = THETA_GRID, rounds: int = 50) -> Worst:
        """Largest ``xi_eq`` over every in-phase load distribution, and the load.

        For each phase angle ``theta`` of ``p = (h_ref / h(q)) q = |.| e^{i theta} q`` the smallest
        ``c^T Gamma c`` is an equality-constrained least-squares problem (exact); ``theta`` is
        scanned on ``grid`` points of ``[0, pi)`` and the best refined by ``rounds`` golden-section
        steps.  ``q*`` has unit norm and ``Re(h(q*) conj(h_ref)) >= 0``.
        """
        with single_thread_blas:
            th = np.pi * np.arange(grid) / grid
            vals = np.stack([self._theta_min(np.full(len(self), t))[0] for t in th], axis=1)
            j = np.argmin(vals, axis=1)
            h = np.pi / grid
            lo, hi = th[j] - h, th[j] + h
            g = 0.5 * (np.sqrt(5.0) - 1.0)
            a, b = hi - g * (hi - lo), lo + g * (hi - lo)
            fa, fb = self._theta_min(a)[0], self._theta_min(b)[0]
            for _ in range(rounds):
                left = fa <= fb
                hi, lo = np.where(left, b, hi), np.where(left, lo, a)
                a, b = np.where(left, hi - g * (hi - lo), b), np.where(left, a, lo + g * (hi - lo))
                new = self._theta_min(np.where(left, a, b))[0]
                fb, fa = np.where(left, fa, new), np.where(left, new, fb)
            tb = np.where(fa <= fb, a, b)
            val, q = self._theta_min(tb)
        xi = self.dPL_ref / (2 * val)
        q = q / np.linalg.norm(q, axis=1, keepdims=True)
        hq = np.einsum("pi,pi->p", self.H[:, -1, :], q)
        sign = np.where((hq * np.conj(self.h_ref)).real < 0, -1.0, 1.0)
        return Worst(xi, q * sign[:, None], np.full(len(self), self.n), np.zeros(len(self)))

    def take(self, idx) -> "DampedLoadForms":
        """A subset of the path points."""
        f = {k: getattr(self, k) for k in self.__dataclass_fields__}
        for k in ("T1", "T2", "phi", "branch", "point", "H", "Gamma", "dPL_ref", "h_ref"):
            f[k] = f[k][idx]
        return DampedLoadForms(**f)


def damped_forms(orb: Orbits, branch, point, dPL, denom) -> DampedLoadForms:
    """:class:`DampedLoadForms` at the path points ``orb`` of a damped bar (``dPL``, ``denom``: the solver's)."""
    s, prob = orb.prob.system, orb.prob
    W = orb.W[:, None, None]
    Z = s.K[None] - W ** 2 * s.M[None] + 1j * W * s.C[None]
    with single_thread_blas:
        H = np.linalg.inv(Z)
    h_ref = H[:, -1, :] @ prob.q
    Gam = _gram(orb, denom)
    return DampedLoadForms(orb.T1.copy(), orb.T2.copy(), orb.phi.copy(), branch, point, H, Gam, np.asarray(dPL),
                           h_ref, np.asarray(prob.q, float).copy(), s.x.copy(), prob.asm)
