"""Where responses of other signatures come from, without the user: closed forms, bifurcations, simulations.

* :func:`zero_dwell` -- the class ``1Z`` (one impact per period, no stuck phase) is one
  equation in ``(T, phi)``: at each ``T`` the free phase lasts ``T``, the periodic
  state is linear in ``(cos phi, sin phi)`` and so is the gap at the impact, so
  ``phi`` is exact (two roots, ``phi`` and ``phi + pi``), like the paper's class
  after the phase elimination (FORMULATION §4);
* :func:`doubled` -- at a period doubling (a multiplier through ``-1``) the orbit
  seen over two periods is a solution of the doubled signature where its
  Jacobian is singular; the branch of ``m = 2`` leaves along the null vector;
* :func:`from_events` -- a periodic motion of a simulation (its switches over ``m``
  periods and the state at an impact) as a guess for Newton.
"""

from __future__ import annotations

import numpy as np

from ..model import Problem
from .chain import evaluate, layout
from .signature import ZERO_DWELL, Signature
from .solve import HybridOrbit, NotConverged, orbit_at, polish

__all__ = ["zero_dwell", "doubled", "from_events"]


def zero_dwell(prob: Problem, T: float) -> list[HybridOrbit]:
    """The responses of class ``1Z`` at period ``T`` (both phase roots; checked, not yet for admissibility)."""
    nz, q, nX = layout(prob, ZERO_DWELL)
    T = float(T)
    base = np.zeros(nX)
    base[nz] = T
    ch0 = evaluate(prob, ZERO_DWELL, T, base)                     # phi = 0, z0 = 0: the cos phi column, and d/dz0
    Xs = base.copy()
    Xs[-1] = 0.5 * np.pi
    ch1 = evaluate(prob, ZERO_DWELL, T, Xs, jac=False)           # phi = pi/2: the sin phi column
    rows = np.r_[0, np.arange(2, 2 + nz)]                         # impact residual and periodicity
    A = ch0.J[rows][:, :nz]                                       # d/dz0 of both (affine in z0)
    cc, cs = ch0.F[rows], ch1.F[rows]
    try:
        Zc = np.linalg.solve(A[1:], -cc[1:])
        Zs = np.linalg.solve(A[1:], -cs[1:])
    except np.linalg.LinAlgError:
        return []
    a = A[0] @ Zc + cc[0]
    b = A[0] @ Zs + cs[0]
    out = []
    for phi in np.mod(np.arctan2(-a, b) + np.array([0.0, np.pi]), 2 * np.pi):
        X = np.concatenate([Zc * np.cos(phi) + Zs * np.sin(phi), [T, phi]])
        orb = orbit_at(prob, ZERO_DWELL, T, X)
        if orb.residual <= 1e-9:
            out.append(orb)
    return out


def doubled(prob: Problem, orb: HybridOrbit, eps=(1e-3, 1e-2, 3e-2)) -> list[HybridOrbit]:
    """Orbits of the doubled signature near ``orb`` (at its ``T``) that are not ``orb`` itself."""
    sig2 = orb.sig.repeated(2)
    nz, q, _ = layout(prob, orb.sig)
    X1 = orb.X
    X2 = np.concatenate([X1[:nz], np.tile(X1[nz:nz + q], 2), [X1[-1]]])
    ch = evaluate(prob, sig2, orb.T, X2)
    _, sv, vt = np.linalg.svd(ch.J)
    n = vt[-1]
    scale = np.concatenate([np.full(nz, max(np.abs(X1[:nz]).max(), 1e-12)), np.full(2 * q, orb.T), [1.0]])
    out = []
    for e in eps:
        for sgn in (1.0, -1.0):
            try:
                o = polish(prob, sig2, orb.T, X2 + sgn * e * n * scale / np.linalg.norm(n * scale))
            except NotConverged:
                continue
            d = o.durations
            if np.max(np.abs(d[:d.size // 2] - d[d.size // 2:])) > 1e-6 * orb.T:
                out.append(o)
        if out:
            break
    return out


def from_events(prob: Problem, sig: Signature, T: float, t_impact: float, z_after: np.ndarray, durations,
                phi_sim: float = 0.0) -> HybridOrbit:
    """Polish a simulated periodic motion: ``z_after`` (state I modal, just after the impact at ``t_impact``) and the
    ``2k`` durations that follow it; the orbit's ``t = 0`` is that impact, so ``phi = phi_sim - W t_impact``."""
    nz, q, _ = layout(prob, sig)
    d = np.asarray(durations, float)
    taus = [d[2 * i] for i, positive in enumerate(sig.dwell) if positive]
    var = []
    for i, positive in enumerate(sig.dwell):
        if positive:
            var.append(d[2 * i])
        var.append(d[2 * i + 1])
    phi = np.mod(phi_sim - 2 * np.pi / T * t_impact, 2 * np.pi)
    del taus
    return polish(prob, sig, T, np.concatenate([z_after, var, [phi]]))
