"""Load studies on the exact structure of the problem (issue #12, ``docs/load_structure.md``).

For a bar with one unilateral DOF ``c`` every switch and impact condition
involves the load vector ``q`` only through the scalar ``h(q) = (H q)_c``,
``H = (K - W^2 M)^-1``.  Hence, at a path point ``(T^I, T^II, phi)`` found for
a reference load ``q_ref`` (``h(q_ref) != 0``):

* every load has its periodic response there (``phi`` or ``phi + pi``);
* the response is linear in ``q``: with ``Z = K - W^2 M`` every ``q`` is
  ``q = alpha q_ref + Z u`` with ``u_c = 0`` (``alpha = h(q) / h(q_ref)``), and
  ``x(t; q) = alpha x(t; q_ref) + u cos(W t - phi)``;
* ``Delta_PL(q) = (b . q)^2`` (rank one, through ``v_c(T-)``, Eq. (14)) and the
  denominator of Eq. (22) is ``q^T G q``: ``xi_eq(q) = (b . q)^2 / (2 q^T G q)``;
* the largest ``xi_eq`` over all loads is ``b^T G^+ b / 2`` at ``q* = G^+ b``.

Everything is built from the reference orbits (no path solve per load):
the Gram matrix ``Gamma`` of the velocity histories in the coordinates
``c = (u_r, alpha)`` (basis ``B = [Z e_1, ..., Z e_{n-1}, q_ref]``) needs

* ``Gamma_aa = denom(q_ref)`` (Eqs. (20)-(22), closed form of the solver),
* ``Gamma_ra = sum_alpha A_alpha^T Omega_alpha m_alpha`` with
  ``m_alpha = int s(t) etadot_ref(t) dt``, ``s = -W sin(W t - phi)``, by
  polarisation of the solver's own ``Psi`` (Eq. (20): closed form, quadrature
  near resonance); checked against Gauss-Legendre on the exact modal
  velocities to ~1e-13,
* ``Gamma_rr = sigma_I A_I^T Omega_I A_I + sigma_II A_II^T Omega_II A_II``,
  ``sigma_alpha = int_alpha s^2 dt`` in closed form,

with ``A_I = V1^T M_rr`` and ``A_II = (V2^T M)_{:, r}`` (modal velocities of
``u``).  Then ``G = B^-T Gamma B^-1`` and ``b = sqrt(Delta_PL(q_ref)) B^-T e_a``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...response import Forcing, Modes, Orbits, damping
from ...response.flow import gauss, psi
from ...util.blas import single_thread_blas
from .damped import DampedLoadForms, damped_forms
from .extremes import RCOND, ElementMax, PointLoads, Worst, element_max, worst

__all__ = ["LoadForms", "DampedLoadForms", "Worst", "ElementMax", "load_forms", "HZERO_TOL", "RCOND"]

HZERO_TOL = 1e-10   #: |h(q)| / (|H e_c| |q|) below which a load has no path at that point
QUAD_ELEMENTS = 4e6  #: largest (points x nodes x modes) array of one quadrature chunk


def _sigma(W, phi, t0, t1):
    """``int_{t0}^{t1} W^2 sin^2(W t - phi) dt`` in closed form."""
    a0, a1 = W * t0 - phi, W * t1 - phi
    return W ** 2 * (0.5 * (t1 - t0) - (np.sin(2 * a1) - np.sin(2 * a0)) / (4 * W))


def _state_args(orb: Orbits, state: int):
    s, p = orb.prob.system, orb.prob
    if state == 1:
        return s.w1, p.f1, np.zeros_like(orb.T1), orb.T1, orb.eta0, orb.v0
    return s.w2, p.f2, orb.T1, orb.T2, orb.eta_s, orb.v_s


def _m_vectors(orb: Orbits, state: int) -> np.ndarray:
    """``Omega_alpha int_alpha s(t) etadot_ref(t) dt`` per mode (P, m), by polarisation of Eq. (20).

    ``s(t) = -W sin(W t - phi)`` is the velocity of the mode driven by ``f = w^2 - W^2`` that starts
    on its particular solution (``eta = cos(W t_s - phi)``); the modal velocity is linear in
    ``(f, eta0, v0)``, so ``Psi(ref + e u) - Psi(ref - e u) = 4 e int s etadot_ref``.  ``Psi`` is the
    solver's own closed form (quadrature near resonance, :func:`plbar.flow.psi`); ``e`` balances
    the two parts (``e^2 sigma_j = Psi_j``), so the difference loses no more than round-off of ``Psi``.
    """
    w, f, ts, span, e0, v0 = _state_args(orb, state)
    W = orb.W[:, None]
    ph = orb.phi[:, None]
    c, sn = np.cos(ph), np.sin(ph)
    th = W * ts[:, None] - ph
    fu, eu, vu = w ** 2 - W ** 2, np.cos(th), -W * np.sin(th)
    fc, seg = Forcing(W, c, sn), (ts[:, None], span[:, None])
    p0, _ = psi(Modes(w[None], f[None]), fc, *seg, e0, v0)
    sig = _sigma(W, ph, ts[:, None], ts[:, None] + span[:, None])
    e = np.sqrt(np.divide(p0, sig, out=np.ones_like(p0), where=(sig > 0) & (p0 > 0)))
    pp, _ = psi(Modes(w[None], f[None] + e * fu), fc, *seg, e0 + e * eu, v0 + e * vu)
    pm, _ = psi(Modes(w[None], f[None] - e * fu), fc, *seg, e0 - e * eu, v0 - e * vu)
    return (pp - pm) / (4 * e) * w


def _m_vectors_quadrature(orb: Orbits, state: int) -> np.ndarray:
    """:func:`_m_vectors` by Gauss-Legendre on the exact modal velocities (an independent check)."""
    w, _, t0, span, _, _ = _state_args(orb, state)
    k = (w.max() + orb.W.max()) * float(span.max())
    nq = 20 * int(np.ceil((0.6 * k + 60) / 20))
    x, wt = gauss(nq)
    out = np.empty((len(orb), w.size))
    step = max(1, int(QUAD_ELEMENTS // (nq * w.size)))
    for a in range(0, len(orb), step):
        o = orb.take(slice(a, a + step))
        sp, W, t_s = span[a:a + step, None], o.W[:, None], t0[a:a + step, None]
        tau = 0.5 * sp * (x + 1)
        _, v = o.state_I(tau) if state == 1 else o.state_II(tau)
        sfun = -W * np.sin(W * (t_s + tau) - o.phi[:, None])
        out[a:a + step] = 0.5 * sp * np.einsum("pk,pkj->pj", wt * sfun, v)
    return out * w


def _gram(orb: Orbits, denom: np.ndarray) -> np.ndarray:
    """``Gamma`` (P, n, n) in the coordinates ``c = (u_r, alpha)`` (module docstring)."""
    s = orb.prob.system
    A1 = s.V1.T @ s.M[:-1, :-1]                 # (m1, n-1): state I modal velocity of u per -W sin
    A2 = s.V2.T @ s.M[:, :-1]                   # (m2, n-1)
    S1 = A1.T @ (s.w1[:, None] * A1)
    S2 = A2.T @ (s.w2[:, None] * A2)
    W, phi = orb.W, orb.phi
    sI = _sigma(W, phi, 0.0, orb.T1)
    sII = _sigma(W, phi, orb.T1, orb.T)
    g = _m_vectors(orb, 1) @ A1 + _m_vectors(orb, 2) @ A2
    n = s.n
    Gam = np.empty((len(orb), n, n))
    Gam[:, :-1, :-1] = sI[:, None, None] * S1 + sII[:, None, None] * S2
    Gam[:, :-1, -1] = g
    Gam[:, -1, :-1] = g
    Gam[:, -1, -1] = denom
    return Gam


def _solve_pts(A, b):
    """Batched ``solve(A[p], b[p])`` (b (P, n) or (P, n, L)); an exactly singular point gets least squares."""
    vec = b.ndim == A.ndim - 1
    bb = b[..., None] if vec else b
    try:
        x = np.linalg.solve(A, bb)
    except np.linalg.LinAlgError:
        x = np.stack([np.linalg.lstsq(A[i], bb[i], rcond=None)[0] for i in range(A.shape[0])])
    return x[..., 0] if vec else x


def _as_loads(q, n: int):
    q = np.asarray(q, float)
    one = q.ndim == 1
    Q = np.atleast_2d(q)
    if Q.ndim != 2 or Q.shape[1] != n or not np.all(np.isfinite(Q)):
        raise InputError(f"load vectors must be finite, of shape (n,) or (L, n) with n = {n}; got {q.shape}")
    return Q, one


@dataclass(frozen=True, eq=False)
class LoadForms(PointLoads):
    """``b`` and ``G`` at every path point: ``xi_eq(q) = (b . q)^2 / (2 q^T G q)``.

    Attributes
    ----------
    T1, T2, phi : ndarray, shape (P,)
        The path points (of the reference load; ``phi`` mod ``pi`` holds for every load).
    branch, point : ndarray of int, shape (P,)
        Branch id and index along the branch (-1 if built from bare orbits).
    b : ndarray, shape (P, n)
        ``Delta_PL(q) = (b . q)^2``; ``b . q = v_c(T-) / sqrt(2 (M^-1)_cc)``.
    G : ndarray, shape (P, n, n)
        Symmetric PSD: ``q^T G q`` is the denominator of Eq. (22) (without the 2).
    B, Gamma : ndarray, shape (P, n, n)
        The factored form: ``G = B^-T Gamma B^-1`` (see the module docstring).
    hc : ndarray, shape (P, n)
        Unit vector along ``H e_c``: ``h(q) = 0`` iff ``hc . q = 0``.
    h_ref : ndarray, shape (P,)
        ``h(q_ref)``.
    q_ref : ndarray, shape (n,)
    x : ndarray, shape (n,)
        Free-DOF positions (contact last).
    """

    T1: np.ndarray
    T2: np.ndarray
    phi: np.ndarray
    branch: np.ndarray
    point: np.ndarray
    b: np.ndarray
    G: np.ndarray
    B: np.ndarray
    Gamma: np.ndarray
    hc: np.ndarray
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
        return f"LoadForms({len(self)} path points, n = {self.n})"

    # -- any load vector -------------------------------------------------------------------------
    def dPL(self, q):
        """``Delta_PL(q) = (b . q)^2`` (Eq. (14)); q (n,) -> (P,), q (L, n) -> (P, L)."""
        Q, one = _as_loads(q, self.n)
        d = (self.b @ Q.T) ** 2
        return d[:, 0] if one else d

    def denom(self, q):
        """``q^T G q``: the bracket of Eq. (22); q (n,) -> (P,), (L, n) -> (P, L)."""
        Q, one = _as_loads(q, self.n)
        d = np.einsum("lj,pjk,lk->pl", Q, self.G, Q, optimize=True)
        return d[:, 0] if one else d

    def xi(self, q):
        """``xi_eq(q) = (b . q)^2 / (2 q^T G q)`` (Eq. (22)); 0 where ``q^T G q = 0``."""
        num, den = self.dPL(q), self.denom(q)
        return np.divide(num, 2 * den, out=np.zeros_like(num), where=den > 0)

    def h(self, q):
        """Contact response ``h(q) = (H q)_c`` of state II; q (n,) -> (P,), (L, n) -> (P, L)."""
        Q, one = _as_loads(q, self.n)
        alpha = _solve_pts(self.B, np.broadcast_to(Q.T, (len(self),) + Q.T.shape))[:, -1, :]
        d = alpha * self.h_ref[:, None]
        return d[:, 0] if one else d

    def phase(self, q):
        """The forcing phase of load ``q`` at every path point: ``phi_ref`` where ``h(q)`` has the sign of ``h_ref``,
        ``phi_ref + pi`` where it has the other (the response is ``alpha`` times the reference's, ``alpha < 0`` a half
        period late), in ``[0, 2 pi)``; q (n,) -> (P,), (L, n) -> (P, L)."""
        hq = self.h(q)
        ref = self.h_ref if np.ndim(hq) == 1 else self.h_ref[:, None]
        p = self.phi if np.ndim(hq) == 1 else self.phi[:, None]
        return np.mod(p + np.where(hq * ref < 0, np.pi, 0.0), 2 * np.pi)

    def h_relative(self, q):
        """``|h(q)| / (|H e_c| |q|)`` in ``[0, 1]``: 0 means no periodic path at that point."""
        Q, one = _as_loads(q, self.n)
        nq = np.linalg.norm(Q, axis=1)
        r = np.abs(self.hc @ Q.T) / np.where(nq > 0, nq, 1.0)
        return r[:, 0] if one else r

    def no_path(self, q, tol: float = HZERO_TOL):
        """True where ``h(q) = 0`` (relative ``tol``): the load has no periodic response there."""
        return self.h_relative(q) < tol

    # -- point forces (_elems, point_vectors: extremes.PointLoads) --------------------------------
    def _local(self):
        """``b`` and ``G`` padded with a zero dummy DOF ``n`` (the clamped DOF of element tables)."""
        cache = self.__dict__.get("_local_cache")
        if cache is None:
            P, n = self.b.shape
            bp = np.zeros((P, n + 1))
            bp[:, :n] = self.b
            Gp = np.zeros((P, n + 1, n + 1))
            Gp[:, :n, :n] = self.G
            cache = (bp, Gp)
            object.__setattr__(self, "_local_cache", cache)
        return cache

    def point_loads(self, s):
        """``xi_eq`` and ``Delta_PL`` of unit point forces at ``s`` (S,): each (P, S), element-local."""
        el = self._elems()
        e, t = el.locate(np.atleast_1d(np.asarray(s, float)))
        N = el.values(e, t)                                    # (S, k)
        d = el.dofs[e]                                         # (S, k)
        bp, Gp = self._local()
        bl = np.einsum("psk,sk->ps", bp[:, d], N)
        den = np.einsum("psk,sk->ps", np.einsum("psij,sj->psi", Gp[:, d[:, :, None], d[:, None, :]], N), N)
        num = bl ** 2
        return np.divide(num, 2 * den, out=np.zeros_like(num), where=den > 0), num

    def xi_point(self, s):
        """``xi_eq`` of unit point forces at positions ``s`` (S,): shape (P, S)."""
        return self.point_loads(s)[0]

    def element_max(self) -> ElementMax:
        """Exact maximum of ``xi_eq(s)`` of a unit point force over each element (:func:`.extremes.element_max`)."""
        return element_max(self)

    def worst(self, rcond: float = RCOND) -> Worst:
        """Largest ``xi_eq`` over every load and its shape, ``b^T G^+ b / 2`` at ``q* = G^+ b``.

        :func:`.extremes.worst`.
        """
        return worst(self, rcond)

    def take(self, idx) -> "LoadForms":
        """A subset of the path points."""
        f = {k: getattr(self, k) for k in self.__dataclass_fields__}
        for k in ("T1", "T2", "phi", "branch", "point", "b", "G", "B", "Gamma", "hc", "h_ref"):
            f[k] = f[k][idx]
        return LoadForms(**f)


def load_forms(source) -> LoadForms | DampedLoadForms:
    """The quadratic forms ``b, G`` at every path point of ``source``.

    With Rayleigh damping: :class:`plbar.studies.loads.damped.DampedLoadForms` (the same interface;
    ``xi_eq(q)`` through the complex contact response, the worst load by a phase scan).

    Parameters
    ----------
    source : Paths or Orbits
        Solved paths (all branches, in branch order) or periodic orbits of a reference load
        with ``h(q_ref) != 0``.

    Raises
    ------
    InputError
        For a modally truncated system (``modes=``): the structure does not hold there
        (``docs/load_structure.md`` §6); use the full model or the per-load sweep.
    """
    with single_thread_blas:
        return _load_forms(*_points(source))


def _load_forms(orb, branch, point, dPL, denom):
    prob = orb.prob
    s = prob.system
    if s.damped and not s.truncated and len(orb):
        return damped_forms(orb, branch, point, dPL, denom)
    if s.truncated:
        raise InputError("load studies on the exact structure need the full modal model: with modes = "
                         f"({s.w1.size}, {s.w2.size}) of ({s.n - 1}, {s.n}) the two states live in different "
                         "Galerkin subspaces and the paths depend on the load (docs/load_structure.md §6); "
                         "solve with modes=None, or use the per-load sweep (plbar.sweep)")
    if len(orb) == 0:
        raise InputError("no path points: solve a case with at least one branch first")
    n = s.n
    W = orb.W
    Z = s.K[None] - W[:, None, None] ** 2 * s.M[None]
    B = Z.copy()
    B[:, :, -1] = prob.q
    Gam = _gram(orb, denom)
    ea = np.zeros(n)
    ea[-1] = 1.0
    y = _solve_pts(np.swapaxes(B, 1, 2), np.broadcast_to(ea, (len(orb), n)))      # B^-T e_a
    b = np.sqrt(np.maximum(dPL, 0.0))[:, None] * y
    Binv = _solve_pts(B, np.broadcast_to(np.eye(n), (len(orb), n, n)))
    G = np.einsum("pji,pjk,pkl->pil", Binv, Gam, Binv, optimize=True)
    G = 0.5 * (G + np.swapaxes(G, 1, 2))
    ec = np.zeros((len(orb), n))
    ec[:, -1] = 1.0
    Hc = _solve_pts(Z, ec)
    nh = np.linalg.norm(Hc, axis=1, keepdims=True)
    h_ref = _solve_pts(Z, np.broadcast_to(prob.q, (len(orb), n)))[:, -1]
    return LoadForms(orb.T1.copy(), orb.T2.copy(), orb.phi.copy(), branch, point, b, G, B, Gam,
                     Hc / np.where(nh > 0, nh, 1.0), h_ref, np.asarray(prob.q, float).copy(), s.x.copy(), prob.asm)


def _points(source):
    """Orbits, branch ids, point indices, ``Delta_PL`` and the Eq. (22) bracket of every path point."""
    if isinstance(source, Orbits):
        d = damping(source)
        m = len(source)
        return source, np.full(m, -1), np.arange(m), d.dPL, d.denom
    br = getattr(source, "branches", None)
    if br is None:
        raise InputError(f"load_forms needs plbar Paths or Orbits, not {type(source).__name__}")
    orb = source.points()
    if orb is None:
        raise InputError("the paths have no branch: there is nothing to study (solve a larger domain or grid)")
    cat = np.concatenate
    return (orb, cat([np.full(len(b), b.id) for b in br]), cat([np.arange(len(b)) for b in br]),
            cat([b.damping.dPL for b in br]), cat([b.damping.denom for b in br]))
