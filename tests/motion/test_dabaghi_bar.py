"""Dabaghi et al.'s clamped bar released compressed against the wall (GetFEM's ``demo_dynamic_contact_1D.py``).

The benchmark (Dabaghi, Petrov, Pousin & Renard 2016; GetFEM's interface/tests/python/demo_dynamic_contact_1D.py,
whose closed form ``uExact`` it checks against): a bar of unit length, ``E = rho = 1`` (``c = 1``), clamped at one
end, its other end ``1/2`` from a rigid wall, released at rest from the uniform compression ``u0 = (1 - x) / 2``
(GetFEM's coordinates: the wall at ``x = 0``, ``u(0) >= 0``).  In plbar's coordinates (the clamp at ``X = 0``, the
stop at ``X = L``, ``U = -u``): ``U0(X) = -X / 2``, no load.  The exact solution is periodic of period 3: the end
reaches the wall at ``t = 1`` at speed 1/2, stays there until ``t = 2`` and leaves at speed 1/2; the energy, 1/8,
is conserved (a continuum's plastic contact without a contact mass loses nothing).

plbar's FE bar from that given start (``plbar.motion.given``, a zero load: the compiled simulator's exact flows
between events) converges to it: the impact loss of the contact node's share of the mass, ``O(h)``, and the
release time with it, measured for P1 and P2, lumped and consistent mass on N = 10 .. 160 (orders fitted by least
squares; the first impact's time converges faster).  A redistributed mass (which would move the contact node's mass
off it, as GetFEM's ``mass_matrix_type = 1`` does) needs an end mass in plbar, and the benchmark has none.
"""

import numpy as np
import pytest

import plbar
from plbar.motion import given, run

NS = (10, 20, 40, 80, 160)
E0 = 0.125                                   # the strain energy of the start, 1/2 (1/2)^2


def _first_period(n: int, element: str, mass: str):
    """(the release time of the first contact, the first impact's time, the fraction of the energy lost by t = 3)."""
    prob = plbar.problem(plbar.Bar(np.linspace(0.0, 1.0, n + 1), element, mass), plbar.point(0.5, 0.0))
    x0 = -0.5 * prob.structure.x
    assert 0.5 * x0 @ prob.structure.K @ x0 == pytest.approx(E0, rel=1e-14)   # a linear field: exact in P1, P2
    r = run(prob, np.array([3.0]), periods=1, record=1, start=given(prob, x0, np.zeros(x0.size)))
    ev = r.events
    kind, t = ev["kind"], ev["time"]
    assert abs(r.energy_residual[0]) < 1e-12
    release = t[(kind == 1) & (t > 1.5) & (t < 2.5)].max()
    return release, t[kind == 2].min(), ev["loss"].sum() / E0


@pytest.mark.parametrize("element", ["P1", pytest.param("P2", marks=pytest.mark.slow)])   # P2: the longest
@pytest.mark.parametrize("mass", ["lumped", "consistent"])
def test_the_fe_bar_converges_to_dabaghis_closed_form(element, mass):
    rows = np.array([_first_period(n, element, mass) for n in NS])
    h = 1.0 / np.array(NS)
    release, first, lost = abs(rows[:, 0] - 2.0), abs(rows[:, 1] - 1.0), rows[:, 2]
    order = {name: np.polyfit(np.log(h), np.log(err), 1)[0]
             for name, err in (("release", release), ("first", first), ("lost", lost))}
    assert 0.85 < order["lost"] < 1.25, order              # the contact node's share of the mass: O(h)
    assert 0.55 < order["release"] < 1.1, order
    assert order["first"] > 1.2, order
    assert lost[-1] < 3e-3 and release[-1] < 1e-2 and first[-1] < 1e-4
