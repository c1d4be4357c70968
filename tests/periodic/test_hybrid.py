"""Periodic responses of every signature: exactness, independent checks, stability, load independence."""

import numpy as np
import pytest

import plbar
from plbar.check import simulate
from plbar.periodic import (PAPER, ZERO_DWELL, admissible, evaluate, expected_events, find_branches,
                            from_motion, monodromy, multipliers, orbit_at, polish, signature, zero_dwell)
from plbar.periodic.chain import layout
from plbar.motion import run, steady


@pytest.fixture(scope="module")
def prob():
    return plbar.Case().problem()


@pytest.fixture(scope="module")
def hybrid(default_result):
    """The branches of every signature but the paper's class in (6, 14), seeded as plbar run seeds them but
    without the simulation: the paper's branches, the structure's seeds."""
    p = default_result.prob
    _CURVES.clear()
    found = find_branches(p, (6.0, 14.0), default_result.branches, progress=lambda: _CURVES.append(1))
    return [b for b in found if not b.paper]


_CURVES: list = []      #: one entry per curve find_branches reported as followed (its progress callback)


def check_by_simulation(o, tol=1e-9):
    """The independent simulator from the orbit's state: the same switches at the same times over m periods,
    back to the start, and the work of the load = the impact losses (energy balance)."""
    prob = o.prob
    x0, v0 = o.start
    sim = simulate(prob, o.T, o.phi, x0, v0, state=1, n_periods=o.sig.m)
    et, ek = expected_events(o)
    span = o.sig.m * o.T
    n = et.size
    assert np.array_equal(sim.events["kind"][:n], ek)
    assert np.max(np.abs(sim.events["time"][:n] - et)) <= tol * span
    assert np.all(sim.events["time"][n:] >= span * (1 - tol))
    # back to the start (the simulator samples after an event at the period boundary, FORMULATION §7)
    z = np.concatenate([sim.strobe_x[-1][:-1], sim.strobe_v[-1][:-1]])
    z0 = np.concatenate([x0[:-1], v0[:-1]])
    if ek[0] == 2 or o.sig.dwell[0]:
        assert np.max(np.abs(z - z0)) <= tol * np.max(np.abs(z0))
    scale = max(abs(sim.work), sim.energy0)          # near grazing the loss is tiny beside the energy exchanged
    assert abs(sim.work - o.dPL) <= tol * scale
    assert abs(sim.energy_residual) <= tol * scale


def test_paper_class_is_signature_1P(default_result):
    """Every path point of plbar run solves the chain's equations at round-off (its monodromy:
    tests/response/test_stability.py against finite differences)."""
    prob = default_result.prob
    for b in default_result.paths.branches:
        o = b.orbits
        for i in range(0, len(b), max(1, len(b) // 4)):
            X = np.concatenate([o.eta0[i], o.v0[i], [o.T1[i], o.T2[i], o.phi[i]]])
            h = orbit_at(prob, PAPER, o.T[i], X)
            assert h.residual <= 1e-11
            # near grazing the paper class's kinetic-energy difference loses digits; S v_c^2 / 2 does not
            ek = 0.5 * float(np.sum(h.chain.segments[-1].z1[prob.system.w2.size:] ** 2))   # kinetic energy
            assert h.dPL == pytest.approx(b.dPL[i], rel=1e-10, abs=1e-12 * ek)
            assert h.xi == pytest.approx(b.xi[i], rel=1e-9, abs=1e-10 * max(b.xi.max(), 1e-3))
            M = monodromy(prob, PAPER, o.T[i], o.phi[i], h.chain)        # the branch's verdict is this one's
            assert np.abs(multipliers(M)).max() == pytest.approx(default_result.paper[b.id].max_abs_multiplier[i],
                                                                 rel=1e-12)


@pytest.mark.parametrize("sig_text", ["1P", "1PZ", "2PZ", "1Z"])
def test_jacobian_is_exact(prob, sig_text, hybrid, default_result):
    sig = signature(sig_text)
    if sig == PAPER:
        b = default_result.paths.branches[0].orbits
        orbs = [orbit_at(prob, PAPER, b.T[0], np.concatenate([b.eta0[0], b.v0[0], [b.T1[0], b.T2[0], b.phi[0]]]))]
    else:
        orbs = [o for h in hybrid for o in h.orbits if h.sig == sig] or \
            [o for T in (8.5,) for o in zero_dwell(prob, T)]
    o = orbs[len(orbs) // 2]
    X = o.X.copy()
    X[-1] += 1e-3
    ch = evaluate(prob, o.sig, o.T, X)
    J = np.zeros_like(ch.J)
    h = 1e-6
    for j in range(X.size):
        e = np.zeros(X.size)
        e[j] = h
        J[:, j] = (evaluate(prob, o.sig, o.T, X + e, jac=False).F
                   - evaluate(prob, o.sig, o.T, X - e, jac=False).F) / (2 * h)
    assert np.max(np.abs(J - ch.J)) <= 1e-7 * np.abs(ch.J).max()


def _resolvable(o, per_rad) -> bool:
    """Can a sampled event search (``per_rad`` samples per radian of the fastest frequency) see every segment and
    every impact (not one so slow that the gap's dip before it is shallower than the samples see)?"""
    w = max(o.prob.system.w2.max(), 2 * np.pi / o.T)
    short = [d for d in o.durations if d > 0]
    slow = o.v_impact.min() < 1e-3 * o.amplitude * float(o.prob.system.w2[0])
    return min(short) * w * per_rad > 4 and not slow


def test_every_new_response_checked_by_the_simulator_and_the_energy_balance(hybrid, monkeypatch):
    """Default case, T in [6, 14]: residuals <= 1e-12 relative; the independent simulator (sampling 20 times
    denser than its default) meets the same events at the same times (1e-9 m T), returns to the start (1e-9),
    and the energy balance closes (1e-9), on a sample of every branch.  Orbits with a segment shorter than a
    few samples (grazing) are beyond any sampled event search; the certified replay checks them."""
    import plbar.check.segments as seg

    monkeypatch.setattr(seg, "SAMPLES_PER_RAD", 50.0)
    assert hybrid, "no responses of other signatures found"
    checked, grazing = 0, []
    for b in hybrid:
        for o in b.orbits[::max(1, len(b) // 6)]:
            assert o.residual <= 1e-12
            if _resolvable(o, 50.0):
                check_by_simulation(o)
                checked += 1
            else:
                grazing.append(o)
    assert checked >= 30
    assert np.all(admissible(grazing)) and len(grazing) <= checked


def test_zero_dwell_class_in_closed_form(prob):
    """FORMULATION §8: the default chain from rest at T = 8.5 settles on a zero-dwell response, loss 1.9139."""
    orbs = zero_dwell(prob, 8.5)
    losses = sorted(o.loss_per_T for o in orbs)
    assert losses[0] == pytest.approx(1.9139205895, rel=1e-9)
    good = [o for o in orbs if np.all(o.v_impact > 0)]
    check_by_simulation(good[0])
    assert good[0].zero_margins[0] < 0


def test_survey_motion_polished(prob):
    """A subharmonic settled on from rest is polished into its exact orbit: the same loss, the simulator agrees."""
    T = 8.4
    r = run(prob, [T], periods=800, record=60)
    s = steady(r)
    assert s.kind_names[0] == "periodic" and s.m[0] == 2
    o = from_motion(prob, r, 0, 2)
    assert str(o.sig.canonical()) == "2PZ"
    assert o.loss_per_T == pytest.approx(s.loss_per_T[0], rel=1e-9)
    check_by_simulation(o)
    mu = multipliers(monodromy(prob, o.sig, o.T, o.phi, o.chain))
    assert np.abs(mu).max() < 1                          # it attracts the motion from rest: stable


def test_floquet_multipliers_against_the_simulated_map(prob):
    """The m-period map's Jacobian by finite differences of the independent simulator (a 2PZ orbit)."""
    T = 8.4
    r = run(prob, [T], periods=800, record=60)
    o = from_motion(prob, r, 0, 2)
    M = monodromy(prob, o.sig, o.T, o.phi, o.chain)
    s = prob.system
    m = s.w1.size
    Mass = np.asarray(s.M, float)[:-1, :-1]

    def fmap(z):
        x0, v0 = s.embed(s.V1 @ z[:m]), s.embed(s.V1 @ z[m:])
        sim = simulate(prob, T, o.phi, x0, v0, state=1, n_periods=2)
        x, v = sim.strobe_x[-1][:-1], sim.strobe_v[-1][:-1]
        return np.concatenate([s.V1.T @ Mass @ x, s.V1.T @ Mass @ v])

    h = 1e-7 * np.abs(o.z0).max()
    J = np.column_stack([(fmap(o.z0 + h * e) - fmap(o.z0 - h * e)) / (2 * h) for e in np.eye(2 * m)])
    assert np.allclose(J, M, atol=1e-5 * np.abs(M).max())


def test_paths_are_load_independent_for_any_signature(prob, hybrid):
    """Lemma 1 of docs/load_structure.md holds for any sequence of segments: a load with the same contact
    response (q2 = a q + Z u, u_c = 0) has the same durations, and phi (mod pi), brute force by Newton."""
    s = prob.system
    b = next(b for b in hybrid if b.sig.k >= 2)
    o = b.orbits[len(b) // 2]
    W = 2 * np.pi / o.T
    Z = np.asarray(s.K, float) - W * W * np.asarray(s.M, float)
    u = np.r_[np.linspace(0.3, -0.2, s.n - 1), 0.0]
    q2 = -0.7 * np.asarray(prob.q, float) + Z @ u
    p2 = plbar.problem(prob.bar, q=q2)
    X = o.X.copy()
    X[-1] += np.pi                                     # a < 0: the phase moves by pi
    nz, q, _ = layout(prob, o.sig)
    X[:nz] = 0.0                                       # the state is unknown: Newton finds it
    o2 = polish(p2, o.sig, o.T, np.concatenate([X[:nz] + 1e-3, X[nz:]]))
    assert np.allclose(o2.durations, o.durations, rtol=0, atol=1e-9 * o.T)
    assert np.mod(o2.phi - o.phi - np.pi + 1, 2 * np.pi) - 1 == pytest.approx(0, abs=1e-9)
    assert o2.loss_per_T == pytest.approx(0.49 * o.loss_per_T, rel=1e-9)


def test_signature_strings():
    assert str(signature("2ZP").canonical()) == "2PZ"
    assert signature("1P") == PAPER and str(ZERO_DWELL) == "1Z"
    with pytest.raises(plbar.InputError):
        signature("2PX")


def test_signature_parts_are_the_shorter_orbits_it_could_repeat():
    assert signature("2PZPZ").parts() == [(1, 2)]
    assert signature("3PPPPPP").parts() == [(1, 2)]
    assert signature("4PZPZ").parts() == [(2, 2)]
    assert signature("6PPP").parts() == [(2, 1)]                # m' = 2: one pair, three times
    assert signature("2PZZ").parts() == [] and signature("1P").parts() == []


def test_an_orbit_seen_twice_is_known_by_its_own_period(hybrid):
    """The 1PZ orbits written as 2PZPZ (two periods: a solution of the doubled signature) have period 1 and give
    back the 1PZ orbit; a genuine two-period orbit has period 2; the default run's labels are all minimal."""
    prob = hybrid[0].orbits[0].prob
    one = next(b for b in hybrid if b.label == "1PZ" and len(b) > 3).orbits[2]
    nz, q, _ = layout(prob, one.sig)
    X = np.concatenate([one.X[:nz], one.X[nz:nz + q], one.X[nz:nz + q], one.X[-1:]])
    twice = polish(prob, one.sig.repeated(2), one.T, X)
    assert twice.residual <= 1e-12 and twice.period == 1 and one.period == 1
    back = twice.minimal()
    assert back.sig == one.sig and back.loss_per_T == pytest.approx(one.loss_per_T, rel=1e-12)
    assert np.allclose(back.z0, one.z0, rtol=0, atol=1e-10 * np.abs(one.z0).max())
    two = next(b for b in hybrid if b.sig.m == 2)
    assert all(o.period == 2 for o in two.orbits)
    assert all(o.period == o.sig.m for b in hybrid for o in b.orbits[::5])


def test_damped_responses_of_every_signature(monkeypatch):
    """Rayleigh damping 2 %: the chain's Jacobian stays exact, the paper's class is reproduced, and every new
    response (a sample) meets the independent damped simulator's events, returns to its start and balances
    work = impact losses + viscous loss."""
    import plbar.check.segments as seg
    from plbar.model import rayleigh_from_ratio

    monkeypatch.setattr(seg, "SAMPLES_PER_RAD", 50.0)
    case = plbar.Case(rayleigh=rayleigh_from_ratio(0.02, 6.0, 14.0))
    res = plbar.solve(case)
    prob = res.prob
    b = res.paths.branches[0]
    o = b.orbits
    i = len(b) // 2
    X = np.concatenate([o.eta0[i], o.v0[i], [o.T1[i], o.T2[i], o.phi[i]]])
    h = orbit_at(prob, PAPER, o.T[i], X)
    assert h.residual <= 1e-11 and h.dPL == pytest.approx(b.dPL[i], rel=1e-9)
    assert h.viscous == pytest.approx(b.viscous[i], rel=1e-9) and h.xi == pytest.approx(b.xi[i], rel=1e-8)
    hy = [b for b in res.branches if not b.paper and 6.0 <= b.T.min() and b.T.max() <= 14.0]
    assert hy
    checked = 0
    for br in hy:
        for orb in br.orbits[::max(1, len(br) // 3)]:
            if not _resolvable(orb, 50.0):
                continue
            x0, v0 = orb.start
            sim = simulate(prob, orb.T, orb.phi, x0, v0, state=1, n_periods=orb.sig.m)
            et, ek = expected_events(orb)
            n = et.size
            assert np.array_equal(sim.events["kind"][:n], ek)
            assert np.max(np.abs(sim.events["time"][:n] - et)) <= 1e-9 * orb.sig.m * orb.T
            scale = max(abs(sim.work), sim.energy0)
            assert abs(sim.work - orb.dPL - orb.viscous) <= 1e-9 * scale
            assert abs(sim.viscous - orb.viscous) <= 1e-9 * scale
            checked += 1
    assert checked >= 10
    ch = evaluate(prob, hy[0].sig, hy[0].orbits[0].T, hy[0].orbits[0].X)
    Xp = hy[0].orbits[0].X
    e = np.zeros(Xp.size)
    e[0] = 1e-6
    fd = (evaluate(prob, hy[0].sig, hy[0].orbits[0].T, Xp + e, jac=False).F -
          evaluate(prob, hy[0].sig, hy[0].orbits[0].T, Xp - e, jac=False).F) / 2e-6
    assert np.max(np.abs(fd - ch.J[:, 0])) <= 1e-7 * np.abs(ch.J).max()


def test_progress_once_per_curve_followed(hybrid):
    """Every branch lies on a curve that was reported; a curve can hold several branches (admissible runs), or none."""
    labels = {b.label for b in hybrid}
    assert len(_CURVES) >= len(labels) >= 3
    assert len(_CURVES) <= 4 * len(hybrid) + 40
