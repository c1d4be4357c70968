"""The simulator with Rayleigh damping (issue 21): its own damped flow, reaction and energy budget.

The simulator builds ``C = alpha M + beta K`` from ``prob.system.alpha, beta`` itself and integrates
each mode as steady state plus free decay (:mod:`plbar.check.viscous`), independently of
:mod:`plbar.response`; its budget is ``work = impact losses + viscous loss + change of energy``.
"""

import dataclasses

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import plbar
from plbar.check import simulate
from plbar.check.viscous import damped_flow, modal_ratios

ODE = dict(method="DOP853", rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("z", [0.0, 0.03, 0.7, 1.0, 1.0 + 1e-10, 1.6, 25.0])
@pytest.mark.parametrize("W", [0.8, 1.2])
def test_damped_flow_against_solve_ivp(z, W):
    if z == 0.0 and W == 1.2:
        with pytest.raises(plbar.InputError, match="resonance"):
            damped_flow(np.array([1.2]), np.array([0.0]), np.array([1.0]), W, 0.0, 1.0, np.zeros(1), np.zeros(1))
        return
    w, f, theta = np.array([1.2]), np.array([0.9]), 0.4
    taus = np.linspace(0, 6.0, 13)[1:]
    e, v = damped_flow(w, np.array([z]), f, W, theta, taus, np.array([0.2]), np.array([-0.5]))
    rhs = lambda t, y: [y[1], -1.44 * y[0] - 2 * z * 1.2 * y[1] + 0.9 * np.cos(W * t + theta)]  # noqa: E731
    ref = solve_ivp(rhs, (0, 6.0), [0.2, -0.5], t_eval=taus, **ODE).y
    scale = np.abs(ref).max()
    assert np.abs(e[:, 0] - ref[0]).max() < 1e-10 * scale and np.abs(v[:, 0] - ref[1]).max() < 1e-10 * scale


def test_modal_ratios_are_rayleigh(damped_fe_result):
    """The simulator's own ratios diag(V^T C V) / (2 w) are the system's alpha / (2 w) + beta w / 2."""
    s = damped_fe_result.prob.system
    assert np.allclose(modal_ratios(s.C, s.V2, s.w2), s.zeta2, rtol=1e-12, atol=0)
    assert np.allclose(modal_ratios(s.C[:-1, :-1], s.V1, s.w1), s.zeta1, rtol=1e-12, atol=0)
    off = s.V2.T @ s.C @ s.V2 - np.diag(2 * s.zeta2 * s.w2)
    assert np.abs(off).max() < 1e-12 * np.abs(s.C).max()


def test_damped_free_vibration_loses_exactly_the_viscous_and_impact_losses(damped_result):
    prob = damped_result.prob
    n = prob.system.n
    free = dataclasses.replace(prob, q=np.zeros(n), f1=np.zeros(n - 1), f2=np.zeros(n), r_q=0.0)
    orb = damped_result.paths.points()
    xr, vr = plbar.response.periodic_state(orb.take([10]))
    sim = simulate(free, 10.0, 0.3, xr[0], vr[0], n_periods=6)
    assert sim.work == 0.0 and sim.viscous > 0 and sim.impact_times.size >= 2
    assert abs(sim.energy_residual) < 1e-10 * sim.energy0


def test_damped_forced_budget_and_settling(damped_result):
    """From rest, 60 periods: the budget with the viscous loss closes; the motion settles on the periodic one."""
    prob = damped_result.prob
    b = max(damped_result.branches, key=len)
    k = int(np.argmin(b.max_abs_multiplier))
    T, phi = float(b.T[k]), float(b.phi[k])
    n = prob.system.n
    sim = simulate(prob, T, phi, np.zeros(n), np.zeros(n), n_periods=60.5, t0=0.7)
    assert sim.viscous > 0 and sim.impact_losses.sum() > 0
    assert abs(sim.energy_residual) < 1e-9 * sim.work


def test_reaction_has_its_damper_part():
    """Lumped chain: R = r_eta . eta + r_v . eta' + r_q cos with r_v = beta r_eta (M_cr = 0)."""
    prob = plbar.Case(rayleigh=(0.01, 0.05)).problem()
    s = prob.system
    assert np.allclose(s.r_v, 0.05 * s.r_eta, rtol=1e-13, atol=0)
    fe = plbar.Case(model="fe", n=5, element="P2", mass="consistent", rayleigh=(0.01, 0.05)).problem().system
    Mc = fe.M[-1, :-1] @ fe.V1
    assert np.allclose(fe.r_v, (fe.C[-1, :-1] @ fe.V1) - 2 * Mc * fe.zeta1 * fe.w1, rtol=1e-12, atol=1e-14)
    assert np.abs(fe.r_v).max() > 0
    und = plbar.Case().problem().system
    assert not und.damped and np.all(und.r_v == 0) and np.all(und.zeta1 == 0) and und.zeta == (None, None)
