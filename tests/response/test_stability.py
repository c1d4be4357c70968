"""Floquet multipliers of the paper's class (the periodic core's, :mod:`plbar.periodic.floquet`) against finite
differences of the independent simulator's one-period map and long simulations (FORMULATION §7)."""

import dataclasses

import numpy as np
import pytest

import plbar
from plbar.check import period_map, simulate
from plbar.periodic import PAPER, monodromy, multipliers, orbit_at
from plbar.response import Orbits, periodic_state

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


def core_monodromy(prob, orb, k):
    """The periodic core's monodromy of the paper's point ``k`` of ``orb``, in physical ``(x_r, v_r)``: the chain's
    is in the state I modal coordinates ``(eta, eta')``, ``x_r = V1 eta``."""
    X = np.r_[orb.eta0[k], orb.v0[k], orb.T1[k], orb.T2[k], orb.phi[k]]
    o = orbit_at(prob, PAPER, float(orb.T[k]), X)
    M = monodromy(prob, PAPER, o.T, o.phi, o.chain)
    V1 = prob.system.V1
    if V1.shape[0] != V1.shape[1]:
        return M, M
    C = np.kron(np.eye(2), V1)
    return M, C @ M @ np.linalg.inv(C)


def test_multipliers_match_finite_differences(default_result):
    prob = default_result.prob
    pts = good_points(default_result, per_branch=2)
    assert len(pts) >= 8 and len({id(o) for o, _ in pts}) >= 4
    worst_J, worst_mu = 0.0, 0.0
    for orb, k in pts:
        o = orb.take([k])
        M, Phi = core_monodromy(prob, orb, k)
        mu = multipliers(M)
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
    M, Phi = core_monodromy(prob, orb, k)
    assert Phi.shape == (2 * (prob.system.n - 1),) * 2
    assert np.abs(J - Phi).max() / np.abs(Phi).max() < 1e-6
    assert eig_distance(multipliers(M), np.linalg.eigvals(J)) < 1e-6


def test_the_verdict_and_the_events_of_the_paper_class(default_result):
    """``stable`` is ``max |mu| < 1 - 1e-9`` of the core's multipliers; both kinds occur; each change of the
    verdict along a branch is an event of the periodic core at that point."""
    prob = default_result.prob
    kinds = set()
    for b in default_result.paper:
        np.testing.assert_array_equal(b.stable, b.max_abs_multiplier < 1 - 1e-9)
        for i in range(0, len(b), max(1, len(b) // 3)):
            o = b.orbits[i]
            mu = multipliers(monodromy(prob, PAPER, o.T, o.phi, o.chain))
            assert np.all(np.diff(np.abs(mu)) <= 1e-12)
            assert np.abs(mu).max() == pytest.approx(b.max_abs_multiplier[i], rel=1e-12)
        flips = np.flatnonzero(b.stable[1:] != b.stable[:-1]) + 1
        at = {e["index"] for e in b.events if e["kind"] in (plbar.paths.PERIOD_DOUBLING,
                                                              plbar.paths.NEIMARK_SACKER, plbar.paths.FOLD_MU)}
        assert set(flips) <= at, (b.describe(), flips, at)
        kinds |= {e["kind"] for e in b.events}
    stable = np.concatenate([b.stable for b in default_result.paper])
    assert stable.any() and (~stable).any()
    assert plbar.paths.NEIMARK_SACKER in kinds


def test_multipliers_do_not_depend_on_load_scale(default_result):
    """The map is affine in z and its linear part does not contain the load (FORMULATION §7)."""
    prob = default_result.prob
    orb = default_result.paths.points().take(np.arange(0, len(default_result.paths.points()), 25))
    p3 = dataclasses.replace(prob, q=3 * prob.q, f1=3 * prob.f1, f2=3 * prob.f2, r_q=3 * prob.r_q)
    o3 = Orbits(p3, orb.T1, orb.T2, orb.phi, 3 * orb.eta0, 3 * orb.v0, 3 * orb.eta_s, 3 * orb.v_s)
    for k in range(len(orb)):             # near grazing (small v_c) the saltation matrices lose digits
        M = core_monodromy(prob, orb, k)[0]
        assert np.abs(core_monodromy(p3, o3, k)[0] - M).max() <= 1e-9 * np.abs(M).max()


def test_paper_points(default_result):
    """Not in the paper: the red point (path 1) is unstable, the green point (path 2) is stable."""
    br = default_result.paper
    T1, T2 = np.concatenate([b.T1 for b in br]), np.concatenate([b.T2 for b in br])
    mx = np.concatenate([b.max_abs_multiplier for b in br])
    st = np.concatenate([b.stable for b in br])
    d_red = np.hypot(T1 - RED[0], T2 - RED[1])
    d_green = np.hypot(T1 - GREEN[0], T2 - GREEN[1])
    red, green = np.argmin(d_red), np.argmin(d_green)
    assert d_red[red] < 0.03 and d_green[green] < 0.03
    # along the branches within 0.05 of the points: red 1.04 .. 1.075, green 0.992 .. 0.9992
    assert 1.03 < mx[red] < 1.10 and not st[red]
    assert 0.99 < mx[green] < 0.9995 and st[green]


def _strobe_distance(sim, z0):
    """Distance of the stroboscopic samples from the periodic start, relative (x all DOFs, v without v_c)."""
    z = np.c_[sim.strobe_x, sim.strobe_v[:, :-1]]
    return np.linalg.norm(z - np.r_[z0[: z0.size // 2], 0.0, z0[z0.size // 2:]], axis=1) / np.linalg.norm(z0)


@pytest.fixture(scope="module")
def extremes(default_result):
    """The most stable and the most unstable well-conditioned path points of the default case."""
    pts = good_points(default_result, per_branch=6)
    rho = np.array([np.abs(multipliers(core_monodromy(default_result.prob, o, k)[0])).max() for o, k in pts])
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


def test_truncated_model_multipliers_converge_to_the_full_ones():
    """With every mode kept the truncated path is the full one; with most modes the multipliers agree closely."""
    full = plbar.Case(model="fe", n=12, grid=(80, 80), signatures="paper")
    res = plbar.solve(full)
    i = max(range(len(res.paths.branches)), key=lambda j: len(res.paper[j]))      # the scan's, in its order
    b, p = res.paper[i], res.paths.branches[i]
    k = len(b) // 2
    o = b.orbits[k]
    mu_full = multipliers(monodromy(res.prob, PAPER, o.T, o.phi, o.chain))
    assert np.abs(mu_full).max() == pytest.approx(b.max_abs_multiplier[k], rel=1e-12)
    for modes, exact in ((11, False), (12, True)):       # all modes of state I and 11 (12: all) of 12 of state II
        prob_t = plbar.Case(model="fe", n=12, modes=modes).problem()
        ot = plbar.orbits(prob_t, p.T1[k:k + 1], p.T2[k:k + 1], p.phi[k:k + 1])
        M = core_monodromy(prob_t, ot, 0)[0]
        assert M.shape == (2 * prob_t.system.w1.size,) * 2 and np.isfinite(M).all()
        if exact:
            assert eig_distance(multipliers(M), mu_full) < 1e-8 * np.abs(mu_full).max()
