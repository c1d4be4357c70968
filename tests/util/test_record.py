"""The one run record (issue 40): every simulator returns a Record, events of one dtype, status from one table."""

import numpy as np
import pytest

import plbar
import plbar.continuum as pc
from plbar import motion
from plbar.check import simulate
from plbar.util.record import CHATTER, EVENT, OK, STALLED, STATUS, Record, events


def _records():
    prob = plbar.Case().problem()
    bar = pc.ContinuumBar()
    x0 = np.zeros(prob.system.M.shape[0])
    return {"motion": motion.run(motion.padded(prob), [7.0, 9.6], 0.0, 4, 2),
            "check": simulate(prob, 7.0, 0.0, x0, x0, n_periods=2),
            "continuum": pc.simulate(bar, 2.5, periods=2, steps_per_L=16, record=1),
            "modal": pc.simulate_modal(bar, 2.5, 2, (0.01, 0.0), modes=64, record=1)}


@pytest.fixture(scope="module")
def records():
    return _records()


def test_every_simulator_returns_one_record_shape(records):
    """The same fields with the same types: T, phi, an integer status per trajectory, events of dtype EVENT (in time
    order per trajectory; openings and impacts among them)."""
    for name, r in records.items():
        assert isinstance(r, Record), name
        assert r.events.dtype == EVENT, name
        assert r.status.dtype.kind == "i" and r.status.shape == np.shape(r.T) or r.status.shape == (1,), name
        assert r.success and r.message == STATUS[OK], name
        for b in np.unique(r.events["traj"]):
            t = r.events["time"][r.events["traj"] == b]
            assert np.all(np.diff(t) >= 0), name
        assert set(np.unique(r.events["kind"])) >= {1, 2}, name


def test_the_status_table_is_the_motion_kernels():
    """The kernel's codes are the table's: a stopped trajectory's message is read from it."""
    assert (motion.OK, motion.CHATTER, motion.STALLED) == (OK, CHATTER, STALLED)
    r = Record(T=np.ones(3), phi=np.zeros(3), status=np.array([OK, CHATTER, CHATTER]), events=events([], [], []))
    assert not r.success and r.message == f"2 of 3 stopped by {STATUS[CHATTER]}"


def test_event_columns_default_to_one_trajectory_and_no_velocity():
    ev = events([0.5, 1.0], [1, 2], [0.0, 0.3])
    assert ev.dtype == EVENT and np.all(ev["traj"] == 0) and np.all(np.isnan(ev["v"]))
    assert ev["kind"].tolist() == [1, 2] and ev["loss"][1] == 0.3
