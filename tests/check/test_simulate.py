"""The event-driven simulator (plbar.simulate) against the closed-form periodic responses and energy identities."""

import dataclasses
import time

import numpy as np
import pytest
from shared_points import FE_POINT, good_points

import plbar
from plbar.errors import InputError
from plbar.check import IMPACT, OPEN, duhamel, modal_flow, period_map, simulate
from plbar.response import periodic_state

@pytest.fixture(scope="module")
def fe_small():
    """The FE P2 consistent case of conftest, on a small window of the (T1, T2) plane around one branch."""
    return plbar.solve(plbar.Case(**FE_POINT, signatures="paper"))


def _returns(prob, orb, k):
    xr, vr = periodic_state(orb)
    sim = simulate(prob, orb.T[k], orb.phi[k], xr[k], vr[k], n_periods=1.0)
    z0 = np.r_[xr[k], vr[k]]
    z1 = np.r_[sim.x[:-1], sim.v[:-1]]
    return sim, np.linalg.norm(z1 - z0) / np.linalg.norm(z0)


def test_one_period_returns_to_periodic_state(default_result):
    prob = default_result.prob
    pts = good_points(default_result)
    assert len({id(o) for o, _ in pts}) >= 4 and len(pts) >= 12
    worst_z, worst_t = 0.0, 0.0
    for orb, k in pts:
        sim, err = _returns(prob, orb, k)
        assert sim.state == 1
        assert sim.x[-1] == 0.0 and sim.v[-1] == 0.0
        assert list(sim.events["kind"]) == [OPEN, IMPACT]
        dt = np.abs(sim.events["time"] - [orb.T1[k], orb.T[k]]).max()
        worst_z, worst_t = max(worst_z, err), max(worst_t, dt)
    assert worst_z < 1e-9
    assert worst_t < 1e-10


def test_period_map_fixed_point(default_result):
    prob = default_result.prob
    for orb, k in good_points(default_result, per_branch=1):
        xr, vr = periodic_state(orb)
        x1, v1 = period_map(prob, orb.T[k], orb.phi[k], xr[k], vr[k])
        z0 = np.r_[xr[k], vr[k]]
        assert np.linalg.norm(np.r_[x1, v1] - z0) / np.linalg.norm(z0) < 1e-9


def test_fe_p2_consistent_returns(fe_small):
    prob = fe_small.prob
    assert not prob.system.lumped
    pts = good_points(fe_small, per_branch=3, min_len=10)
    assert len(pts) >= 3
    for orb, k in pts:
        sim, err = _returns(prob, orb, k)
        assert err < 1e-9
        assert list(sim.events["kind"]) == [OPEN, IMPACT]
        assert np.abs(sim.events["time"] - [orb.T1[k], orb.T[k]]).max() < 1e-10
        # consistent mass: the impact changes v_r too, and the loss is the orbit's Delta_PL
        assert sim.impact_losses[0] == pytest.approx(plbar.impact_loss(orb.take([k]))[0], rel=1e-9)


def test_history_matches_closed_form_orbit(default_result):
    prob = default_result.prob
    orb, k = good_points(default_result, per_branch=1)[0]
    o = orb.take([k])
    xr, vr = periodic_state(o)
    t = np.linspace(0, o.T[0], 333, endpoint=False)
    sim = simulate(prob, o.T[0], o.phi[0], xr[0], vr[0], record=t)
    x, v, st = o.response(t)
    scale = np.abs(x).max(), np.abs(v).max()
    assert np.abs(sim.history.x - x[0]).max() < 1e-10 * scale[0]
    assert np.abs(sim.history.v - v[0]).max() < 1e-10 * scale[1]
    assert np.array_equal(sim.history.state, st[0])
    ek, ep = o.energies(t)
    assert np.allclose(sim.history.ek, ek[0], rtol=1e-9, atol=1e-12 * ek.max())
    assert np.allclose(sim.history.ep, ep[0], rtol=1e-9, atol=1e-12 * ep.max())


def test_impact_loss_equals_delta_pl(default_result):
    prob = default_result.prob
    for orb, k in good_points(default_result, per_branch=1):
        sim, _ = _returns(prob, orb, k)
        dpl = plbar.impact_loss(orb.take([k]))[0]
        assert sim.impact_losses[0] == pytest.approx(dpl, rel=1e-9)
        # periodic: the work of the load over a period is the impact loss (FORMULATION §5)
        assert sim.work == pytest.approx(dpl, rel=1e-9)


def test_free_vibration_energy(default_result):
    """q = 0: energy constant between events (1e-10 relative), each impact drops it by its own loss."""
    prob = default_result.prob
    n = prob.system.n
    free = dataclasses.replace(prob, q=np.zeros(n), f1=np.zeros(n - 1), f2=np.zeros(n), r_q=0.0)
    orb, k = good_points(default_result, per_branch=1)[0]
    xr, vr = periodic_state(orb)
    T = 10.0
    rec = np.linspace(0.0, 20 * T, 40001)
    sim = simulate(free, T, 0.3, xr[k], vr[k], n_periods=20, record=rec)
    assert sim.work == 0.0
    assert sim.impact_times.size >= 10
    assert np.all(sim.impact_losses > 0)
    assert np.all(np.abs(sim.events["loss"][sim.events["kind"] == OPEN]) < 1e-13 * sim.energy0)
    E = sim.history.energy
    seg = np.searchsorted(sim.events["time"], rec, side="right")
    # after some impacts the reaction is tensile at once: the gap reopens at the same instant (zero-length
    # state I segments, no samples); compare the energy levels of consecutive non-empty intervals
    levels, idx = [], []
    for i in range(sim.events["time"].size + 1):
        Ei = E[seg == i]
        if Ei.size:
            assert np.ptp(Ei) < 1e-10 * sim.energy0
            levels.append(Ei.mean())
            idx.append(i)
    assert len(idx) > 10
    for (i, a), (j, b) in zip(zip(idx, levels), zip(idx[1:], levels[1:])):
        assert a - b == pytest.approx(sim.events["loss"][i:j].sum(), rel=0, abs=1e-10 * sim.energy0)
    assert sim.energy0 - sim.energy == pytest.approx(sim.events["loss"].sum(), rel=1e-10)
    assert abs(sim.energy_residual) < 1e-12 * sim.energy0


def test_forced_energy_budget(default_result):
    """100 forced periods from rest, with impacts: work in - losses - change of energy closes to 1e-9."""
    prob = default_result.prob
    orb, k = good_points(default_result, per_branch=1)[-1]
    n = prob.system.n
    sim = simulate(prob, orb.T[k], orb.phi[k], np.zeros(n), np.zeros(n), n_periods=100)
    assert sim.impact_times.size >= 90
    losses = sim.impact_losses.sum()
    assert losses > 0 and sim.work > 0
    assert abs(sim.energy_residual) < 1e-9 * max(sim.work, losses)
    # and the same budget on a non-integer run that ends mid-period
    sim2 = simulate(prob, orb.T[k], orb.phi[k], np.zeros(n), np.zeros(n), n_periods=37.3, t0=2.5)
    assert abs(sim2.energy_residual) < 1e-9 * max(sim2.work, sim2.impact_losses.sum())


def test_duhamel_resonance_and_limits():
    w = np.array([0.7, 1.3, 2.0])
    tau = np.linspace(-3.0, 40.0, 97)[:, None]
    for W in (0.5, 1.3, 1.3 * (1 + 1e-9), 3.1):
        C, Cp, S, Sp = duhamel(w, W, tau)
        with np.errstate(divide="ignore", invalid="ignore"):
            d = w * w - W * W
            Cref = (np.cos(W * tau) - np.cos(w * tau)) / d
            Sref = (w * np.sin(W * tau) - W * np.sin(w * tau)) / (w * d)
            Cpref = (w * np.sin(w * tau) - W * np.sin(W * tau)) / d
        far = np.abs(w - W) > 1e-3
        assert np.allclose(C[:, far], Cref[:, far], atol=1e-12)
        assert np.allclose(S[:, far], Sref[:, far], atol=1e-12)
        assert np.allclose(Cp[:, far], Cpref[:, far], atol=1e-12)
        assert np.allclose(Sp, W * C)
        if not far.all():
            j = np.flatnonzero(~far)[0]
            lim = tau[:, 0] * np.sin(w[j] * tau[:, 0]) / (2 * w[j])      # exact resonance limit
            assert np.allclose(C[:, j], lim, atol=1e-7)
    # the flow satisfies the ODE: eta'' + w^2 eta = f cos(W t + theta) (centred differences)
    w, f, W, th = np.array([1.3]), np.array([0.8]), 1.3, 0.4
    t = np.linspace(0.5, 20, 50)
    h = 1e-4
    e = [modal_flow(w, f, W, th, t + s, np.array([0.2]), np.array([-0.1]))[0][:, 0] for s in (-h, 0, h)]
    acc = (e[0] - 2 * e[1] + e[2]) / h**2
    assert np.allclose(acc + w[0] ** 2 * e[1], f[0] * np.cos(W * t + th), atol=1e-6)


def test_settles_from_rest_runtime(default_result):
    """A plain transient: 200 periods of the N = 5 chain in well under a few seconds."""
    prob = default_result.prob
    orb, k = good_points(default_result, per_branch=1)[-1]
    t = time.perf_counter()
    sim = simulate(prob, orb.T[k], orb.phi[k], np.zeros(5), np.zeros(5), n_periods=200)
    assert time.perf_counter() - t < 5.0
    assert sim.strobe_t.size == 200 and sim.strobe_x.shape == (200, 5)
    assert np.allclose(sim.strobe_t, orb.T[k] * np.arange(1, 201))


def test_state_2_start_and_immediate_opening(default_result):
    prob = default_result.prob
    orb, k = good_points(default_result, per_branch=1)[0]
    o = orb.take([k])
    # start in state II from the orbit's state at T1 + T2 / 2: one impact at T, then periodic again
    tm = o.T1[0] + 0.5 * o.T2[0]
    x, v, st = o.response([tm])
    assert st[0, 0] == 2
    sim = simulate(prob, o.T[0], o.phi[0], x[0, 0], v[0, 0], state=2, t0=tm, n_periods=1.0)
    assert list(sim.events["kind"]) == [IMPACT, OPEN]
    assert np.allclose(sim.events["time"], [o.T[0], o.T[0] + o.T1[0]], rtol=0, atol=1e-10)
    assert np.allclose(sim.x, x[0, 0], atol=1e-10 * np.abs(x).max())
    # at rest with a load pulling the contact node away from the wall: the gap opens at once
    q = np.zeros(5)
    q[-1] = -1.0
    pull = dataclasses.replace(prob, q=q, f1=np.zeros(4), f2=prob.system.V2.T @ q, r_q=1.0)
    sim = simulate(pull, 10.0, 0.0, np.zeros(5), np.zeros(5), n_periods=0.1)
    assert sim.events["kind"][0] == OPEN and sim.events["time"][0] == 0.0
    assert sim.state == 2 and sim.x[-1] < 0


@pytest.mark.parametrize("kw, match", [
    (dict(T=0.0), "T = 0.0"),
    (dict(T=np.nan), "T = nan"),
    (dict(state=3), "state = 3"),
    (dict(n_periods=-1), "n_periods = -1"),
    (dict(x0=np.ones(3)), "x0 has shape"),
    (dict(x0=np.r_[np.zeros(4), 0.1]), r"x0\[-1\] = 0.1"),
    (dict(x0=np.r_[np.zeros(4), 0.1], state=2), "penetrates"),
    (dict(record=[-1.0, 2.0]), "record times"),
])
def test_input_errors(default_result, kw, match):
    prob = default_result.prob
    args = dict(T=10.0, phi=0.0, x0=np.zeros(5), v0=np.zeros(5))
    args.update(kw)
    with pytest.raises(InputError, match=match):
        simulate(prob, **args)
    assert issubclass(InputError, ValueError)


def test_period_map_input_error(default_result):
    with pytest.raises(InputError, match="x_r and v_r must have 4 values"):
        period_map(default_result.prob, 10.0, 0.0, np.zeros(5), np.zeros(5))
