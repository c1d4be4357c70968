"""Periodic paths of the paper's case and the identities of FORMULATION §5 on every path point."""

import numpy as np
import pytest

import plbar
from plbar.response import psi_sums, work_quadrature

RED = (1.7748, 8.1525, 3.5495)
GREEN = (2.3876, 9.8894, 4.8050)


def _dist_to_polyline(b, p):
    """Distance in (T1, T2, phi) from point p to the polyline of branch b (phi compared mod 2 pi)."""
    P = np.c_[b.T1, b.T2, np.mod(b.phi, 2 * np.pi)]
    q = np.array([p[0], p[1], np.mod(p[2], 2 * np.pi)])
    best = np.inf
    for a, c in zip(P[:-1], P[1:]):
        d = c - a
        t = np.clip((q - a) @ d / (d @ d), 0, 1) if d @ d > 0 else 0.0
        best = min(best, np.linalg.norm(a + t * d - q))
    return best if len(P) > 1 else np.linalg.norm(P[0] - q)


@pytest.mark.parametrize("point", [RED, GREEN], ids=["red", "green"])
def test_paper_points_lie_on_branches(default_result, point):
    d = min(_dist_to_polyline(b, point) for b in default_result.paths.branches)
    assert d < 5e-3


def test_green_point_impact_loss(default_result):
    b = min(default_result.paths.branches, key=lambda b: _dist_to_polyline(b, GREEN))
    k = np.argmin(np.hypot(b.T1 - GREEN[0], b.T2 - GREEN[1]))
    assert b.dPL[k] == pytest.approx(1.05, rel=0.05)


def test_paper_branches_found(default_result):
    """Path 1 near T0_I (through the red point) and path 2 near T0_II/2 (through the green point)."""
    T = [(b.T.min(), b.T.max()) for b in default_result.paths.branches]
    assert any(lo < 9.9273 < hi for lo, hi in T)
    assert any(lo < 12.277 < hi for lo, hi in T)
    for b in default_result.paths.branches:
        assert np.all(np.diff(np.hypot(b.T1, b.T2)) != 0) or len(b) == 1


def _identities(res, scale_model=None):
    orb = res.paths.points()
    assert orb is not None and len(orb) > 10
    # 1. periodicity of the state (after the impact at T we are back at the start)
    e, v = orb.after_impact()
    z0 = np.c_[orb.eta0, orb.v0]
    err = np.linalg.norm(np.c_[e, v] - z0, axis=1) / np.linalg.norm(z0, axis=1)
    assert err.max() < 1e-9
    # 2. switch residuals from the flow itself, relative to the amplitude of each signal
    u = np.linspace(0, 1, 801)
    mI = orb.reaction_margin(orb.T1[:, None] * u)
    gII = orb.gap(orb.T2[:, None] * u)
    e1, e2 = orb.residuals()
    assert np.max(np.abs(e1) / np.abs(mI).max(axis=1)) < 1e-9
    assert np.max(np.abs(e2) / np.abs(gII).max(axis=1)) < 1e-9
    # 3. work of the force over one period = Delta_PL (the impact is the only loss)
    dmp = plbar.damping(orb)
    work = work_quadrature(orb)
    ek, ep = orb.energies(orb.T[:, None] * u)
    emax = (ek + ep).max(axis=1)
    assert np.max(np.abs(work - dmp.dPL) / np.maximum(dmp.dPL, emax)) < 1e-9
    assert np.all(dmp.dPL >= -1e-12 * emax)
    # 4. closed-form Psi = Gauss quadrature of etadot^2 (independent nodes, per state)
    x, w = np.polynomial.legendre.leggauss(400)
    s = orb.prob.system
    _, v1 = orb.state_I(0.5 * orb.T1[:, None] * (x + 1))
    _, v2 = orb.state_II(0.5 * orb.T2[:, None] * (x + 1))
    q1 = 0.5 * orb.T1 * np.einsum("k,pkj,j->p", w, v1 ** 2, s.w1)
    q2 = 0.5 * orb.T2 * np.einsum("k,pkj,j->p", w, v2 ** 2, s.w2)
    c1, c2, _ = psi_sums(orb)
    assert np.max(np.abs(c1 - q1) / (q1 + q2)) < 1e-9
    assert np.max(np.abs(c2 - q2) / (q1 + q2)) < 1e-9
    # 5. xi invariant to the load amplitude
    p3 = plbar.model.with_load_vector(s, 3.7 * orb.prob.q)
    d3 = plbar.damping(plbar.orbits(p3, orb.T1, orb.T2, orb.phi))
    np.testing.assert_allclose(d3.xi, dmp.xi, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(d3.dPL, 3.7 ** 2 * dmp.dPL, rtol=1e-9, atol=1e-12 * emax.max())
    # 6. xi invariant to scaling mass and stiffness (time rescales by sqrt(m/k)): corresponding points
    if scale_model is not None:
        ps, ts = scale_model
        ds = plbar.damping(plbar.orbits(ps, ts * orb.T1, ts * orb.T2, orb.phi))
        np.testing.assert_allclose(ds.xi, dmp.xi, rtol=1e-9, atol=1e-15)
    return dmp


def test_identities_default_run(default_result):
    ps = plbar.problem(plbar.chain(5, m=2.5, k=0.4), plbar.node(1))
    dmp = _identities(default_result, (ps, np.sqrt(2.5 / 0.4)))
    assert np.all(np.isfinite(dmp.xi))


@pytest.mark.slow
def test_identities_fe_p2_consistent(fe_p2_result):
    c = fe_p2_result.case
    bar = plbar.Bar(plbar.uniform_nodes(8), "P2", "consistent", EA=3.0, rhoA=0.75)
    ps = plbar.problem(bar, c.load())
    _identities(fe_p2_result, (ps, np.sqrt(0.75 / 3.0)))


def test_resonance_is_finite():
    """Forcing exactly at a natural frequency of state I or II: finite response, finite xi."""
    p = plbar.problem(plbar.chain(5), plbar.node(1))
    T0I, T0II = p.system.T0
    for T in (T0I, T0II / 3, 2 * np.pi / p.system.w2[1]):
        T1 = 0.3 * T
        orb = plbar.orbits(p, [T1], [T - T1], [1.0])
        d = plbar.damping(orb)
        assert np.all(np.isfinite(orb.eta0)) and np.isfinite(d.xi).all() and np.isfinite(d.dPL).all()


def test_branch_points_exact_and_admissible(default_result):
    for b in default_result.paths.branches:
        assert np.all(b.e1 < 1e-9) and np.all(b.e2 < 1e-9)
        assert np.all(b.adm.ok)
        assert np.all(b.adm.v_impact > 0)
        assert np.all((b.phi >= 0) & (b.phi < 2 * np.pi))
