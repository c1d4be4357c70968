"""A peer's own example: COCO's impact oscillator (Recipes for Continuation, Example 15.2; COCO's ``hspo`` demo).

The demo: ``x'' + c x' + k x = A cos(w t)`` with a stop at ``x = d`` and Newton's law ``v+ = -e v-``, its
parameters ``p0 = [k; c; A; w; d; e] = [1; 0.1; 1; 1; 1; 0.8]`` and the periodic orbit of one impact per forcing
period it continues from.  Its initial guess (two segments: 3.2 from the phase ``-pi`` to the impact, 3.1 from
the impact, which it starts at ``x = 1``, ``v = -1.36``, phase ``0.076``, to the phase ``pi``) is the orbit to two
digits; COCO publishes no more digits than that, so the orbit itself is computed here independently.

Independent route (written here, not plbar's): the impact-to-impact map by ``solve_ivp`` (DOP853) with an event
on ``x = d``, its fixed point by ``fsolve`` and its Jacobian by central differences.  plbar's route: the structure
``M = K = 1``, ``C = 0.1``, contact on its one DOF, gap 1, restitution 0.8 (a state I without DOF), the exact
``1R`` orbit of :func:`plbar.periodic.zero_dwell`, admissibility by plbar's simulator and the multipliers of
:func:`plbar.periodic.monodromy`.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

import plbar
from plbar.periodic import ONE_REBOUND, admissible, find_branches, monodromy, multipliers, zero_dwell

K, C, A, W, D, E = 1.0, 0.1, 1.0, 1.0, 1.0, 0.8
T = 2 * np.pi / W


def _flight(v0: float, psi: float, energy: bool = False):
    """From the stop (``x = d``, ``v = v0 < 0``) at the forcing phase ``psi``: the next impact's velocity and
    phase (``psi`` plus the flight time); with ``energy`` also the damper's loss and the load's work over it."""
    def f(t, y):
        force = A * np.cos(W * t + psi)
        return [y[1], force - C * y[1] - K * y[0], C * y[1] ** 2, force * y[1]]

    def hit(t, y):
        return y[0] - D
    hit.terminal, hit.direction = True, 1.0
    r = solve_ivp(f, (0.0, 3 * T), [D, v0, 0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-13, events=hit,
                  first_step=1e-3)   # the flight starts on the stop, going away from it: not an event
    (te,), (ye,) = r.t_events[0], r.y_events[0]
    return (float(ye[1]), float(psi + W * te)) + ((float(ye[2]), float(ye[3])) if energy else ())


def _impact_map(u):
    """One impact to the next: (impact velocity, phase) -> (impact velocity, phase)."""
    v, psi = u
    return np.array(_flight(-E * v, psi))


@pytest.fixture(scope="module")
def independent():
    def res(u):
        v1, psi1 = _impact_map(u)
        return [v1 - u[0], psi1 - u[1] - 2 * np.pi]
    u = fsolve(res, [1.7, 0.076], xtol=1e-14)
    h = 1e-6
    J = np.column_stack([(_impact_map(u + h * e) - _impact_map(u - h * e)) / (2 * h) for e in np.eye(2)])
    return u, np.sort_complex(np.linalg.eigvals(J))


@pytest.fixture(scope="module")
def prob():
    s = plbar.Structure(M=np.eye(1), K=K * np.eye(1), contact=[1.0], q=[A], rayleigh=(C, 0.0), restitution=E,
                        gap=D)
    return plbar.problem(s)


def _admissible_1r(prob):
    orbs = zero_dwell(prob, T, ONE_REBOUND)
    ok = admissible(orbs)
    return [o for o, a in zip(orbs, ok) if a], orbs


def test_independent_route_is_cocos_orbit(independent):
    """The fixed point found here is the demo's guess, to the guess's two digits."""
    (v, psi), _ = independent
    assert abs(-E * v - (-1.36)) < 0.01 and abs(psi - 0.076) < 0.001
    assert abs((np.pi - psi) - 3.1) < 0.05 and abs((psi + np.pi) - 3.2) < 0.05   # the two segments' durations


def test_orbit_period_impact_velocity_phase(prob, independent):
    (v, psi), _ = independent
    good, every = _admissible_1r(prob)
    assert len(every) == 2 and len(good) == 1          # the other root comes in with v < 0: not a motion
    o = good[0]
    assert o.T == pytest.approx(T, abs=1e-14)
    assert o.v_impact[0] == pytest.approx(v, rel=1e-9)
    # plbar's load is q cos(W t - phi) with t = 0 at the impact: the impact's forcing phase is -phi
    assert np.angle(np.exp(1j * (-o.phi - psi))) == pytest.approx(0.0, abs=1e-9)
    # the energy the impact takes per period: (1 - e^2) v^2 / 2 (one rebound of the unit mass)
    assert o.loss_per_T == pytest.approx((1 - E**2) * v**2 / 2, rel=1e-9)
    # the damper's, by quadrature along the flight, and the balance: the load's work is both
    _, _, damper, work = _flight(-E * v, psi, energy=True)
    assert o.viscous == pytest.approx(damper, rel=1e-9)
    assert work == pytest.approx(o.loss_per_T + damper, rel=1e-9)


def test_stability(prob, independent):
    _, mu_ivp = independent
    o = _admissible_1r(prob)[0][0]
    mu = np.sort_complex(multipliers(monodromy(prob, o.sig, o.T, o.phi, o.chain)))
    assert np.max(np.abs(mu - mu_ivp)) < 1e-6                 # central differences of a 1e-13 integration
    assert np.max(np.abs(mu)) < 1                              # stable: what the demo continues
    # the map's determinant in closed form: e^2 (the rebound) times exp(-c T) (the damper over a period)
    assert abs(np.prod(mu)) == pytest.approx(E**2 * np.exp(-C * T), rel=1e-12)


def test_one_branch_through_it(prob):
    """Over the window of ``plbar run`` (T0_II / 4 to T0_II) one 1R branch, no copy of it, ending at T = 2 pi."""
    branches = find_branches(prob, (0.25 * T, T))
    assert [str(b.sig) for b in branches] == ["1R"]
    assert branches[0].T.max() == pytest.approx(T, rel=1e-12)


def test_every_seed_on_the_followed_curve_is_known(prob):
    """Brute force over the seeds: every admissible 1R root of the closed form on a grid across the window lies
    on the one curve followed (plbar.periodic.followed: on a chord or, where the curve bends, the same orbit by
    Newton); before, the bent curve passed as new from a second seed and was listed three times."""
    from plbar.periodic.branches import _curve
    from plbar.periodic.followed import Followed
    from plbar.periodic.follow import FollowSettings

    window = (0.25 * T, T)
    grid = np.linspace(*window, 60)
    roots = [o for t in grid for o in zero_dwell(prob, t, ONE_REBOUND)]
    seeds = [o for o, a in zip(roots, admissible(roots)) if a]
    assert len(seeds) > 40
    f = Followed(prob)
    f.add(_curve(prob, seeds[0], window, FollowSettings())[0])
    assert all(f.known(o) for o in seeds)


def test_phase_roots():
    """The phases of a0 + a cos phi + b sin phi = 0: two where |a0| < hypot(a, b), none beyond."""
    from plbar.periodic.seeds import _phase_roots

    rng = np.random.default_rng(3)
    for a0, a, b in rng.normal(size=(50, 3)):
        r = _phase_roots(a0, a, b)
        if abs(a0) > np.hypot(a, b):
            assert r.size == 0
        else:
            assert r.size == 2 and np.all((0 <= r) & (r < 2 * np.pi))
            assert np.allclose(a0 + a * np.cos(r) + b * np.sin(r), 0.0, atol=1e-12)


def test_the_command_line_takes_the_oscillator(tmp_path):
    """A structure file of one DOF (``M = K = C / 0.1 = [[1]]``, ``contact = 0``, the gap and the restitution):
    ``plbar run --model matrices`` lists the one 1R branch, up to T = T0_II = 2 pi."""
    import csv

    from plbar.cli import main

    f = tmp_path / "coco.npz"
    np.savez(f, M=np.eye(1), K=K * np.eye(1), contact=0, q=np.array([A]), rayleigh=np.array([C, 0.0]),
             restitution=np.array(E), gap=np.array(D))
    assert main(["run", "--model", "matrices", "--matrices", str(f), "--no-plot", "--quiet",
                 "--out", str(tmp_path / "o")]) == 0
    rows = list(csv.DictReader(open(tmp_path / "o" / "paths.csv")))
    assert {r["signature"] for r in rows} == {"1R"} and len({r["branch"] for r in rows}) == 1
    assert max(float(r["T"]) for r in rows) == pytest.approx(T, rel=1e-12)
