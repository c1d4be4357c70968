"""Stiff Rayleigh damping: the simulator's certified steps shorten (the Taylor model is scaled by the fastest
decay, ``beta omega_max^2``), so a fine damped mesh can take thousands of rounds between two events.  Such rounds
are progress, not a stall (``loop.PROGRESS``); it used to stop as ``stalled`` after 5,000 of them (P2 redistributed
N = 256 at 2 %, N = 512 at 1 %)."""

import numpy as np

import plbar
from plbar.continuum import ContinuumBar, simulate_modal
from plbar.motion import OK, padded, run
from plbar.motion.kernel.loop import MAX_STALL


def test_a_stiffly_damped_fine_mesh_runs_and_opens_when_the_damped_continuum_does():
    ray = plbar.rayleigh_from_ratio(0.2, 2.0, 4.0)
    prob = plbar.Case(model="fe", n=128, element="P2", mass="redistributed", end_mass=0.5,
                      load_points=((0.37, 1.0),), rayleigh=ray).problem()
    r = run(padded(prob), np.array([2.5]), 0.0, 1, 1)
    assert r.status[0] == OK and r.rounds > MAX_STALL          # more rounds before its first event than the limit
    t_fe = r.events["time"][r.events["kind"] == 1][0]
    m = simulate_modal(ContinuumBar(end_mass=0.5, s=0.37), 2.5, 1, ray, modes=512)
    t_c = m.events["time"][m.events["kind"] == 1][0]
    assert abs(t_fe - t_c) < 1e-6                              # the opening of the damped continuum (1.1326136)
