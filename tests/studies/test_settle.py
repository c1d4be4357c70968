"""Settling motions (issue 28): a motion still approaching a stable orbit is periodic, with the evidence.

Brute force: the simulation carried on from the survey's final state until its window repeats (the compiled
simulator alone, no orbit) must land on the orbit the survey named: same period, loss per period equal to the
polished orbit's.
"""

import numpy as np
import pytest

import plbar
from plbar.motion import padded, run, steady
from plbar.studies.survey import survey_chunk
from plbar.studies.survey.settle import CANDIDATE, SETTLED, approach, candidate_periods, orbit_of, settle

#: default case, 600 periods from rest: still approaching a weakly stable orbit (multiplier 0.98-0.99)
SLOW_T = [12.1, 12.9]


@pytest.fixture(scope="module")
def slow():
    case = plbar.Case()
    rows, final = survey_chunk(case, SLOW_T, 600, 60)
    return case, rows, final


def test_a_settling_motion_is_reported_periodic_with_its_distance_and_rate(slow):
    _, rows, _ = slow
    for row, sig in zip(rows, ("1P", "1PZ")):
        assert row["kind"] == "periodic" and row["m"] == 1 and row["signature"] == sig
        assert row["distance"] > 1e-6                     # the window alone does not repeat to 1e-6 ...
        assert 1e-7 < row["orbit_distance"] <= SETTLED     # ... it is on its way to the orbit
        # a linear approach: the measured rate per period is the orbit's largest multiplier
        assert row["rate"] == pytest.approx(row["max_abs_multiplier"], abs=2e-3)
        assert row["max_abs_multiplier"] < 1
        assert row["loss_per_T"] == pytest.approx(row["exact_loss"], rel=1e-4)


def test_carried_on_the_motion_lands_on_the_orbit_the_survey_named(slow):
    """Brute force: 3,000 more periods from the final state; the window then repeats to 1e-6 (no orbit needed),
    with the survey's period, and its mean loss per period is the polished orbit's (1e-8)."""
    case, rows, final = slow
    r = run(padded(case.problem()), np.array(SLOW_T), 0.0, 3000, 100, final)
    s = steady(r)
    assert list(s.kind_names) == ["periodic", "periodic"]
    for i, row in enumerate(rows):
        assert s.m[i] == row["m"] and s.distance[i] <= 1e-6
        assert s.loss_per_T[i] == pytest.approx(row["exact_loss"], rel=1e-8)


def test_the_orbit_distance_decays_at_the_orbits_rate_across_the_window(slow):
    """The distance from the orbit measured over a longer window falls by rate^periods (the rate stays)."""
    case, rows, final = slow
    prob = case.problem()
    r = run(padded(prob), np.array(SLOW_T), 0.0, 200, 150, final)
    for b, row in enumerate(rows):
        a = approach(r, b, orbit_of(prob, r, b, row["m"]))
        e = a.distance
        assert e[-1] < e[0] < row["orbit_distance"]
        assert a.rate == pytest.approx(row["rate"], abs=1e-3)


def test_irregular_motions_do_not_settle():
    """T = 9.5 approaches a 3ZZPZP orbit over the window, but not at a rate of its multipliers (0.998 per period
    against |mu|^(1/3) = 0.99983, 0.944): carried on, it repeats only after 40,000 periods, on an orbit of period 9.
    """
    case = plbar.Case()
    rows, _ = survey_chunk(case, [6.8, 7.0, 9.5], 600, 60)
    assert [r["kind"] for r in rows] == ["irregular"] * 3
    assert all("rate" not in r and r["signature"] == "" for r in rows)


def test_a_periodic_row_is_on_its_orbit():
    rows, _ = survey_chunk(plbar.Case(), [9.0, 11.8], 1000, 100)
    for row in rows:
        assert row["kind"] == "periodic" and row["orbit_distance"] < 1e-9 and "rate" not in row
        assert row["max_abs_multiplier"] < 1


def test_candidate_periods_of_a_geometric_approach():
    """An approach to a period-3 cycle at rate 0.97 per period: 3 (and its multiples) are candidates, 1 and 2 not."""
    R, n = 60, 4
    rng = np.random.default_rng(1)
    cycle = rng.normal(size=(3, n))
    r = np.arange(R + 1)
    z = cycle[r % 3] + 0.5 * CANDIDATE * np.outer(0.97 ** r, rng.normal(size=n))
    assert candidate_periods(z) == [3, 6, 9, 12]
    assert candidate_periods(cycle[r % 3] + 0.5 * rng.normal(size=(R + 1, n))) == []


def test_settle_needs_a_stable_orbit():
    """T = 8.7: the repeat distance shrinks toward the 1Z orbit, which is unstable (|mu| = 1.02): not settled."""
    case = plbar.Case()
    prob = case.problem()
    r = run(padded(prob), np.array([8.7]), 0.0, 600, 60)
    assert settle(prob, r, 0) is None
    m = candidate_periods(np.concatenate([r.strobe_x[0], r.strobe_v[0]], axis=1))
    a = approach(r, 0, orbit_of(prob, r, 0, m[0]))
    assert a.max_abs_multiplier > 1 and not a.settled
