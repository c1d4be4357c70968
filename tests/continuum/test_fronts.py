"""Why the undamped continuum has no periodic response with an impact loss (docs/continuum.md), against brute force.

A plastic impact of the end mass stops it: its velocity jumps by ``-v`` while the incoming wave is continuous, so the
outgoing invariant ``w_out = 2 v(L) - w_in`` jumps by ``-2 v``.  That front is reflected by the clamp (``w+ = -w-``)
and by the end, stuck (``w_out = -w_in``) or moving (``v(L)`` continuous, the mass has inertia), each time unchanged
in size: ``w_out`` jumps by ``-2 v`` at ``t_1 + k 2L/c`` for every ``k``.  A T-periodic motion with impacts would
carry the jumps of all its past impacts, one sign, at every ``t_i + j T + k 2L/c``: without bound.  So the undamped
continuum with an end mass has no periodic response with a loss, and its motion from rest keeps its fronts.
"""

import numpy as np

import plbar.continuum as pc
from plbar.continuum.fields import w_out


def test_an_impacts_front_is_carried_for_ever():
    """The first impact's jump in ``w_out`` is found again at every ``t_1 + 2k L/c``, its size kept to the solver's
    accuracy (a drift below 1 % of it over 10 round trips at n = 64, and smaller at n = 128)."""
    drift = {}
    for n in (64, 128):
        cr = pc.simulate(pc.ContinuumBar(end_mass=0.5, s=0.37), 2.5, periods=10, steps_per_L=n, record=1)
        ev = cr.events
        i = np.flatnonzero(ev["kind"] == 2)[0]
        t1, v1 = ev["time"][i], ev["v"][i]
        t = t1 + 2.0 * np.arange(11)
        J = w_out(cr.line, t + 1e-9) - w_out(cr.line, t - 1e-9)
        assert abs(J[0] + 2 * v1) <= 1e-3 * abs(v1)           # the impact's own jump
        drift[n] = np.abs(J + 2 * v1).max() / abs(2 * v1)
        # between the fronts w_out is continuous: no jump of that size anywhere else on a round trip
        mid = t[:-1] + 1.0
        assert np.all(np.abs(w_out(cr.line, mid + 1e-9) - w_out(cr.line, mid - 1e-9)) < 1e-3 * abs(v1))
    assert drift[64] < 0.01 and drift[128] < drift[64]
