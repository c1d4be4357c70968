"""The continuum started from a given field (plbar.continuum.Field, issue 41 item 5).

* Dabaghi et al.'s clamped bar released compressed against the wall (GetFEM's ``demo_dynamic_contact_1D.py``, its
  closed form ``uExact``): ``u0 = -X / 2`` at rest, the wall at the end, no load, no end mass.  The exact solution
  is periodic of period 3: the end reaches the wall at ``t = 1 + 3 k`` and leaves it at ``t = 2 + 3 k``, and the
  energy 1/8 is kept.  plbar's characteristics from the field: every event time of 20 contact cycles to 1e-10.
* The same bar held open (``hold="open"``, no wall), where d'Alembert by hand gives the end's motion: a triangle
  wave between ``-a`` and ``a`` of period ``4 L / c``.
* Any field: its energy at ``t = 0`` is the test's quadrature of the piecewise-linear field, and a bar with no end
  mass keeps it through its contacts (round-off).
* The refusals: a field off the grid, moving on the clamp, past the wall.
"""

import numpy as np
import pytest

from plbar.continuum import ContinuumBar, Field, simulate
from plbar.errors import InputError

N = 16
X = np.linspace(0.0, 1.0, N + 1)
FREE_BAR = ContinuumBar(1.0, 1.0, 1.0, 0.0, 0.5, 0.0)        # L = EA = rhoA = 1 (c = 1), no end mass, no load


def test_dabaghis_bar_meets_its_closed_form_over_twenty_cycles():
    r = simulate(FREE_BAR, 3.0, periods=20, steps_per_L=N, start=Field(-0.5 * X, np.zeros(N + 1)), record=2)
    ev = r.events
    exact = np.sort(np.r_[1.0 + 3 * np.arange(20), 2.0 + 3 * np.arange(20)])
    assert ev.size == exact.size and np.array_equal(ev["kind"], np.tile([2, 1], 20))   # impact, then opening
    assert np.max(np.abs(ev["time"] - exact)) < 1e-10
    assert np.max(np.abs(r.energy - 0.125)) < 1e-13 and ev["loss"].sum() == 0.0
    assert np.max(np.abs(r.end[:, 0] - (-0.5))) < 1e-12          # at every t = 3 k: back to the start


@pytest.mark.parametrize("a", [0.5, 0.2])
def test_a_field_held_open_is_dalemberts_triangle_wave(a):
    """No wall: the end released from ``u0 = -a X`` moves at ``+-a`` (the incoming invariant), a triangle wave."""
    T = 0.7
    r = simulate(FREE_BAR, T, periods=20, steps_per_L=N, start=Field(-a * X, np.zeros(N + 1)), hold="open")
    t = T * np.arange(21)
    phase = np.mod(t, 4.0)
    exact = np.where(phase <= 2.0, -a + a * phase, a - a * (phase - 2.0))
    assert r.events.size == 0
    assert np.max(np.abs(r.end[:, 0] - exact)) < 1e-12


def test_any_field_carries_its_energy_through_its_contacts():
    rng = np.random.default_rng(7)
    u = np.r_[0.0, rng.uniform(-0.2, 0.2, N - 1), -0.1]
    v = np.r_[0.0, rng.uniform(-0.3, 0.3, N)]
    h = 1.0 / N
    ux = np.diff(u) / h
    energy = 0.5 * np.sum(h * ux ** 2) + 0.5 * np.sum(h * (v[:-1] ** 2 + v[:-1] * v[1:] + v[1:] ** 2) / 3)
    r = simulate(FREE_BAR, 1.3, periods=6, steps_per_L=N, start=Field(u, v))
    assert r.events.size > 2 and (r.events["kind"] == 2).any()
    assert abs(r.energy[0] - energy) < 1e-14 * energy
    assert np.max(np.abs(r.energy - energy)) < 1e-12 * energy


@pytest.mark.parametrize("u, v, match", [
    (np.zeros(N), np.zeros(N), "grid"),
    (np.r_[0.1, np.zeros(N)], np.zeros(N + 1), "clamp"),
    (0.1 * X, np.zeros(N + 1), "past the wall"),
])
def test_a_bad_field_is_refused(u, v, match):
    with pytest.raises(InputError, match=match):
        simulate(FREE_BAR, 3.0, periods=1, steps_per_L=N, start=Field(u, v))
