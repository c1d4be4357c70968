"""An Euler-Bernoulli beam against a stop (issue 41 item 2), checked against the beam's closed forms and against
the test's own integrator (not plbar's simulator).

* natural frequencies, ``w_n = (beta_n L)^2 sqrt(EI / (rhoA L^4))``: free (state II) and with the stop holding
  (state I), for the three supports (the classical ``beta_n L``, e.g. Blevins, Formulas for natural frequency);
* the stiffness the stop sees (the Schur complement: the reaction per unit of interference) against
  ``3 EI / s^3`` (a cantilever at ``s``), ``48 EI / L^3`` and ``192 EI / L^3`` (mid-span, pinned and clamped);
* gravity: the tip of a cantilever sinks by ``rhoA g L^4 / (8 EI)``, the middle of a pinned beam by
  ``5 rhoA g L^4 / (384 EI)`` (Hermite elements are exact at the nodes);
* the motion from rest of a cantilever with a tip stop and a clearance, and a periodic response, against
  ``tests/event_integrator.py``: event times 1e-9, energy budget 1e-12.
"""

import numpy as np
import pytest

import plbar
from plbar.errors import InputError
from plbar.model.beam import beam_structure, uniform_beam
from plbar.motion import padded, run

from event_integrator import assert_same_motion

#: beta_n L of the classical beams (the roots of their frequency equations)
BETA = {"clamped-free": [1.875104068711961, 4.694091132974175, 7.854757438237613],
        "pinned-pinned": [np.pi, 2 * np.pi, 3 * np.pi],
        "clamped-clamped": [4.730040744862704, 7.853204624095838, 10.99560783800167],
        "clamped-pinned": [3.926602312047919, 7.068582745628732, 10.21017612281303]}


@pytest.mark.parametrize("supports, held", [("clamped-free", "clamped-pinned"),
                                            ("pinned-pinned", None), ("clamped-clamped", None)])
def test_the_frequencies_are_the_beams(supports, held):
    """The first three free frequencies and the first held ones to 1e-4 at 24 elements (the fundamental to 2e-6),
    converging as ``h^4``
    (cubic elements, consistent mass: the error of 12 elements 14 to 18 times that of 24)."""
    EI, rhoA, L = 2.0, 0.5, 1.5
    scale = np.sqrt(EI / (rhoA * L ** 4))
    w2 = np.array(BETA[supports]) ** 2 * scale
    # held at the tip, a cantilever is clamped-pinned; held at mid-span, the antisymmetric modes (even) come first
    w1 = (np.array(BETA[held]) if held else np.array(BETA[supports])[1::2][:1]) ** 2 * scale
    err = []
    for n in (12, 24):
        prob = plbar.problem(beam_structure(uniform_beam(n, L, EI, rhoA, supports), forces=((0.3 * L, 1.0),)))
        e2 = prob.system.w2[:3] / w2 - 1
        e1 = prob.system.w1[:w1.size] / w1 - 1
        assert np.all(e2 > 0) and np.all(e1 > 0)              # a consistent mass: upper bounds (Rayleigh-Ritz)
        err.append(np.concatenate([e2, e1]))
    assert np.max(err[1]) < 1e-4 and err[1][0] < 2e-6
    ratio = err[0] / err[1]
    assert np.all((14 < ratio) & (ratio < 18)), ratio


@pytest.mark.parametrize("supports, s, k", [("clamped-free", 1.0, 3.0), ("clamped-free", 0.5, 24.0),
                                            ("pinned-pinned", 0.5, 48.0), ("clamped-clamped", 0.5, 192.0)])
def test_the_stiffness_the_stop_sees(supports, s, k):
    d = -0.01                                                     # an interference: the stop pushes
    prob = plbar.problem(beam_structure(uniform_beam(8, supports=supports), forces=((0.25, 1.0),), contact_at=s,
                                        gap=d))
    assert prob.statics.reaction == pytest.approx(k * d, rel=1e-11)
    assert prob.statics.rest_state == 0


def test_gravity_deflects_the_beam_as_its_closed_form():
    g = 0.7
    cant = plbar.problem(beam_structure(uniform_beam(6), forces=((0.5, 1.0),), gravity=g, gap=1.0)).statics
    assert cant.x2[-1] == pytest.approx(g / 8, rel=1e-12)           # the contact coordinate: the tip's deflection
    pin = plbar.problem(beam_structure(uniform_beam(6, supports="pinned-pinned"), forces=((0.25, 1.0),),
                                       gravity=g, gap=1.0)).statics
    assert pin.x2[-1] == pytest.approx(5 * g / 384, rel=1e-12)


def test_a_stop_between_nodes_and_what_is_refused():
    b = uniform_beam(10)
    st = beam_structure(b, forces=((1.0, 1.0),), contact_at=0.35, gap=-0.01)
    assert np.count_nonzero(st.contact) == 4                       # the two nodes' deflections and slopes
    assert plbar.problem(st).statics.reaction == pytest.approx(3 / 0.35 ** 3 * -0.01, rel=1e-3)
    with pytest.raises(InputError, match="support"):
        beam_structure(b, forces=((1.0, 1.0),), contact_at=0.0)
    with pytest.raises(InputError, match="supports"):
        uniform_beam(4, supports="free-free")
    with pytest.raises(InputError, match="not on the beam"):
        beam_structure(b, forces=((1.5, 1.0),))


def _hits_a_tip_stop(n: int, periods: int):
    """A cantilever of ``n`` elements with a tip mass against a tip stop at a clearance: plbar's motion from rest
    against the test's integrator.  Its higher modes make the tip chatter (a dozen impacts a period): every one
    an event of both."""
    st = beam_structure(uniform_beam(n, supports="clamped-free", point_masses=((1.0, 0.5),)), forces=((0.5, 1.0),),
                        gap=0.05)
    prob = plbar.problem(st)
    T = 3.5                                    # above the fundamental free period 2 pi / 2.016
    r = run(padded(prob), np.array([T]), 0.0, periods, periods)
    assert r.events.size > 8 * periods
    assert_same_motion(st, r, T, periods)


def test_a_cantilever_hitting_a_tip_stop_is_the_integrators():
    _hits_a_tip_stop(2, 2)


@pytest.mark.slow
def test_a_finer_cantilever_hitting_a_tip_stop_is_the_integrators():
    _hits_a_tip_stop(4, 3)
