"""A survey row's window statistics are taken over whole orbits of the period it names (issue 44).

On the default chain at T = 13.6 (385 periods from rest, the last 100 recorded) the motion settles on the 1PZ
orbit slowly, turning about 2 pi / 7 a period: the window repeats to the survey's tolerance first at m = 7, and
the row averaged over 98 periods (7 x 14) while naming the polished orbit's m = 1.
"""

import numpy as np
import pytest

import plbar
from plbar.studies.survey.points import survey_chunk

T, PERIODS, RECORD = 13.6, 385, 100


def test_a_row_naming_m_1_averages_over_the_whole_window():
    (row,), _ = survey_chunk(plbar.Case(), [T], PERIODS, RECORD)
    assert row["kind"] == "periodic" and row["m"] == 1 and row["signature"] == "1PZ"
    # the independent simulator's impact losses over the last 100 periods, and over the last 98
    prob = plbar.Case().problem()
    n = prob.system.n
    sim = plbar.simulate(prob, T, 0.0, np.zeros(n), np.zeros(n), n_periods=PERIODS)
    t, loss = np.asarray(sim.impact_times), np.asarray(sim.impact_losses)
    mean = lambda k: loss[t > (PERIODS - k) * T].sum() / k
    assert abs(mean(100) - mean(98)) > 1e-8                        # the two windows differ by more than ...
    assert row["loss_per_T"] == pytest.approx(mean(100), rel=1e-10, abs=0)   # ... the agreement asked here
    assert row["impacts_per_T"] == pytest.approx(np.sum(t > (PERIODS - 100) * T) / 100, rel=1e-12)
    # its distance is the repeat distance at m = 1 (still settling: above the repeat tolerance)
    z = np.concatenate([sim.strobe_x, sim.strobe_v], axis=1)[-RECORD - 1:]
    d1 = np.linalg.norm(z[1:] - z[:-1], axis=1).max() / np.linalg.norm(z, axis=1).max()
    assert row["distance"] == pytest.approx(d1, rel=1e-3)
