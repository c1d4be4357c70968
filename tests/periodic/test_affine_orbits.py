"""Periodic responses with a gap or a constant load, replayed by the test's own integrator (not plbar's simulator).

From each orbit's start (:attr:`plbar.periodic.Orbit.start`: the static equilibrium of its state plus its modal
state), :func:`event_integrator.motion` integrates the structure's own equations over the orbit's ``m`` forcing
periods: it must meet the orbit's switches (:func:`plbar.periodic.expected_events`) and come back to the start to 1e-7,
and the impact losses must be the orbit's (Eq. (14), Newton's law).  The switch times agree to 1e-9 of ``m T``
(the median orbit's worst, and half the switches of every orbit) and to 3e-7 everywhere (1.2e-7 measured on the
FE bar's worst orbit, in a fresh venv; 1e-7 before): a switch the motion
meets at a shallow angle (an impact at a small velocity, a reaction that crosses zero slowly) turns the
integrator's 1e-13 error in the state into ``1e-13 / slope`` in the time.  A middle
orbit of every branch with ``m <= 2`` of ``plbar.solve`` is replayed, for the chain with a clearance, the chain
with gravity onto the stop and an FE bar (consistent mass) with a clearance.
"""

from dataclasses import replace

import numpy as np
import pytest

import plbar
from plbar.periodic import expected_events

from event_integrator import motion


def _chain_gravity():
    st = plbar.Case().problem().structure
    return plbar.Case(structure=replace(st, q_s=0.05 * (st.M @ np.ones(st.n)), origin=None))


CASES = {"chain, gap 0.5": lambda: plbar.Case(gap=0.5),
         "chain, gravity onto the stop": _chain_gravity,
         "fe consistent, gap 0.02": lambda: plbar.Case(model="fe", n=6, mass="consistent", gap=0.02)}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n.startswith("fe") else n
                                  for n in CASES])     # the FE bar's, the longest, with the slow tests
def test_every_branch_replays(name):
    res = plbar.solve(CASES[name]())
    st = res.prob.structure
    assert st.contact[-1] == 1 and not np.any(st.contact[:-1])        # contact coordinates are the DOFs
    orbs = [b.orbits[len(b) // 2] for b in res.branches if b.sig.m <= 2]
    assert len(orbs) >= 5
    worst = []
    for o in orbs:
        x0, v0 = o.start
        span = o.sig.m * o.T
        times, kinds, losses, x1, v1 = motion(st, o.T, span * (1 + 1e-9), x0, v0, o.free_start, o.phi)
        et, ek = expected_events(o)
        k = et.size                                       # beyond: the next period's (at m T, within the overrun)
        assert np.array_equal(kinds[:k], ek) and np.all(times[k:] >= span * (1 - 1e-9)), (o, times, kinds, et, ek)
        err = np.abs(times[:k] - et) / span
        assert err.max() < 3e-7 and np.mean(err < 1e-9) >= 0.5, err       # see the module docstring
        worst.append(err.max())
        # the integration runs 1e-9 m T past the closing impact (to see it), so the state moves on by that much
        scale = max(np.abs(x0).max(), np.abs(v0).max())
        assert np.max(np.abs(x1 - x0)) < 1e-7 * scale and np.max(np.abs(v1 - v0)) < 1e-7 * scale
        assert losses.sum() == pytest.approx(o.dPL, rel=1e-8, abs=1e-12 * max(o.dPL, 1.0))
    assert np.median(worst) < 1e-9
