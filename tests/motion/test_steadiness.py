"""Steadiness of a motion over the recorded window (issue 29): the trend test of :func:`plbar.motion.trend`."""

import numpy as np
import pytest

import plbar
from plbar.motion import BATCHES, DRIFT_TOL, T_CRIT, padded, run, steady, trend


def test_trend_of_a_constant_a_ramp_and_noise():
    R = 200
    t = np.arange(R)
    rows = np.stack([np.full(R, 2.0), 1.0 + 0.5 * t / R, 1.0 - 0.3 * t / R])
    drift, tt = trend(rows)
    assert drift[0] == 0.0 and tt[0] == 0.0
    # a straight line: the batch means lie on it, its change across the window relative to the mean
    mean1, mean2 = rows[1].mean(), rows[2].mean()
    assert drift[1] == pytest.approx(0.5 / mean1, rel=1e-12)       # slope 0.5 / R per period, times R
    assert drift[2] == pytest.approx(-0.3 / mean2, rel=1e-12)
    assert np.isinf(tt[1]) or tt[1] > 1e6
    # white noise: significant at 1 % in about 1 % of the rows (8 degrees of freedom), never a large drift
    rng = np.random.default_rng(0)
    noise = 1.0 + 0.1 * rng.standard_normal((2000, R))
    d, tn = trend(noise)
    flagged = (np.abs(d) > DRIFT_TOL) & (np.abs(tn) > T_CRIT)
    assert flagged.mean() < 0.01 and np.abs(d).max() < 0.1
    assert np.mean(np.abs(tn) > T_CRIT) == pytest.approx(0.01, abs=0.006)
    assert BATCHES == 10


def test_the_survey_says_whether_a_motion_is_steady():
    """Periodic motions are steady; a survey row carries steady, drift_loss and drift_vMv."""
    prob = plbar.Case().problem()
    r = run(padded(prob), np.array([12.2, 7.0]), 0.0, 1000, 100)
    s = steady(r, tol=1e-3)                                        # settling on its orbit (1P)
    assert s.kind[0] == 0 and s.steady[0] == 1                     # the paper's class at T = 12.2: periodic
    assert abs(s.drift_vMv[0]) < 1e-3 and abs(s.drift_loss[0]) < 1e-3
    from plbar.studies.survey import COLUMNS

    assert {"steady", "drift_loss", "drift_vMv"} <= set(COLUMNS)
