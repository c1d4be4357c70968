"""A constant load on a rigid-body motion: a free body dropped on the stop under gravity (FORMULATION §9).

* Doyen, Ern and Piperno's falling bar (SIAM J. Sci. Comput. 33 (2011) 223-249, Sec. 3; the parameters of NLstep's
  example of it): a free-free elastic bar, L = 10, E = 900, rho = 1, dropped from rest at h0 = 5 under g = 10 onto
  a rigid ground.  Its exact (continuum) motion is periodic, of period 16 L / c: it reaches the ground at
  ``tau_f = sqrt(2 h0 / g) = 1 = 3 L / c``, stays on it for ``2 L / c``, flies for ``2 tau_f``, lands again for
  ``2 L / c`` and leaves it undeformed, rising for ``tau_f``: contact times 1, 5/3, 11/3, 13/3 (then + 16/3), no
  energy lost.  plbar's FE bar (its own assembly, ``supports = "free-free"``) reaches them as the mesh is refined:
  the first release time and the energy the first plastic impact takes go to the exact ones, at the rates measured
  here (P1 and P2, lumped and consistent mass).
* The independent route: the test's solve_ivp integrator (tests/event_integrator.py) on a free chain under
  gravity, with and without a harmonic load, plastic and with rebounds: event times 1e-9, energy 1e-12.
"""

from __future__ import annotations

import numpy as np
import pytest

import plbar
from plbar.errors import InputError
from plbar.motion import given, run

from tests.event_integrator import motion

L, E, RHO, G, H0 = 10.0, 900.0, 1.0, 10.0, 5.0
TAU_W, TAU_F = L / np.sqrt(E / RHO), np.sqrt(2 * H0 / G)
#: the exact contact times of the first period: impact, release, impact, release
EXACT = np.array([TAU_F, TAU_F + 2 * TAU_W, 3 * TAU_F + 2 * TAU_W, 3 * TAU_F + 4 * TAU_W])
PERIOD = 4 * TAU_F + 4 * TAU_W          # fall, contact, flight (2 tau_f), contact, rise: 16 L / c


def _drop(N, element="P1", mass="lumped", periods=1):
    bar = plbar.Bar(np.linspace(0.0, L, N + 1), element=element, mass=mass, EA=E, rhoA=RHO, supports="free-free")
    prob = plbar.problem(bar, plbar.point(0.5 * L, 0.0), gravity=G)
    n = prob.system.n
    r = run(prob, np.array([PERIOD]), periods=periods, record=periods,
            start=given(prob, np.full(n, -H0), np.zeros(n)))
    return bar, prob, r


def test_the_drop_height_makes_the_exact_motion_periodic():
    assert TAU_F == pytest.approx(3 * TAU_W, rel=1e-15)
    assert PERIOD == pytest.approx(16 * TAU_W, rel=1e-15)


def test_the_bar_falls_freely_and_lands_at_the_exact_time_with_its_energy_kept():
    """Before the first impact the motion is the rigid fall ``u = -h0 + g t^2 / 2``: plbar lands at ``tau_f`` to
    round-off, on any mesh; the energy budget (the weight's potential ``-g . eta`` included) closes to 1e-13."""
    for element in ("P1", "P2"):
        bar, prob, r = _drop(8, element)
        assert r.status[0] == 0
        assert abs(r.events["time"][0] - TAU_F) < 1e-13 and r.events["kind"][0] == 2
        assert abs(r.energy_residual[0]) < 1e-13
        lost = r.events["loss"][0]
        v = G * TAU_F                                    # the landing speed, the same in every DOF
        assert lost == pytest.approx(0.5 * prob.system.impact_mass * v * v, rel=1e-12)   # Eq. (14)


@pytest.mark.parametrize("element, mass", [("P1", "lumped"), ("P1", "consistent"), ("P2", "lumped"),
                                           ("P2", "consistent")])
def test_the_fe_bar_reaches_the_exact_release_and_loses_nothing_in_the_limit(element, mass):
    """Measured (N = 10, 20, 40, 80, 160): the first impact's loss (of the drop's energy ``m g h0``; the impact mass
    times ``v^2 / 2``, a share of one element's mass) falls exactly as ``h`` (orders 1.00); the first release time's
    error as ``h^0.66`` (P1 lumped), ``h^0.82`` (P2 lumped), and erratically with a consistent mass (orders -0.33 to
    1.39: its spurious oscillations at the contact), 0.0042-0.0076 at N = 160 (P1), 0.0017-0.0019 (P2)."""
    err, loss = [], []
    for N in (10, 20, 40, 80):
        bar, prob, r = _drop(N, element, mass)
        ev = r.events
        assert r.status[0] == 0 and abs(r.energy_residual[0]) < 1e-12
        assert ev["kind"][0] == 2 and ev["kind"][1] == 1
        err.append(abs(ev["time"][1] - EXACT[1]))
        loss.append(ev["loss"][0] / (bar.bar_mass * G * H0))
    err, loss = np.array(err), np.array(loss)
    order_t, order_e = np.log2(err[:-1] / err[1:]), np.log2(loss[:-1] / loss[1:])
    assert np.all(np.abs(order_e - 1.0) < 0.01)
    assert err[-1] < 0.013 and err[-1] < 0.4 * err[0]
    if mass == "lumped":
        lo, hi = (0.6, 0.72) if element == "P1" else (0.75, 0.9)
        assert np.all((order_t > lo) & (order_t < hi))


def _falling_chain(n=6, e=0.0, q=None, g=0.2):
    """A free-free chain of ``n`` masses and springs (no support) under gravity towards the stop on its last mass."""
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[0, 0] = K[-1, -1] = 1.0
    M = np.eye(n) * np.linspace(1.0, 1.5, n)
    r = np.zeros(n)
    r[-1] = 1.0
    return plbar.Structure(M, 3.0 * K, r, np.zeros(n) if q is None else q, restitution=e, q_s=g * np.diag(M))


@pytest.mark.parametrize("e, loaded", [(0.0, False), (0.0, True), (0.5, True)])
def test_a_chain_dropped_under_gravity_is_the_test_integrator_s_motion(e, loaded):
    n = 6
    st = _falling_chain(n, e, 0.3 * np.linspace(1, -1, n) if loaded else None)
    prob = plbar.problem(st)
    assert prob.system.rigid == 1 and prob.statics.accel is not None
    assert prob.statics.accel[0] == pytest.approx(st.q_s @ prob.system.V2[:, 0], rel=1e-14)
    x0, v0 = -np.linspace(0.5, 0.3, n), np.full(n, 0.4)      # thrown at the stop, then falling back on it
    T, periods = 5.0, 6
    times, kinds, losses, x_end, v_end = motion(st, T, periods * T, x0, v0, True)
    r = run(prob, np.array([T]), periods=periods, record=periods, start=given(prob, x0, v0))
    assert r.status[0] == 0
    ev = r.events
    if e > 0 and np.any(ev["kind"] == 4):     # the rebounds accumulate (plbar's kind 4), which the test's
        t_stick = ev["time"][ev["kind"] == 4][0]       # integrator does not follow: compare what comes before
        keep = times < t_stick - 1e-3
        times, kinds, losses = times[keep], kinds[keep], losses[keep]
        ev = ev[:times.size]
    assert times.size >= 7 and np.sum(kinds == 2) + np.sum(kinds == 3) >= 4
    assert np.array_equal(ev["kind"], kinds)
    assert np.max(np.abs(ev["time"] - times)) < 1e-9
    assert np.max(np.abs(ev["loss"] - losses)) < 1e-9 * max(losses.max(), 1e-300)
    if e == 0.0:
        assert np.max(np.abs(st.physical(r.strobe_x[0, -1]) - x_end)) < 1e-8 * np.abs(x_end).max()
    assert abs(r.energy_residual[0]) < 1e-12


def test_the_periodic_solvers_refuse_a_constant_load_on_the_rigid_motion_by_name():
    with pytest.raises(InputError, match="rigid-body motion of the free state"):
        plbar.solve(plbar.Case(structure=_falling_chain(q=0.3 * np.ones(6))))


# -- a crack pressed shut by the weight of the part above it ---------------------------------------------------------

@pytest.mark.parametrize("T", [3.0, 5.0])
def test_a_crack_pressed_shut_by_gravity_breathes_as_the_test_integrator_says(T):
    """A bar standing on its clamp, cracked at mid-height: the outer part floats in the free state, and its weight
    (``gravity < 0``: along ``-x``, towards the clamp) presses the crack shut.  At rest the stop holds it (state I,
    a compressive reaction); the harmonic load above the crack opens it now and then.  The theorem without the
    weight (no periodic contact, tests/model/test_crack.py) does not apply: the crack keeps breathing to the end."""
    bar = plbar.Bar(np.linspace(0.0, 1.0, 9), crack_at=0.5)
    st = plbar.model.bar_structure(bar, plbar.point(0.75, 0.1), gravity=-0.2)
    prob = plbar.problem(st)
    assert prob.system.floating and prob.statics.accel is not None and prob.statics.rest_state == 0
    assert -prob.statics.reaction > 0                              # the stop pushes: the crack is pressed shut
    periods = 12
    x0 = st.physical(prob.statics.x1)
    times, kinds, losses, x_end, v_end = motion(st, T, periods * T, x0, np.zeros(st.n), False)
    r = run(prob, np.array([T]), periods=periods, record=periods)
    assert r.status[0] == 0 and np.array_equal(r.events["kind"], kinds) and times.size >= 8
    assert np.max(np.abs(r.events["time"] - times)) < 1e-9
    assert np.max(np.abs(r.events["loss"] - losses)) < 1e-9 * losses.max()
    assert abs(r.energy_residual[0]) < 1e-12
    assert times.max() > (periods - 2) * T                         # breathing to the end
