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
from .solve import Orbit, NotConverged, orbit_at, polish

__all__ = ["zero_dwell", "doubled", "from_motion", "split"]


def zero_dwell(prob: Problem, T: float, sig: Signature = ZERO_DWELL) -> list[Orbit]:
    """The responses of class ``1Z`` at period ``T`` (both phase roots; checked, not yet for admissibility); with
    ``sig = plbar.periodic.ONE_REBOUND`` those of class ``1R`` (one rebound per period, restitution ``e > 0``: the same
    structure, the start state in state II)."""
    nz, q, nX = layout(prob, sig)
    T = float(T)
    base = np.zeros(nX)
    base[nz] = T
    ch0 = evaluate(prob, sig, T, base)                            # phi = 0, z0 = 0: the cos phi column, and d/dz0
    Xs = base.copy()
    Xs[-1] = 0.5 * np.pi
    ch1 = evaluate(prob, sig, T, Xs, jac=False)                  # phi = pi/2: the sin phi column
    rows = np.r_[0, np.arange(2, 2 + nz)]                         # impact residual and periodicity
    A = ch0.J[rows][:, :nz]                                       # d/dz0 of both (affine in z0)
    cc, cs = ch0.F[rows], ch1.F[rows]
    c0 = np.zeros_like(cc)
    if prob.affine:                                # a gap or a constant load adds a constant (phi = pi: c0 - cos)
        Xs[-1] = np.pi
        c0 = 0.5 * (cc + evaluate(prob, sig, T, Xs, jac=False).F[rows])
        cc, cs = cc - c0, cs - c0
    try:
        Zc = np.linalg.solve(A[1:], -cc[1:])
        Zs = np.linalg.solve(A[1:], -cs[1:])
        Z0 = np.linalg.solve(A[1:], -c0[1:])
    except np.linalg.LinAlgError:
        return []
    a = A[0] @ Zc + cc[0]
    b = A[0] @ Zs + cs[0]
    out = []
    for phi in _phase_roots(A[0] @ Z0 + c0[0], a, b):
        X = np.concatenate([Z0 + Zc * np.cos(phi) + Zs * np.sin(phi), [T, phi]])
        orb = orbit_at(prob, sig, T, X)
        if orb.residual <= 1e-9:
            out.append(orb)
    return out


def _phase_roots(a0: float, a: float, b: float) -> np.ndarray:
    """The phases in ``[0, 2 pi)`` where ``a0 + a cos phi + b sin phi = 0``: two (one at a tangency), none where
    ``|a0| > hypot(a, b)`` (the force cannot reach the stop).  ``a0 = 0`` (no gap): ``phi`` and ``phi + pi``."""
    if a0 == 0.0:
        return np.mod(np.arctan2(-a, b) + np.array([0.0, np.pi]), 2 * np.pi)
    rho = np.hypot(a, b)
    if abs(a0) > rho:
        return np.zeros(0)
    half = np.arccos(-a0 / rho)
    return np.mod(np.arctan2(b, a) + np.array([half, -half]), 2 * np.pi)


def doubled(prob: Problem, orb: Orbit, steps=(1e-3, 3e-3, 1e-2, 3e-2)) -> list[Orbit]:
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


def from_motion(prob: Problem, r, b: int, m: int, k: int = 0) -> Orbit:
    """Polish a periodic motion of a simulation into an exact orbit.

    The motion is trajectory ``b`` of the run ``r`` (a :class:`plbar.motion.Run` of ``prob``) from its recorded
    period boundary ``k`` on (``t_b = (r.periods - r.record + k) T``), an orbit of ``m`` forcing periods: its state
    at ``t_b`` (``r.strobe_x, r.strobe_v``, physical, contact DOF last; ``r.strobe_state``: 0 stuck, 1 free) and its
    switches after it (``r.events``: 1 opening, 2 impact, 3 rebound, 4 the impact that ends a chattering sequence:
    the simulator's kinds), which must cover the first impact after ``t_b`` and ``m`` periods beyond.  The state is
    carried by the exact flows to that impact, the orbit's ``t = 0``; the switches of the next ``m`` periods give
    the signature and the durations; Newton polishes (:func:`polish`).  Raises :class:`NotConverged` or
    ``ValueError``.
    """
    T, phi = float(r.T[b]), float(r.phi[b])
    t_b = (r.periods - r.record + k) * T
    x_b, v_b, state_b = r.strobe_x[b, k], r.strobe_v[b, k], int(r.strobe_state[b, k])
    ev = r.events[r.events["traj"] == b]
    ev = ev[ev["time"] >= t_b]                       # the switches after t_b
    times, kinds = np.asarray(ev["time"], float), np.asarray(ev["kind"], int)
    sy = prob.system
    M = np.asarray(sy.M, float)
    W = 2 * np.pi / T
    if state_b == 0:
        z = np.concatenate([sy.V1.T @ M[:-1, :-1] @ x_b[:-1], sy.V1.T @ M[:-1, :-1] @ v_b[:-1]])
    else:
        z = np.concatenate([sy.V2.T @ M @ x_b, sy.V2.T @ M @ v_b])
    s, t = (1 if state_b == 0 else 2), float(t_b)
    imp = np.flatnonzero(kinds >= 2)                  # impacts: plastic (2), rebound (3), sticking after rebounds (4)
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
    closing = np.flatnonzero((kinds_after == 3) == (kinds[imp[0]] == 3))
    closing = closing[kinds_after[closing] >= 2]
    if not closing.size:
        raise ValueError("no impact of the first one's kind after it")
    # the orbit closes on the impact nearest to m T later: a motion still settling on its orbit repeats only
    # nearly, its closing impact a little before or after (a fixed window would cut or add a pair)
    j = int(closing[np.argmin(np.abs(after[closing] - end))])
    if abs(after[j] - end) > 0.05 * T:
        raise ValueError(f"no impact within 0.05 T of m T = {m} T after the first one: not an orbit of m periods")
    n = j + 1
    seq_t, seq_k = np.concatenate([[t_imp], after[:n]]), np.concatenate([[kinds[imp[0]]], kinds_after[:n]])
    sig, var = _pairs(seq_t, seq_k, T, m)
    var[-1] += end - seq_t[-1]                    # the sum is m T exactly
    return polish(prob, sig, T, np.concatenate([z, var, [np.mod(phi - W * t_imp, 2 * np.pi)]]))


def _pairs(seq_t, seq_k, T: float, m: int) -> tuple[Signature, list]:
    """The signature and the unknown durations of a switch sequence that starts and ends with an impact.

    ``seq_t, seq_k``: times and the simulator's kinds (1 opening, 2 impact, 3 rebound, 4 sticking impact); each
    impact begins a pair: a rebound the free phase at once (``R``), a sticking impact a stuck phase ended by an
    opening (``P``, or ``Z`` where the opening is at once).  Raises ``ValueError`` on any other sequence.
    """
    n = len(seq_t) - 1
    dwell, rebound, var = [], [], []
    i = 0
    while i < n:                                     # one pair per impact: what follows it, then the free phase
        if seq_k[i] == 3:                            # a rebound: the free phase at once
            if seq_k[i + 1] < 2:
                raise ValueError("an opening after a rebound")
            dwell.append(False)
            rebound.append(True)
            var.append(seq_t[i + 1] - seq_t[i])
            i += 1
        else:                                        # the contact sticks: an opening, then the free phase
            if i + 2 > n or seq_k[i + 1] != 1 or seq_k[i + 2] < 2:
                raise ValueError("the switches after a sticking impact are not an opening and an impact")
            positive = bool(seq_t[i + 1] - seq_t[i] > 1e-9 * T)
            dwell.append(positive)
            rebound.append(False)
            if positive:
                var.append(seq_t[i + 1] - seq_t[i])
            var.append(seq_t[i + 2] - seq_t[i + 1])
            i += 2
    if i != n:
        raise ValueError("the switches do not end with an impact")
    return Signature(int(m), tuple(dwell), tuple(rebound)), var


def _carry(prob, s, z, W, t, tau, phi):
    from ..response import segment

    from .chain import state_data

    w, f, _, _, zeta, _ = state_data(prob, s)
    m = w.size
    e, v = segment(w, f, W, t, tau, z[:m], z[m:], np.cos(phi), np.sin(phi), zeta=zeta)
    return np.concatenate([e, v])


def _switch(prob, z, kind):
    from .chain import rebound_map, switch_maps

    E, G = switch_maps(prob)
    if kind == 1:
        return E @ z, 2
    if kind == 3:
        return rebound_map(prob) @ z, 2
    return G @ z, 1


def split(prob: Problem, orb: Orbit) -> list[Orbit]:
    """The orbit of the signature the bar follows from ``orb``'s state when ``orb`` is not admissible.

    Replays ``orb`` (its state just after its last impact, its load phase) with the certified simulator
    for ``m`` periods; the switches met, one more pair where the orbit switched prematurely, are the
    guess; Newton polishes.  Empty if the replay does not end with an impact near ``m T``, or Newton fails.
    """
    from ..motion import Start, padded, run
    from .verify import start_of

    pad = padded(prob)
    state, eta, vel = start_of(orb, pad.m)
    m = orb.sig.m
    r = run(pad, [orb.T], [orb.phi], m + 1, m + 1, Start(np.array([state]), eta[None], vel[None]), accounts=False)
    te, ke = r.events["time"], r.events["kind"]
    end = m * orb.T
    n = int(np.sum(te <= end * (1 + 1e-3)))
    while n and ke[n - 1] == 1:
        n -= 1
    if n < 1 or ke[n - 1] < 2 or (ke[n - 1] == 3) != orb.free_start or abs(te[n - 1] - end) > 0.05 * orb.T:
        return []
    try:
        sig, var = _pairs(np.concatenate([[0.0], te[:n]]), np.concatenate([[3 if orb.free_start else 2], ke[:n]]),
                          orb.T, m)
    except ValueError:
        return []
    if sig == orb.sig:
        return []
    var[-1] += end - te[n - 1]
    try:
        return [polish(prob, sig, orb.T, np.concatenate([orb.z0, var, [orb.phi]]))]
    except NotConverged:
        return []
