"""One periodic response at a given forcing period, from a nearby guess (fast path).

At a fixed period ``T`` the periodic responses are the zeros of
``G(T^I) = D(T^I, T - T^I) sign(det(Id - A)) / (a1^2 + b1^2 + a2^2 + b2^2)``
(FORMULATION §4; the phase is exact once ``D = 0``).  :func:`find_response`
evaluates the periodicity system at ``K`` Chebyshev points around the guess in
one batched call, takes the root of the Chebyshev interpolant of ``G`` inside
the sign-change bracket nearest the guess, and interpolates the periodic
states and the residual coefficients there (barycentric formula).  The result
is then *checked*, not trusted: the switch residuals are recomputed from the
closed-form flow of the interpolated state (Eqs. (4)-(5)) and the state is
mapped over one period (Eq. (10)); if either check is not at round-off, one
direct evaluation at the root and secant steps on ``G`` take over.

This is what a user who needs one response (not the whole path) calls; it is
the plbar side of the "one response" benchmark against shooting.
"""

from __future__ import annotations

import math
from contextlib import nullcontext
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import InputError, PlbarError
from ..model import Problem
from ..util import check as _check
from ..util.blas import single_thread_blas
from ..util.reprs import build
from ..util.roots import bracketed
from . import scalar as _scalar
from .energy import damping
from .onemap import Coefficients, period_map, phase
from .orbit import Orbits, orbits

__all__ = ["Response", "find_response", "NoResponseError"]

SMALL = 32           #: up to this many modes (both states) the final orbit is evaluated in plain Python floats
ACCEPT = 1e-12        #: accepted relative switch residual / periodicity defect of the result


class NoResponseError(PlbarError):
    """No periodic response near the guess (no sign change of ``G`` in the search window)."""


@dataclass(frozen=True)
class Response:
    """One periodic response at forcing period ``T`` (floats unless noted).

    Attributes
    ----------
    T, T1, T2, phi : float
        Period, times in state I and II, forcing phase (``v_c(T^-) > 0``).
    eta0, v0 : ndarray
        Modal state I at ``t = 0`` (periodic initial condition).
    e1, e2 : float
        Switch residuals ``-R(T^I-)`` and ``x_c(T^-)`` recomputed from the
        flow of the returned state, relative to the response amplitude
        (Eqs. (4)-(5)).
    periodicity : float
        ``max |z(T^+) - z(0)| / max |z(0)|`` after the plastic impact (Eq. (10)).
    v_impact : float
        Contact velocity just before the impact (> 0 for a physical response).
    dPL, xi : float
        Impact loss (Eq. (14)) and ``xi_eq`` (Eq. (22)).
    evaluations : int
        ``(T^I, T^II)`` points at which the periodicity system was solved.
    prob : Problem
    eta_s, v_s : ndarray
        Modal state II just after the gap opens (``t = T^I``).
    viscous : float
        Energy dissipated by the Rayleigh dampers over the period (0 without damping);
        the work of the load is ``dPL + viscous``.
    zeta_rayleigh : float
        Rayleigh damping ratio at the forcing frequency (``xi_total = zeta_rayleigh + xi``).

    ``x0, xdot0`` (physical state at ``t = 0``) and ``orbit`` (a one-orbit
    :class:`~plbar.orbit.Orbits` for time histories, energies and
    ``plbar.admissible.check``) are computed on first access.
    """

    T: float
    T1: float
    T2: float
    phi: float
    eta0: np.ndarray
    v0: np.ndarray
    e1: float
    e2: float
    periodicity: float
    v_impact: float
    dPL: float
    xi: float
    evaluations: int
    prob: Problem
    eta_s: np.ndarray
    v_s: np.ndarray
    viscous: float = 0.0
    zeta_rayleigh: float = 0.0

    @property
    def xi_total(self) -> float:
        """``zeta_rayleigh + xi``: the equivalent ratio of the damped structure with its impact."""
        return self.zeta_rayleigh + self.xi

    def __repr__(self) -> str:
        return build("Response", {k: getattr(self, k) for k in ("T", "T1", "T2", "phi", "xi", "dPL", "v_impact", "e1",
                                                                "e2", "periodicity", "evaluations")}
                     | {"n": self.prob.system.n})

    @cached_property
    def orbit(self) -> Orbits:
        return Orbits(self.prob, np.array([self.T1]), np.array([self.T2]), np.array([self.phi]),
                      self.eta0[None], self.v0[None], self.eta_s[None], self.v_s[None])

    @cached_property
    def x0(self) -> np.ndarray:
        """Physical displacements at ``t = 0`` (free DOFs, contact DOF last, where it is 0)."""
        s = self.prob.system
        return s.embed(s.V1 @ self.eta0)

    @cached_property
    def xdot0(self) -> np.ndarray:
        """Physical velocities at ``t = 0``."""
        s = self.prob.system
        return s.embed(s.V1 @ self.v0)


def _cheb(K: int):
    th = np.pi * (np.arange(K) + 0.5) / K
    x = np.cos(th)                                   # descending in [-1, 1]
    C = np.cos(np.outer(np.arange(K), th)) * (2.0 / K)
    C[0] *= 0.5
    bw = (-1.0) ** np.arange(K) * np.sin(th)         # barycentric weights (first-kind points)
    return x, C, bw


_CHEB: dict[int, tuple] = {}


def _clenshaw(c, t):
    """Chebyshev series ``sum c_j T_j(t)`` and its derivative at a float ``t`` (pure Python, short series)."""
    b1 = b2 = 0.0
    d1 = d2 = 0.0
    for cj in reversed(c[1:]):
        d1, d2 = 2.0 * b1 + 2.0 * t * d1 - d2, d1
        b1, b2 = 2.0 * t * b1 - b2 + cj, b1
    return t * b1 - b2 + c[0], b1 + t * d1 - d2


def _poly_root(c, lo, hi, flo, fhi):
    """Root of the Chebyshev series in ``[lo, hi]`` (values of opposite signs there): safeguarded Newton."""
    t = lo - flo * (hi - lo) / (fhi - flo)
    for _ in range(60):
        p, dp = _clenshaw(c, t)
        if p == 0.0:
            return t
        if (p < 0) == (flo < 0):
            lo = t
        else:
            hi = t
        tn = t - p / dp if dp != 0 else 0.5 * (lo + hi)
        if not lo <= tn <= hi:
            tn = 0.5 * (lo + hi)
        if abs(tn - t) <= 2e-16:
            return tn
        t = tn
    return t


class _Lean:
    """Per-problem constants of :func:`_assemble` (cached on the Problem)."""

    def __init__(self, prob: Problem):
        s = prob.system
        self.nr = float(np.linalg.norm(s.r_eta))
        self.nrv = float(np.linalg.norm(s.r_v))
        self.ng = float(np.abs(s.gap_row).max())
        # the plain-float pass is undamped only; damped systems take the batched (damped) flows
        self.small = _scalar.Small(prob) if s.w1.size + s.w2.size <= SMALL and not s.damped else None


def _lean(prob: Problem) -> _Lean:
    """The constants of ``prob``, computed once."""
    return prob.cached("response", _Lean)


def _assemble(prob: Problem, T: float, T1: float, a, Z, evaluations: int) -> Response:
    """The response at ``T1`` from its coefficients ``a = (a1, b1, a2, b2)`` and states ``Z`` (2 n1, 2).

    Small undamped systems: one plain-float pass (:mod:`plbar._scalar`).  Otherwise
    (damped systems, and near resonance, where ``Psi`` needs quadrature) the
    batched orbit and energy code on a one-orbit batch.
    """
    k = _lean(prob)
    if k.small is not None:
        o = _scalar.orbit(k.small, T, T1, [float(v) for v in a], Z.tolist())
        if o["cancel"] < _scalar.CANCEL_LIMIT:
            den = o["den"]
            return Response(T=T, T1=T1, T2=T - T1, phi=o["phi"], eta0=np.array(o["eta0"]), v0=np.array(o["v0"]),
                            e1=abs(o["r1"]) / o["sc1"], e2=abs(o["r2"]) / o["sc2"], periodicity=o["per"],
                            v_impact=o["v_imp"], dPL=o["dPL"], xi=o["dPL"] / (2 * den) if den > 0 else 0.0,
                            evaluations=evaluations, prob=prob, eta_s=np.array(o["eta_s"]), v_s=np.array(o["v_s"]))
    T2 = T - T1
    one = np.ones(1)
    co = Coefficients(np.array([T1]), np.array([T2]), *[np.array([float(v)]) for v in a], one, Z[None], one, one)
    phi = phase(co)                                     # the exact phase; phi + pi is the negated response
    orb = orbits(prob, co.T1, co.T2, phi, co=co)
    v_imp = float(orb.contact_velocity(co.T2[:, None])[0, 0])
    if v_imp <= 0:
        orb = orbits(prob, co.T1, co.T2, phi + np.pi, co=co)
        v_imp = -v_imp
    e, ve = orb.state_I(co.T1[:, None])
    eT, _ = orb.end()
    r1, r2 = orb.residuals()
    sc1 = k.nr * max(np.abs(e).max(), np.abs(orb.eta0).max()) + abs(prob.r_q)
    if prob.system.damped:
        sc1 += k.nrv * max(np.abs(ve).max(), np.abs(orb.v0).max())
    sc2 = k.ng * max(np.abs(eT).max(), np.abs(orb.eta_s).max())
    ep, vp = orb.after_impact()
    z0, z1 = np.c_[orb.eta0, orb.v0], np.c_[ep, vp]
    per = float(np.abs(z1 - z0).max() / max(np.abs(z0).max(), 1e-300))
    d = damping(orb)
    return Response(T=float(T), T1=float(T1), T2=float(T2), phi=float(np.mod(orb.phi[0], 2 * np.pi)),
                    eta0=orb.eta0[0], v0=orb.v0[0], e1=abs(float(r1[0])) / sc1, e2=abs(float(r2[0])) / sc2,
                    periodicity=per, v_impact=v_imp, dPL=float(d.dPL[0]), xi=float(d.xi[0]),
                    evaluations=evaluations, prob=prob, eta_s=orb.eta_s[0], v_s=orb.v_s[0],
                    viscous=float(d.viscous[0]), zeta_rayleigh=float(d.zeta_rayleigh[0]))


def _ok(r: Response) -> bool:
    return r.e1 < ACCEPT and r.e2 < ACCEPT and r.periodicity < ACCEPT


def _arguments(prob, T, T1_guess, nodes):
    """Validated ``(T, T1_guess, K)`` (floats pass through without the generic checks: the fast path)."""
    if not isinstance(prob, Problem):
        raise InputError(f"prob must be a plbar Problem (plbar.problem(...)), got {type(prob).__name__}")
    T = T if type(T) is float and math.isfinite(T) else _check.finite("period T", T)
    g = T1_guess if type(T1_guess) is float and math.isfinite(T1_guess) else _check.finite("T1_guess", T1_guess)
    if not (T > 0 and 0 < g < T):
        raise InputError(f"T = {T!r}, T1_guess = {g!r} are not allowed; they must satisfy 0 < T1_guess < T")
    K = nodes if type(nodes) is int and nodes in _CHEB else _check.integer("nodes", nodes, 4, 64)
    if K not in _CHEB:
        _CHEB[K] = _cheb(K)
    return T, g, K


def _window(prob, T, g, h, lim, x):
    """The first window around ``g`` (widened four-fold up to four times) where ``G`` changes sign.

    ``G`` is taken unsigned (``D / |a, b|^2``: smooth through the poles of ``D``,
    where it also vanishes); a sign change is a periodic response iff
    ``sign(det(Id - A))`` is the same at both ends.  Returns the bracket index
    ``k`` (None if none), the half-width, the map at the nodes, the signed
    ``G`` there and the evaluation count.
    """
    evals = 0
    for _ in range(5):
        t1 = g + h * x
        pm = period_map(prob, t1, T - t1, signs=False, scales=False)
        evals += x.size
        Dn = pm.G
        neg = Dn < 0
        ch = np.flatnonzero(neg[:-1] != neg[1:])
        for j in ch[np.argsort(np.abs(x[ch] + x[ch + 1]), kind="stable")]:    # nearest the guess first
            sg = np.linalg.slogdet(pm.IA[j:j + 2])[0]       # 0 where singular
            if sg[0] == sg[1] != 0:
                return int(j), h, pm, Dn * sg[0], evals
        if h >= lim:
            break
        h = min(4.0 * h, lim)
    raise NoResponseError(f"no periodic response with T1 within {h:.3g} of {g!r} at T = {T!r} "
                          f"(D has no sign change there, only poles); try another guess or plbar.find_paths")


def _interpolated(prob, T, g, h, k, pm, Gv, K, evals) -> Response:
    """The response at the root of the Chebyshev interpolant of ``G`` in bracket ``k`` (barycentric states)."""
    x, C, bw = _CHEB[K]
    t = _poly_root((C @ Gv).tolist(), float(x[k + 1]), float(x[k]), float(Gv[k + 1]), float(Gv[k]))
    dx = t - x
    if np.all(dx != 0):
        wts = bw / dx
        wts /= wts.sum()
    else:
        wts = (dx == 0).astype(float)
    e = wts @ np.concatenate([pm.e1, pm.e2, pm.Z.reshape(K, -1)], axis=1)
    return _assemble(prob, T, g + h * t, e[:4], e[4:].reshape(pm.Z.shape[1:]), evals)


def _direct(prob, T, lo, hi, glo, ghi, T1, evals) -> Response:
    """Direct evaluations and bracketed (Anderson-Björck) steps on ``G`` from ``T1``, until the result checks."""
    gen = bracketed(lo, hi, glo, ghi, 4e-16 * T, x0=T1)
    r = None
    try:
        _, x = next(gen)
        while True:
            T1 = float(x[0])
            pm = period_map(prob, np.array([T1]), np.array([T - T1]), scales=False)
            evals += 1
            r = _assemble(prob, T, T1, (*pm.e1[0], *pm.e2[0]), pm.Z[0], evals)
            if _ok(r):
                break
            _, x = gen.send(pm.G)
    except StopIteration:
        pass
    return r


def find_response(prob: Problem, T, T1_guess, *, width=None, nodes: int = 12) -> Response:
    """The periodic response at period ``T`` whose ``T^I`` is nearest ``T1_guess``.

    Parameters
    ----------
    prob : Problem
    T : float
        Forcing period ``2 pi / Omega``.
    T1_guess : float
        Guess of the time spent in state I, in ``(0, T)``.
    width : float, optional
        Half-width of the first search window in ``T^I`` (default
        ``min(0.005 T, T1_guess / 2, (T - T1_guess) / 2)``); widened four-fold
        up to four times if ``G`` has no sign change in it.
    nodes : int
        Chebyshev points per window; the interpolant's root is checked, not
        trusted: where it is not at round-off, direct evaluations and
        bracketed steps on ``G`` take over.

    Returns
    -------
    Response
        Checked at round-off: the switch residuals recomputed from the flow of
        the returned state and its periodicity defect after one period with
        the impact are below ``ACCEPT`` (else :class:`NoResponseError`).

    Notes
    -----
    Admissibility (no premature switch) is not part of this fast path: check
    it with ``plbar.response.check(r.orbit)``.  At a fold in ``T`` the root in
    ``T^I`` is ill-conditioned: the residuals stay at round-off, ``T^I`` is
    accurate to about the square root of it.
    """
    T, g, K = _arguments(prob, T, T1_guess, nodes)
    x = _CHEB[K][0]
    lim = 0.5 * min(g, T - g) * (1 - 1e-9)
    h = min(float(width) if width is not None else 0.005 * T, lim)
    # BLAS threads only matter for large systems (single_thread_blas: see plbar.util.blas)
    with (single_thread_blas if _lean(prob).small is None else nullcontext()):
        k, h, pm, Gv, evals = _window(prob, T, g, h, lim, x)
        r = _interpolated(prob, T, g, h, k, pm, Gv, K, evals)
        if not _ok(r):
            r = _direct(prob, T, g + h * float(x[k + 1]), g + h * float(x[k]), float(Gv[k + 1]), float(Gv[k]),
                        r.T1, r.evaluations)
    if not _ok(r):
        raise NoResponseError(f"the root near T1 = {r.T1!r} at T = {T!r} does not converge to a periodic response "
                              f"(residuals {r.e1:.1e}, {r.e2:.1e}, periodicity defect {r.periodicity:.1e}): "
                              f"probably a pole of D (Id - A singular)")
    return r
