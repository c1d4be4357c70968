"""Periodic responses with Rayleigh damping (issue 21): every path point checked independently.

* the event-driven simulator (its own damped flow, reaction and switches) started from the state
  switches only at T^I and T and comes back to the start (1e-9), and its energy budget with the
  viscous loss closes (1e-9);
* the work of the load over a period equals the impact loss plus the viscous loss (1e-9), and the
  closed-form viscous loss equals the simulator's quadrature (1e-9);
* Floquet multipliers against finite differences of the simulator's one-period map (1e-6);
* the zero-damping limit reproduces the undamped responses (1e-12).
"""

import numpy as np
import pytest

import plbar
from plbar.check import simulate
from plbar.periodic import multipliers
from plbar.response import check, orbits, periodic_state
from plbar.response import work_quadrature


def _cases(request):
    return [request.getfixturevalue("damped_result"), request.getfixturevalue("damped_fe_result")]


@pytest.fixture(params=["chain", "fe"])
def res(request):
    return request.getfixturevalue("damped_result" if request.param == "chain" else "damped_fe_result")


def test_damped_cases_have_branches(damped_result, damped_fe_result):
    for r in (damped_result, damped_fe_result):
        s = r.prob.system
        assert s.damped and len(r.paths.branches) >= 2 and sum(len(b) for b in r.paths.branches) > 150
        assert np.all(s.zeta1 > 0) and np.all(s.zeta2 > 0)


def test_every_damped_response_is_verified_by_the_simulator(res):
    """Events at T^I and T only, back to the start after one period; the energy budget with the viscous loss."""
    prob = res.prob
    orb = res.paths.points()
    d = plbar.damping(orb)
    xr, vr = periodic_state(orb)
    worst = dict(events=0.0, back=0.0, budget=0.0, viscous=0.0)
    for k in range(len(orb)):
        sim = simulate(prob, orb.T[k], orb.phi[k], xr[k], vr[k], n_periods=1.0)
        assert list(sim.events["kind"]) == [plbar.check.OPEN, plbar.check.IMPACT]
        worst["events"] = max(worst["events"], abs(sim.events["time"][0] - orb.T1[k]) / orb.T[k],
                              abs(sim.events["time"][1] - orb.T[k]) / orb.T[k])
        z0 = np.r_[xr[k], vr[k]]
        worst["back"] = max(worst["back"], np.abs(np.r_[sim.x[:-1], sim.v[:-1]] - z0).max() / np.abs(z0).max())
        worst["budget"] = max(worst["budget"], abs(sim.energy_residual) / sim.work)
        worst["viscous"] = max(worst["viscous"], abs(sim.viscous - d.viscous[k]) / d.viscous[k])
        assert abs(sim.impact_losses[0] - d.dPL[k]) < 1e-9 * sim.work
    assert worst["events"] < 1e-9 and worst["back"] < 1e-9, worst
    assert worst["budget"] < 1e-9 and worst["viscous"] < 1e-9, worst


def test_work_equals_impact_plus_viscous_loss(res):
    orb = res.paths.points()
    d = plbar.damping(orb)
    w = work_quadrature(orb)
    assert np.all(d.viscous > 0) and np.all(d.dPL > 0)
    assert np.abs(w - d.dPL - d.viscous).max() < 1e-9 * np.abs(w).max()
    # the two losses per branch, as written to paths.csv
    for b in res.paths.branches:
        assert np.array_equal(b.viscous, b.damping.viscous) and np.array_equal(b.xi_total, b.damping.xi_total)


def test_residuals_periodicity_and_admissibility(res):
    orb = res.paths.points()
    r1, r2 = orb.residuals()
    e, v = orb.state_I(orb.T1[:, None])
    s = orb.prob.system
    sc1 = np.linalg.norm(s.r_eta) * np.abs(e).max() + np.linalg.norm(s.r_v) * np.abs(v).max() + abs(orb.prob.r_q)
    assert np.abs(r1).max() < 1e-9 * sc1
    assert np.abs(r2).max() < 1e-9 * np.abs(orb.eta_s).max()
    ep, vp = orb.after_impact()
    z0, z1 = np.c_[orb.eta0, orb.v0], np.c_[ep, vp]
    assert np.abs(z1 - z0).max() < 1e-10 * np.abs(z0).max()
    assert check(orb).ok.all()


def test_rayleigh_ratio_and_total(damped_result):
    """zeta(W) = alpha / (2 W) + beta W / 2 (2 % at T = 8 and 12 by construction); xi_total = zeta(W) + xi_eq."""
    s = damped_result.prob.system
    for T in (8.0, 12.0):
        assert abs(s.rayleigh_ratio(2 * np.pi / T) - 0.02) < 1e-15
    for b in damped_result.paths.branches:
        W = 2 * np.pi / b.T
        assert np.allclose(b.damping.zeta_rayleigh, s.alpha / (2 * W) + s.beta * W / 2, rtol=1e-15, atol=0)
        assert np.allclose(b.xi_total, b.damping.zeta_rayleigh + b.xi, rtol=1e-15, atol=0)


def test_damped_multipliers_match_finite_differences(res):
    prob = res.prob
    orb = res.paths.points()
    from test_stability import core_monodromy, eig_distance, fd_jacobian

    worst_J = worst_mu = 0.0
    for k in np.linspace(0, len(orb) - 1, 6).astype(int):
        o = orb.take([k])
        M, Phi = core_monodromy(prob, orb, k)
        xr, vr = periodic_state(o)
        J = fd_jacobian(prob, o.T[0], o.phi[0], xr[0], vr[0])
        worst_J = max(worst_J, np.abs(J - Phi).max() / np.abs(Phi).max())
        worst_mu = max(worst_mu, eig_distance(multipliers(M), np.linalg.eigvals(J)))
    assert worst_J < 1e-6 and worst_mu < 1e-6


def test_damping_pulls_the_multipliers_inwards(damped_result, default_result):
    """A stable damped response attracts a perturbed start; damping shrinks the spectral radius."""
    prob = damped_result.prob
    i = max(range(len(damped_result.paths.branches)), key=lambda j: len(damped_result.paper[j]))   # the scan's
    b = damped_result.paper[i]
    k = int(np.argmin(b.max_abs_multiplier))
    o = damped_result.paths.branches[i].orbits.take([k])
    rho = float(b.max_abs_multiplier[k])
    assert rho < 0.9
    xr, vr = periodic_state(o)
    z0 = np.r_[xr[0], vr[0]]
    d = np.random.default_rng(2).standard_normal(z0.size)
    z = z0 + 1e-6 * np.linalg.norm(z0) * d / np.linalg.norm(d)
    sim = simulate(prob, o.T[0], o.phi[0], z[: z.size // 2], z[z.size // 2:], n_periods=200)
    dist = np.linalg.norm(np.c_[sim.strobe_x[:, :-1], sim.strobe_v[:, :-1]] - z0, axis=1) / np.linalg.norm(z0)
    assert dist[-1] < 1e-12 + 1e-6 * rho ** 150
    # the same (T1, T2, phi) without damping is not periodic, but its monodromy's radius is larger
    from test_stability import core_monodromy

    und = orbits(default_result.prob, o.T1, o.T2, o.phi)
    assert np.abs(multipliers(core_monodromy(default_result.prob, und, 0)[0])).max() > rho


def test_find_response_with_damping(res):
    prob = res.prob
    orb = res.paths.points()
    d = plbar.damping(orb)
    for k in np.linspace(0, len(orb) - 1, 12).astype(int):
        r = plbar.find_response(prob, float(orb.T[k]), float(orb.T1[k]) * 1.001)
        assert abs(r.T1 - orb.T1[k]) < 1e-10 * orb.T[k]
        assert abs(np.angle(np.exp(1j * (r.phi - orb.phi[k])))) < 1e-9
        assert abs(r.xi - d.xi[k]) < 1e-10 * d.xi[k] and abs(r.dPL - d.dPL[k]) < 1e-10 * d.dPL[k]
        assert abs(r.viscous - d.viscous[k]) < 1e-10 * d.viscous[k]
        assert abs(r.xi_total - d.xi_total[k]) < 1e-10
        assert max(r.e1, r.e2, r.periodicity) < 1e-12


def test_zero_damping_limit_reproduces_the_undamped_responses(default_result):
    """The damped code path with alpha = beta = 1e-300 (every zeta ~ 1e-300) against the undamped one: 1e-12 (the
    multipliers 1e-11)."""
    und = default_result.prob
    tiny = plbar.Case(rayleigh=(1e-300, 1e-300)).problem()
    assert tiny.system.damped and not und.system.damped
    orb = default_result.paths.points()
    o2 = orbits(tiny, orb.T1, orb.T2, orb.phi)
    for a, b in ((orb.eta0, o2.eta0), (orb.v0, o2.v0), (orb.eta_s, o2.eta_s), (orb.v_s, o2.v_s)):
        assert np.abs(a - b).max() < 1e-12 * np.abs(a).max()
    d1, d2 = plbar.damping(orb), plbar.damping(o2)
    assert np.abs(d1.xi - d2.xi).max() < 1e-12 * d1.xi.max()
    assert np.abs(d1.dPL - d2.dPL).max() < 1e-12 * d1.dPL.max()
    assert np.abs(d2.viscous).max() < 1e-290
    co1 = plbar.response.coefficients(und, orb.T1, orb.T2)
    co2 = plbar.response.coefficients(tiny, orb.T1, orb.T2)
    assert np.abs(co1.G - co2.G).max() < 1e-12
    from test_stability import core_monodromy

    # saltation ~ 1 / v_c amplifies round-off near grazing; elsewhere the two code paths differ by the round-off of
    # the eigenvalues of a 10 x 10 product (1.1e-12 at the end of a branch, T = 9.774, with numpy 2.4 / scipy 1.17)
    graze = np.concatenate([b.grazing for b in default_result.paths.branches])
    d = np.array([np.abs(np.abs(multipliers(core_monodromy(und, orb, k)[0]))
                         - np.abs(multipliers(core_monodromy(tiny, o2, k)[0]))).max()
                  for k in range(0, len(orb), 7)])
    assert d[~graze[::7]].max() < 1e-11 and d.max() < 1e-8
    assert plbar.Case(rayleigh=(0, 0)).rayleigh is None and not plbar.Case(rayleigh=(0.0, 0.0)).problem().system.damped


def test_xi_eq_is_invariant_to_the_load_amplitude_with_damping(damped_result):
    orb = damped_result.paths.points()
    ab = damped_result.case.rayleigh
    p3 = plbar.Case(load_nodes=((1, 3.0),), rayleigh=ab).problem()
    o3 = orbits(p3, orb.T1, orb.T2, orb.phi)
    d1, d3 = plbar.damping(orb), plbar.damping(o3)
    assert np.allclose(d3.xi, d1.xi, rtol=1e-12, atol=0)
    assert np.allclose(d3.dPL, 9 * d1.dPL, rtol=1e-12, atol=0)
    assert np.allclose(d3.viscous, 9 * d1.viscous, rtol=1e-12, atol=0)


@pytest.mark.parametrize("rayleigh", [(0.05, 0.01), (0.1, 0.3), (1e-5, 1e-6)])
def test_damped_signals_equal_the_modal_flows(rayleigh):
    """Orbits' reaction and gap signals (free decay + one summed steady harmonic) = the mode-by-mode flow."""
    prob = plbar.Case(model="fe", n=6, element="P2", mass="consistent", load_points=((0.37, 1.0),),
                      rayleigh=rayleigh).problem()
    s = prob.system
    rng = np.random.default_rng(0)
    T = np.r_[rng.uniform(0.5, 3.0, 40), 2 * np.pi / s.w2[:3], 2 * np.pi / s.w1[:3]]   # some at resonance
    T1 = T * rng.uniform(0.1, 0.6, T.size)
    orb = orbits(prob, T1, T - T1, rng.uniform(0, 2 * np.pi, T.size))
    tI = orb.T1[:, None] * np.linspace(0, 1, 33)
    e, v = orb.state_I(tI)
    R = e @ s.r_eta + v @ s.r_v + prob.r_q * np.cos(orb.W[:, None] * tI - orb.phi[:, None])
    assert np.abs(orb.reaction_margin(tI) + R).max() < 1e-12 * np.abs(R).max()
    tII = orb.T2[:, None] * np.linspace(0, 1, 33)
    e, v = orb.state_II(tII)
    xc, vc = orb.gap_signals(tII)
    assert np.abs(xc - e @ s.gap_row).max() < 1e-12 * np.abs(xc).max()
    assert np.abs(vc - v @ s.gap_row).max() < 1e-12 * np.abs(vc).max()
