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

import plbar
from plbar.errors import InputError
from plbar.motion import padded, run
from event_integrator import assert_same_motion


def _gapped(case: plbar.Case, d: float, scale: float = 1.0) -> plbar.Problem:
    st = case.problem().structure
    return plbar.problem(replace(st, gap=d, q=st.q * scale, origin=None))


CASES = {"chain": plbar.Case(), "fe consistent": plbar.Case(model="fe", n=6, element="P1", mass="consistent")}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n == "fe consistent" else n
                                  for n in CASES])     # the FE bar's, the longest, with the slow tests
@pytest.mark.parametrize("d", [0.4, -0.3])
def test_the_motion_with_a_gap_is_the_integrators(name, d):
    case = CASES[name]
    prob = _gapped(case, d * (1.0 if name == "chain" else 0.05))
    pad = padded(prob)
    T, periods = 9.3, 12
    r = run(pad, np.array([T]), 0.0, periods, periods)
    assert pad.rest_state == (1 if prob.gap > 0 else 0)
    assert_same_motion(prob.structure, r, T, periods, state=pad.rest_state)


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


#: a constant load (FORMULATION §9, affine terms): (name, gap, q_s as a multiple of M 1, the start state)
PRELOADS = [("gravity onto the stop, no gap", 0.0, 0.05, 0), ("gravity away from the stop", 0.0, -0.05, 1),
            ("gravity onto a clearance it does not close", 0.6, 0.02, 1),
            ("gravity that closes a clearance", 0.1, 0.08, 0),
            ("gravity onto an interference", -0.2, 0.03, 0)]


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("what,d,g,state", PRELOADS, ids=[p[0] for p in PRELOADS])
def test_a_constant_load_is_the_integrators(name, what, d, g, state):
    """A constant load ``q_s = g M 1`` (gravity along the bar) beside the harmonic one, with and without a gap:
    the simulator's motion from its static equilibrium against the integrator's, event times to 1e-9, the losses,
    the end state and the energy budget (the constant load's potential in the mechanical energy) to 1e-12."""
    case = CASES[name]
    s = 1.0 if name == "chain" else 0.05
    st = case.problem().structure
    prob = plbar.problem(replace(st, gap=d * s, q_s=g * s * (st.M @ np.ones(st.n)) / (st.M.sum() / st.n),
                                 origin=None))
    pad = padded(prob)
    assert pad.rest_state == state
    T, periods = 9.3 if name == "chain" else 2.1, 12
    r = run(pad, np.array([T]), 0.0, periods, periods)
    assert_same_motion(prob.structure, r, T, periods, state=state)


def test_a_constant_load_scales_with_the_load():
    """Homogeneity with a constant load: ``(lambda d, lambda q, lambda q_s)`` is ``lambda`` times the motion."""
    T = np.linspace(6.0, 13.0, 8)
    st = plbar.Case().problem().structure
    base = replace(st, gap=0.3, q_s=0.04 * (st.M @ np.ones(st.n)), origin=None)
    a = run(padded(plbar.problem(base)), T, 0.0, 40, 40)
    for lam in (0.01, 4.0):
        b = run(padded(plbar.problem(replace(base, gap=lam * base.gap, q=lam * base.q, q_s=lam * base.q_s))),
                T, 0.0, 40, 40)
        assert np.array_equal(a.events["kind"], b.events["kind"])
        assert np.max(np.abs(a.events["time"] - b.events["time"])) < 1e-12 * T.max() * 40
        assert np.max(np.abs(lam * a.strobe_x - b.strobe_x)) < 1e-12 * lam * np.abs(a.strobe_x).max()
