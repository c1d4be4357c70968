"""A gap or an interference at the stop in the simulator (issue 41 item 1), checked by an integrator written here.

* the real motion from rest with a clearance (``d > 0``: it starts free) and an interference (``d < 0``: it
  starts held, in the static equilibrium against the stop) against scipy's ``solve_ivp`` with events on the
  structure's own equations (``M x'' + K x = q cos(W t)``, the stop at ``x_c = d`` held by a Lagrange multiplier,
  the plastic impact ``v -> v - M^-1 r (r . v) / (r M^-1 r)``): every event time to 1e-9, for the paper's chain
  (lumped) and an FE bar with a consistent mass (the impact then moves every DOF);
* the energy budget (the mechanical energy ``v M v / 2 + x K x / 2``, with the held state's static energy) to
  1e-12 of the work, and the impact losses against the integrator's;
* homogeneity (FORMULATION §9): ``(lambda d, lambda q)`` is ``lambda`` times the motion of ``(d, q)``: the same
  events, the states scaled, to 1e-12;
* ``d = 0`` is the paper's simulator bit for bit.
"""

from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import plbar
from plbar.errors import InputError
from plbar.motion import padded, run
from plbar.motion.kernel import data as D


def _gapped(case: plbar.Case, d: float, scale: float = 1.0) -> plbar.Problem:
    st = case.problem().structure
    return plbar.problem(replace(st, gap=d, q=st.q * scale, origin=None))


def _phase(rhs, g, t, z, t_end, chunk):
    """Integrate ``rhs`` from ``(t, z)`` until ``g`` first rises through 0 (or ``t_end``): ``(t, z, hit)``.

    Each step of the dense output is scanned at 64 points (solve_ivp's own events see only a step's ends, and a
    flight that starts at the stop, ``g = 0``, and returns within one step would go unseen); the crossing is
    then a root of the dense output, and the state there is integrated to it again from the phase's start."""
    from scipy.optimize import brentq

    opts = dict(rtol=1e-13, atol=1e-14, method="DOP853")
    t0, z0 = t, z
    while t < t_end:
        b = min(t + chunk, t_end)
        sol = solve_ivp(rhs, (t, b), z, dense_output=True, **opts)
        grid = np.concatenate([np.linspace(sol.t[i], sol.t[i + 1], 65)[1:] for i in range(sol.t.size - 1)])
        gv = g(grid, sol.sol(grid))
        up = np.flatnonzero((gv[1:] >= 0) & (gv[:-1] < 0))
        if up.size:
            te = brentq(lambda u, s=sol: g(u, s.sol(u)), grid[up[0]], grid[up[0] + 1], xtol=1e-15, rtol=1e-15)
            return te, solve_ivp(rhs, (t0, te), z0, **opts).y[:, -1], True
        t, z = b, sol.y[:, -1]
    return t_end, solve_ivp(rhs, (t0, t_end), z0, **opts).y[:, -1], False


def ivp_events(st: plbar.Structure, T: float, t_end: float, start_free: bool):
    """``(times, kinds, losses, x_end)`` of the structure from rest, event-driven with solve_ivp (DOP853)."""
    M, K, r, q, d = st.M, st.K, st.contact, st.q, st.gap
    Mi, n, W = np.linalg.inv(M), M.shape[0], 2 * np.pi / T
    rMr = r @ Mi @ r

    def lam(t, x):                       # the stop's force holding u'' = 0: M x'' = f + r lam (t, x vectorised)
        return -(r @ Mi @ (np.multiply.outer(q, np.cos(W * t)) - K @ x)) / rMr

    def stuck(t, z):
        return np.concatenate([z[n:], Mi @ (q * np.cos(W * t) - K @ z[:n] + r * lam(t, z[:n]))])

    def free(t, z):
        return np.concatenate([z[n:], Mi @ (q * np.cos(W * t) - K @ z[:n])])

    if start_free:
        x0 = np.zeros(n)
    else:                                # held at u = d: K x = r lam with r . x = d
        Ki = np.linalg.inv(K)
        x0 = Ki @ r * (d / (r @ Ki @ r))
    z, t, free_now = np.concatenate([x0, np.zeros(n)]), 0.0, start_free
    times, kinds, losses = [], [], []
    while t < t_end:
        if not free_now and lam(t, z[:n]) > 0:
            free_now = True              # a zero dwell: the reaction pulls at once
            times.append(t), kinds.append(D.OPENS), losses.append(0.0)
            continue
        if free_now:
            t, z, hit = _phase(free, lambda u, y: r @ y[:n] - d, t, z, t_end, T / 4)
        else:
            t, z, hit = _phase(stuck, lambda u, y: lam(u, y[:n]), t, z, t_end, T / 4)
        if not hit:
            break
        if free_now:
            v = z[n:]
            vp = v - Mi @ r * (r @ v) / rMr
            losses.append(0.5 * v @ M @ v - 0.5 * vp @ M @ vp)
            z = np.concatenate([z[:n], vp])
            times.append(t), kinds.append(D.IMPACT)
        else:
            times.append(t), kinds.append(D.OPENS), losses.append(0.0)
        free_now = not free_now
    return np.array(times), np.array(kinds), np.array(losses), z[:n]


CASES = {"chain": plbar.Case(), "fe consistent": plbar.Case(model="fe", n=6, element="P1", mass="consistent")}


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("d", [0.4, -0.3])
def test_the_motion_with_a_gap_is_the_integrators(name, d):
    case = CASES[name]
    prob = _gapped(case, d * (1.0 if name == "chain" else 0.05))
    pad = padded(prob)
    T, periods = 9.3, 12
    r = run(pad, np.array([T]), 0.0, periods, periods)
    assert r.status[0] == 0
    st = prob.structure
    times, kinds, losses, x_end = ivp_events(st, T, periods * T, start_free=prob.gap > 0)
    assert pad.rest_state == (1 if prob.gap > 0 else 0)
    ev = r.events
    assert ev.size == times.size > 10
    assert np.array_equal(ev["kind"], kinds)
    assert np.max(np.abs(ev["time"] - times)) < 1e-9
    assert np.max(np.abs(ev["loss"] - losses)) < 1e-9 * max(losses.max(), 1e-300)
    assert np.max(np.abs(r.strobe_x[0, -1] - x_end)) < 1e-8 * np.abs(x_end).max()
    assert abs(r.energy_residual[0]) < 1e-12


def test_a_gap_scales_with_the_load():
    """Homogeneity: the motion of ``(lambda d, lambda q)`` is ``lambda`` times that of ``(d, q)`` (40 periods from
    rest: over longer windows an irregular motion amplifies the round-off); bit for bit for a power of 2."""
    T = np.linspace(6.0, 13.0, 8)
    for d in (0.5, -0.5):
        a = run(padded(_gapped(plbar.Case(), d)), T, 0.0, 40, 40)
        for lam in (0.01, 4.0, 7.0):
            b = run(padded(_gapped(plbar.Case(), lam * d, lam)), T, 0.0, 40, 40)
            assert np.array_equal(a.events["kind"], b.events["kind"])
            assert np.max(np.abs(a.events["time"] - b.events["time"])) < 1e-12 * T.max() * 40
            assert np.max(np.abs(lam * a.strobe_x - b.strobe_x)) < 1e-12 * lam * np.abs(a.strobe_x).max()
            assert np.max(np.abs(b.loss - lam ** 2 * a.loss)) < 1e-12 * lam ** 2 * a.loss.max()
            if lam == 4.0:
                assert np.array_equal(a.events["time"], b.events["time"]) and np.array_equal(4 * a.strobe_x,
                                                                                              b.strobe_x)


def test_zero_gap_is_the_paper_bit_for_bit():
    T = np.linspace(6, 14, 9)
    a = run(padded(plbar.Case().problem()), T, 0.0, 300, 20)
    b = run(padded(_gapped(plbar.Case(), 0.0)), T, 0.0, 300, 20)
    for k in ("loss", "strobe_x", "strobe_v", "d_eq", "amp", "energy_end"):
        assert np.array_equal(getattr(a, k), getattr(b, k))
    for k in ("time", "kind", "loss"):
        assert np.array_equal(a.events[k], b.events[k])


def test_a_gap_is_checked():
    st = plbar.Case().problem().structure
    for bad in (float("nan"), "0.1", None, float("inf")):
        with pytest.raises(InputError, match="gap"):
            replace(st, gap=bad)
