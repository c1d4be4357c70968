"""Bar.bar_mass and the impact mass S = M_cc - M_cr M_rr^-1 M_rc of the two-state system."""

import numpy as np
import pytest

import plbar
from plbar.model import Bar, assemble, graded_nodes, uniform_bar


@pytest.mark.parametrize("element", ["P1", "P2"])
def test_bar_mass_uniform(element):
    b = uniform_bar(10, length=3.0, rhoA=2.0, element=element)
    assert b.bar_mass == pytest.approx(6.0, rel=1e-15)


def test_bar_mass_graded():
    b = Bar(graded_nodes(7, 2.5, 10.0), rhoA=1.3)
    assert b.bar_mass == pytest.approx(1.3 * 2.5, rel=1e-15)


def test_bar_mass_per_element_excludes_point_masses():
    b = Bar([0.0, 0.5, 1.5, 1.75], rhoA=np.array([1.0, 2.0, 4.0]), point_masses=((1.75, 9.0),))
    assert b.bar_mass == pytest.approx(0.5 * 1.0 + 1.0 * 2.0 + 0.25 * 4.0, rel=1e-15)
    assert plbar.chain(5, m=2.0).bar_mass == pytest.approx(10.0, rel=1e-15)      # N m, without its m/2


def test_bar_mass_is_the_assembled_total():
    """P1 lumped: free-DOF masses + the clamp's half element = bar mass + point masses."""
    x = graded_nodes(9, 2.0, 0.3)
    rho = np.linspace(1.0, 5.0, 9)
    b = Bar(x, rhoA=rho, point_masses=((x[4], 0.7), (x[-1], 0.2)))
    total = np.trace(assemble(b).M) + rho[0] * (x[1] - x[0]) / 2
    assert total == pytest.approx(b.bar_mass + 0.9, rel=1e-14)


def _system(n, element, mass, mu):
    case = plbar.Case(model="fe", n=n, element=element, mass=mass, rhoA=2.0, length=3.0, end_mass=mu)
    return case.problem().system, case.end_mass_value


@pytest.mark.parametrize("n", [2, 5, 8, 33])
@pytest.mark.parametrize("mu", [0.05, 0.5, 3.0])
def test_impact_mass_p1_lumped_exact(n, mu):
    """S = rhoA h / 2 + M_e: S / M_e = 1 + 1 / (2 N mu) (bar mass rhoA L)."""
    s, me = _system(n, "P1", "lumped", mu)
    assert me == pytest.approx(mu * 6.0, rel=1e-15)
    assert s.impact_mass / me == pytest.approx(1 + 1 / (2 * n * mu), rel=1e-14)
    assert s.impact_mass == s.M[-1, -1]


def test_impact_mass_is_the_schur_complement():
    s, _ = _system(6, "P2", "consistent", 0.3)
    M = s.M
    S = 1 / np.linalg.inv(M)[-1, -1]                 # the Schur complement, another way
    assert s.impact_mass == pytest.approx(S, rel=1e-13)
    assert s.impact_mass < M[-1, -1] * (1 - 1e-3)    # consistent mass: S is less than M_cc


@pytest.mark.parametrize("element", ["P1", "P2"])
def test_impact_mass_consistent_converges_like_h(element):
    ns = np.array([8, 16, 32, 64, 128])
    err = []
    for n in ns:
        s, me = _system(int(n), element, "consistent", 0.5)
        err.append(abs(s.impact_mass / me - 1))
    slope = np.polyfit(np.log(3.0 / ns), np.log(err), 1)[0]
    assert slope == pytest.approx(1.0, abs=0.05)
