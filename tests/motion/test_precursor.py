"""The undamped P2 bar from rest (issue 29, item 5): the contact's precursor against a 40-digit integration.

Before the load's front arrives (t ~ 0.63) the contact reaction of a consistent-mass P2 bar is real but tiny (2e-16
at t = 0, 1e-10 of the size of its terms at t ~ 0.06): the contact leaves and comes back in flights whose losses grow
from 1e-35 to 1e-4.  The kernel dropped such derivatives as round-off (below SIGNIFICANT = 1e-9 of their terms): a
step crossed an opening and the trajectory then ping-ponged between zero-length impacts and openings at one instant
until the chatter guard stopped it (status CHATTER).  The reference is the discrete model integrated independently in
40 digits (``tests/bench/p2_precursor_reference.py``); the kernel resolves the margin to its round-off level (2e-13
of the reaction's size), which the flights exceed from t ~ 0.12 on.
"""

import numpy as np

import plbar
from plbar.motion import OK, boundary_mismatch, motion_series, padded, run

#: (time, kind 1 opening / 2 impact, loss) from tests/bench/p2_precursor_reference.py, 0.129 < t < 0.7
REFERENCE = [
    (0.12931260560766587, 1, 0),
    (0.15445236371106274, 2, 1.33421e-17),
    (0.15484003458433248, 1, 0),
    (0.18178992866543783, 2, 1.24381e-15),
    (0.18178992866543783, 1, 0),
    (0.21047176580146345, 2, 7.55121e-14),
    (0.21047176580146345, 1, 0),
    (0.24048508056180848, 2, 2.653e-12),
    (0.24048508056180848, 1, 0),
    (0.27180835202572317, 2, 4.35993e-11),
    (0.27180835202572317, 1, 0),
    (0.30416511098862317, 2, 2.94589e-10),
    (0.30416511098862317, 1, 0),
    (0.36899921153734499, 2, 6.89716e-8),
    (0.36899921153734499, 1, 0),
    (0.64085664400348621, 2, 0.000136365),
]
WINDOW = (0.129, 0.7)


def test_p2_consistent_from_rest_follows_the_precursor_and_runs_on():
    case = plbar.Case(model="fe", n=32, element="P2", mass="consistent", end_mass=0.5, load_points=((0.37, 1.0),))
    r = run(padded(case.problem()), np.array([2.5]), 0.0, 40, 40)
    assert r.status[0] == OK
    assert abs(r.energy_residual[0]) < 1e-13
    ev = r.events
    time, kind, loss = ev["time"], ev["kind"], ev["loss"]
    assert np.all(np.diff(time) >= 0)
    # no ping-pong: at most an impact and an opening at one instant (a zero-dwell impact)
    _, counts = np.unique(time, return_counts=True)
    assert counts.max() <= 2
    sel = (time > WINDOW[0]) & (time < WINDOW[1])
    ref = np.array(REFERENCE)
    assert kind[sel].tolist() == ref[:, 1].astype(int).tolist()
    np.testing.assert_allclose(time[sel], ref[:, 0], rtol=0, atol=1e-6)
    np.testing.assert_allclose(loss[sel], ref[:, 2], rtol=1e-4, atol=1e-20)
    assert r.impacts.sum() > 40                   # it runs on through the 40 periods (2.6 impacts a period)


def test_a_series_from_rest_replays_an_opening_at_t_zero():
    """P2 redistributed N = 32 opens at t = 0 exactly (its wall reaction is round-off there): the run's first boundary
    state is its initial state, before that event, and the series replays it (before: "an impact recorded in
    contact"); every boundary state is carried to the next to round-off."""
    case = plbar.Case(model="fe", n=32, element="P2", mass="redistributed", end_mass=0.5, load_points=((0.37, 1.0),))
    prob = case.problem()
    r = run(padded(prob), np.array([2.5]), 0.0, 6, 6)
    assert r.events["time"][0] == 0.0 and r.events["kind"][0] == 1
    assert boundary_mismatch(motion_series(prob, r, 0), r, 0) <= 1e-12
