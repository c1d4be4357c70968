"""Floquet multipliers (plbar.stability) against finite differences and long simulations (FORMULATION §7)."""

import dataclasses

import numpy as np
import pytest

import plbar
from plbar.errors import InputError
from plbar.response import Orbits
from plbar.check import period_map, simulate
from plbar.response import Stability, monodromy, multipliers, periodic_state, stability

from shared_points import FE_POINT, good_points

RED = (1.7748, 8.1525)
GREEN = (2.3876, 9.8894)


def fd_jacobian(prob, T, phi, xr, vr, rel=1e-7):
    """Central finite differences of the one-period map in z = (x_r, v_r)."""
    z0 = np.r_[xr, vr]
    m = xr.size
    h = rel * np.linalg.norm(z0)
    J = np.zeros((2 * m, 2 * m))
    for j in range(2 * m):
        d = np.zeros(2 * m)
        d[j] = h
        zp = np.r_[period_map(prob, T, phi, *np.split(z0 + d, 2))]
        zm = np.r_[period_map(prob, T, phi, *np.split(z0 - d, 2))]
        J[:, j] = (zp - zm) / (2 * h)
    return J


def eig_distance(a, b):
    """Largest distance from an eigenvalue in ``a`` to its nearest one in ``b`` (both ways)."""
    d = np.abs(a[:, None] - b[None, :])
    return max(d.min(axis=1).max(), d.min(axis=0).max())


def test_multipliers_match_finite_differences(default_result):
    prob = default_result.prob
    pts = good_points(default_result, per_branch=2)
    assert len(pts) >= 8 and len({id(o) for o, _ in pts}) >= 4
    worst_J, worst_mu = 0.0, 0.0
    for orb, k in pts:
        o = orb.take([k])
        Phi = monodromy(o)[0]
        mu = multipliers(o)[0]
        xr, vr = periodic_state(o)
        J = fd_jacobian(prob, o.T[0], o.phi[0], xr[0], vr[0])
        worst_J = max(worst_J, np.abs(J - Phi).max() / np.abs(Phi).max())
        worst_mu = max(worst_mu, eig_distance(mu, np.linalg.eigvals(J)))
    assert worst_J < 1e-6
    assert worst_mu < 1e-6


def test_fe_p2_consistent_multipliers_match_finite_differences():
    res = plbar.solve(plbar.Case(**FE_POINT, signatures="paper"))
    prob = res.prob
    orb, k = good_points(res, per_branch=1, min_len=10)[0]
    o = orb.take([k])
    xr, vr = periodic_state(o)
    J = fd_jacobian(prob, o.T[0], o.phi[0], xr[0], vr[0])
    Phi = monodromy(o)[0]
    assert Phi.shape == (2 * (prob.system.n - 1),) * 2
    assert np.abs(J - Phi).max() / np.abs(Phi).max() < 1e-6
    assert eig_distance(multipliers(o)[0], np.linalg.eigvals(J)) < 1e-6


def test_shapes_sorting_and_tolerance(default_result):
    orb = default_result.paths.points()
    st = stability(orb)
    n1 = default_result.prob.system.n - 1
    assert isinstance(st, Stability)
    assert st.multipliers.shape == (len(orb), 2 * n1) and np.iscomplexobj(st.multipliers)
    a = np.abs(st.multipliers)
    assert np.all(np.diff(a, axis=1) <= 1e-12)
    assert np.array_equal(st.max_abs, a[:, 0])
    assert np.array_equal(st.stable, st.max_abs < 1 - 1e-9)
    assert np.array_equal(st.unstable, st.max_abs > 1 + 1e-9)
    assert st.stable.any() and st.unstable.any()
    loose = stability(orb, tol=0.05)
    assert loose.stable.sum() <= st.stable.sum() and loose.unstable.sum() <= st.unstable.sum()
    for bad in (-0.1, 1.0, "x"):
        with pytest.raises(InputError, match="tol = "):
            stability(orb, tol=bad)


def test_multipliers_do_not_depend_on_load_scale(default_result):
    """The map is affine in z and its linear part does not contain the load (FORMULATION §7)."""
    prob = default_result.prob
    orb = default_result.paths.points().take(np.arange(0, len(default_result.paths.points()), 25))
    p3 = dataclasses.replace(prob, q=3 * prob.q, f1=3 * prob.f1, f2=3 * prob.f2, r_q=3 * prob.r_q)
    o3 = Orbits(p3, orb.T1, orb.T2, orb.phi, 3 * orb.eta0, 3 * orb.v0, 3 * orb.eta_s, 3 * orb.v_s)
    assert np.allclose(monodromy(o3), monodromy(orb), rtol=1e-10, atol=1e-10)


def test_paper_points(default_result):
    """Not in the paper: the red point (path 1) is unstable, the green point (path 2) is stable."""
    orb = default_result.paths.points()
    st = stability(orb)
    d_red = np.hypot(orb.T1 - RED[0], orb.T2 - RED[1])
    d_green = np.hypot(orb.T1 - GREEN[0], orb.T2 - GREEN[1])
    red, green = np.argmin(d_red), np.argmin(d_green)
    assert d_red[red] < 0.03 and d_green[green] < 0.03
    # along the branches within 0.05 of the points: red 1.04 .. 1.075, green 0.992 .. 0.9992
    assert 1.03 < st.max_abs[red] < 1.10 and st.unstable[red]
    assert 0.99 < st.max_abs[green] < 0.9995 and st.stable[green]


def _strobe_distance(sim, z0):
    """Distance of the stroboscopic samples from the periodic start, relative (x all DOFs, v without v_c)."""
    z = np.c_[sim.strobe_x, sim.strobe_v[:, :-1]]
    return np.linalg.norm(z - np.r_[z0[: z0.size // 2], 0.0, z0[z0.size // 2:]], axis=1) / np.linalg.norm(z0)


@pytest.fixture(scope="module")
def extremes(default_result):
    """The most stable and the most unstable well-conditioned path points of the default case."""
    pts = good_points(default_result, per_branch=6)
    rho = np.array([stability(o.take([k])).max_abs[0] for o, k in pts])
    return pts[int(np.argmin(rho))], rho.min(), pts[int(np.argmax(rho))], rho.max()


def test_stable_orbit_attracts_unstable_repels(default_result, extremes):
    prob = default_result.prob
    (so, sk), rho_s, (uo, uk), rho_u = extremes
    assert rho_s < 0.97 and rho_u > 1.3
    rng = np.random.default_rng(1)
    for (orb, k), n_per, rho in (((so, sk), 400, rho_s), ((uo, uk), 100, rho_u)):
        xr, vr = periodic_state(orb.take([k]))
        z0 = np.r_[xr[0], vr[0]]
        d = rng.standard_normal(z0.size)
        d *= 1e-6 * np.linalg.norm(z0) / np.linalg.norm(d)
        z = z0 + d
        sim = simulate(prob, orb.T[k], orb.phi[k], z[: z.size // 2], z[z.size // 2:], n_periods=n_per)
        dist = _strobe_distance(sim, z0)
        if rho < 1:
            # back on the orbit: the perturbation decays roughly like rho^k
            assert dist[-1] < 1e-12 + 1e-6 * rho ** (0.8 * n_per)
            assert dist[-1] < 1e-9
            assert sim.strobe_state[-1] == 1
        else:
            # it leaves: the distance grows by four orders of magnitude (to O(1)) within the run
            assert dist.max() > 1e-2
            first = int(np.argmax(dist > 1e-4))
            assert 0 < first < 4 * np.log(1e2) / np.log(rho) + 10


def _similar(prob, Mp, Mm):
    """Physical (x_r, v_r) = (V1 eta, V1 etadot): Mm = C^-1 Mp C with C = diag(V1, V1)."""
    V1 = prob.system.V1
    n, m = V1.shape
    C = np.zeros((2 * n, 2 * m))
    C[:n, :m] = V1
    C[n:, m:] = V1
    return np.linalg.solve(C, Mp @ C)


@pytest.mark.parametrize("which", ["chain", "fe"])
def test_modal_monodromy_is_the_physical_one_in_modal_coordinates(default_result, fe_p2_coarse, which):
    """monodromy_modal (used for the multipliers; works for truncated models) vs the physical monodromy."""
    from plbar.response import monodromy_modal

    res = default_result if which == "chain" else fe_p2_coarse
    orb = res.paths.points()
    idx = np.linspace(0, len(orb) - 1, 60).astype(int)
    sub = orb.take(idx)
    Mp, Mm = monodromy(sub), monodromy_modal(sub)
    X = _similar(sub.prob, Mp, Mm)
    assert np.abs(X - Mm).max() <= 1e-8 * np.abs(Mm).max()


def test_truncated_model_multipliers_converge_to_the_full_ones():
    """With every mode kept the truncated path is the full one; with most modes the multipliers agree closely."""
    full = plbar.Case(model="fe", n=12, grid=(80, 80), signatures="paper")
    res = plbar.solve(full)
    b = max(res.paths.branches, key=len)
    k = len(b) // 2
    mu_full = b.stab.multipliers[k]
    prob_t = plbar.Case(model="fe", n=12, modes=11).problem()          # all modes of state I, 11 of 12 of state II
    o = plbar.orbits(prob_t, b.T1[k:k + 1], b.T2[k:k + 1], b.phi[k:k + 1])
    st = stability(o)
    assert st.multipliers.shape == (1, 2 * prob_t.system.w1.size)
    assert np.isfinite(st.max_abs).all()
    prob_all = plbar.Case(model="fe", n=12, modes=12).problem()        # = the full model
    o2 = plbar.orbits(prob_all, b.T1[k:k + 1], b.T2[k:k + 1], b.phi[k:k + 1])
    assert stability(o2).max_abs[0] == pytest.approx(b.stab.max_abs[k], rel=1e-9)
    assert eig_distance(stability(o2).multipliers[0], mu_full) < 1e-8 * np.abs(mu_full).max()
