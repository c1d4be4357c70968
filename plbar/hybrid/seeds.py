"""Where responses of other signatures come from, without the user: closed forms, bifurcations, simulations.

* :func:`zero_dwell` -- the class ``1Z`` (one impact per period, no stuck phase) is one
  equation in ``(T, phi)``: at each ``T`` the free phase lasts ``T``, the periodic
  state is linear in ``(cos phi, sin phi)`` and so is the gap at the impact, so
  ``phi`` is exact (two roots, ``phi`` and ``phi + pi``), like the paper's class
  after the phase elimination (FORMULATION §4);
* :func:`doubled` -- at a period doubling (a multiplier through ``-1``) the orbit
  seen over two periods is a solution of the doubled signature where its
  Jacobian is singular; the branch of ``m = 2`` leaves along the null vector;
* :func:`split` -- where an orbit stops being admissible (a premature switch: the free flight
  grazes the wall, the reaction touches zero), the switches that the bar makes instead,
  replayed from its state, give the neighbouring signature (one more pair) and its guess;
* :func:`from_motion` -- a periodic motion of a simulation (a boundary state, its switches
  over ``m`` periods) as a guess for Newton.
"""

from __future__ import annotations

import numpy as np

from ..model import Problem
from .chain import evaluate, layout
from .signature import ZERO_DWELL, Signature
from .solve import HybridOrbit, NotConverged, orbit_at, polish

__all__ = ["zero_dwell", "doubled", "from_motion", "split"]


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


def doubled(prob: Problem, orb: HybridOrbit, steps=(1e-3, 3e-3, 1e-2, 3e-2)) -> list[HybridOrbit]:
    """Orbits of the doubled signature that branch off near ``orb`` (a period doubling), not ``orb`` itself.

    The orbit seen over two periods solves the doubled equations; at the doubling their Jacobian
    in ``X`` is singular and the new branch leaves along its null vector: a step along it, then Newton
    on the equations and the plane through the predicted point normal to the step (branch switching).
    """
    from .follow import correct, scale_of

    sig2 = orb.sig.repeated(2)
    nz, q, _ = layout(prob, orb.sig)
    X1 = orb.X
    X2 = np.concatenate([X1[:nz], np.tile(X1[nz:nz + q], 2), [X1[-1]]])
    Y0 = np.concatenate([X2, [orb.T]])
    S = scale_of(prob, sig2, X2, orb.T)
    ch = evaluate(prob, sig2, orb.T, X2)
    _, _, vt = np.linalg.svd(ch.J * S[None, :-1])
    t = np.concatenate([vt[-1], [0.0]])
    out = []
    for h in steps:
        for sgn in (1.0, -1.0):
            o = correct(prob, sig2, Y0 + sgn * h * t * S, sgn * t, S)
            if o is None:
                continue
            d = o.durations
            if np.max(np.abs(d[:d.size // 2] - d[d.size // 2:])) > 1e-6 * o.T:
                out.append(o)
        if out:
            break
    return out


def from_motion(prob: Problem, T: float, m: int, t_b: float, x_b, v_b, state_b: int, times, kinds,
                phi: float = 0.0) -> HybridOrbit:
    """Polish a periodic motion of a simulation into an exact orbit.

    ``x_b, v_b`` (physical, contact DOF last) and ``state_b`` (0 stuck, 1 free) are the state at ``t_b``
    (a period boundary); ``times, kinds`` the switches after it (1 opening, 2 impact), covering the first
    impact after ``t_b`` and ``m`` periods beyond.  The state is carried by the exact flows to that
    impact, the orbit's ``t = 0``; the switches of the next ``m`` periods give the signature and the
    durations; Newton polishes (:func:`polish`).  Raises :class:`NotConverged` or ``ValueError``.
    """
    sy = prob.system
    M = np.asarray(sy.M, float)
    W = 2 * np.pi / T
    times, kinds = np.asarray(times, float), np.asarray(kinds, int)
    if state_b == 0:
        z = np.concatenate([sy.V1.T @ M[:-1, :-1] @ x_b[:-1], sy.V1.T @ M[:-1, :-1] @ v_b[:-1]])
    else:
        z = np.concatenate([sy.V2.T @ M @ x_b, sy.V2.T @ M @ v_b])
    s, t = (1 if state_b == 0 else 2), float(t_b)
    imp = np.flatnonzero(kinds == 2)
    if not imp.size:
        raise ValueError("no impact after the boundary state")
    for te, ke in zip(times[:imp[0] + 1], kinds[:imp[0] + 1]):
        z = _carry(prob, s, z, W, t, te - t, phi)
        t = te
        z, s = _switch(prob, z, ke)
    t_imp = t
    after = times[imp[0] + 1:]
    kinds_after = kinds[imp[0] + 1:]
    end = t_imp + m * T
    closing = np.flatnonzero(kinds_after == 2)
    if not closing.size:
        raise ValueError("no impact after the first one")
    # the orbit closes on the impact nearest to m T later: a motion still settling on its orbit repeats only
    # nearly, its closing impact a little before or after (a fixed window would cut or add a pair)
    j = int(closing[np.argmin(np.abs(after[closing] - end))])
    if abs(after[j] - end) > 0.05 * T:
        raise ValueError(f"no impact within 0.05 T of m T = {m} T after the first one: not an orbit of m periods")
    n = j + 1
    seq_t, seq_k = np.concatenate([[t_imp], after[:n]]), kinds_after[:n]
    if not n or seq_k[-1] != 2 or np.any(seq_k[0::2] != 1) or np.any(seq_k[1::2] != 2):
        raise ValueError("the switches after the impact are not opening/impact pairs over m periods")
    d = np.diff(seq_t)
    dwell = tuple(bool(x > 1e-9 * T) for x in d[0::2])
    sig = Signature(int(m), dwell)
    var = []
    for i, positive in enumerate(dwell):
        if positive:
            var.append(d[2 * i])
        var.append(d[2 * i + 1])
    var[-1] += end - seq_t[-1]                    # the sum is m T exactly
    return polish(prob, sig, T, np.concatenate([z, var, [np.mod(phi - W * t_imp, 2 * np.pi)]]))


def _carry(prob, s, z, W, t, tau, phi):
    from ..response import segment

    from .chain import state_data

    w, f, _, _, zeta, _ = state_data(prob, s)
    m = w.size
    e, v = segment(w, f, W, t, tau, z[:m], z[m:], np.cos(phi), np.sin(phi), zeta=zeta)
    return np.concatenate([e, v])


def _switch(prob, z, kind):
    from .chain import switch_maps

    E, G = switch_maps(prob)
    return (E @ z, 2) if kind == 1 else (G @ z, 1)


def split(prob: Problem, orb: HybridOrbit) -> list[HybridOrbit]:
    """The orbit of the signature the bar follows from ``orb``'s state when ``orb`` is not admissible.

    Replays ``orb`` (its state just after its last impact, its load phase) with the certified simulator
    for ``m`` periods; the switches met, one more pair where the orbit switched prematurely, are the
    guess; Newton polishes.  Empty if the replay does not end with an impact near ``m T``, or Newton fails.
    """
    from ..motion import STUCK, Start, padded, run

    pad = padded(prob)
    m1 = prob.system.w1.size
    eta, vel = np.zeros((1, pad.m)), np.zeros((1, pad.m))
    eta[0, :m1], vel[0, :m1] = orb.z0[:m1], orb.z0[m1:]
    m = orb.sig.m
    r = run(pad, [orb.T], [orb.phi], m + 1, m + 1, Start(np.array([STUCK]), eta, vel), accounts=False)
    te, ke = r.events["time"], r.events["kind"]
    end = m * orb.T
    n = int(np.sum(te <= end * (1 + 1e-3)))
    while n and ke[n - 1] == 1:
        n -= 1
    if n < 2 or ke[n - 1] != 2 or abs(te[n - 1] - end) > 0.05 * orb.T or np.any(ke[:n][0::2] != 1) or \
            np.any(ke[:n][1::2] != 2):
        return []
    d = np.diff(np.concatenate([[0.0], te[:n]]))
    dwell = tuple(bool(x > 1e-9 * orb.T) for x in d[0::2])
    sig = Signature(m, dwell)
    if sig == orb.sig:
        return []
    var = []
    for i, positive in enumerate(dwell):
        if positive:
            var.append(d[2 * i])
        var.append(d[2 * i + 1])
    var[-1] += end - te[n - 1]
    try:
        return [polish(prob, sig, orb.T, np.concatenate([orb.z0, var, [orb.phi]]))]
    except NotConverged:
        return []
