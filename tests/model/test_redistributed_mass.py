"""The redistributed mass (issue 29 item 4): the contact node carries only the end mass.

Khenous, Laborde & Renard (2008): the contact element's mass is moved to its other nodes, keeping its total
mass (P1, P2), its centre of mass and its moment of inertia (P2).  The eigenfrequencies of a clamped bar with
an end mass ``m_e = mu rhoA L`` at its free end converge to the continuum's, the roots of
``tan(kL) m_e k / rhoA = 1``, i.e. ``kL tan(kL) = 1 / mu``: with ``u = sin(kx)``, the end condition
``EA u'(L) = m_e w^2 u(L)`` and ``w = c k``, ``c^2 = EA / rhoA``.
"""

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.optimize import brentq

import plbar
from plbar.cli.main import main
from plbar.errors import InputError
from plbar.model import assemble, uniform_bar
from plbar.model.bar import redistributed_block

MU = 0.5


def _pair(n, element, mu=MU, **kw):
    """Assembled redistributed and consistent bars with an end mass ``mu`` (absolute, on ``L = 1``)."""
    return [assemble(uniform_bar(n, element=element, mass=m, point_masses=((kw.get("length", 1.0), mu),), **kw))
            for m in ("redistributed", "consistent")]


@pytest.mark.parametrize("element", ["P1", "P2"])
def test_mass_and_moments_are_kept(element):
    """Total mass always; the first and second moments too for P2 (P1 has one node left: mass only)."""
    red, con = _pair(7, element, length=2.0, rhoA=1.5)
    d = red.M - con.M
    one = np.ones(red.n)
    assert one @ d @ one == pytest.approx(0.0, abs=1e-13)
    if element == "P2":
        assert one @ d @ red.x == pytest.approx(0.0, abs=1e-13)
        assert red.x @ d @ red.x == pytest.approx(0.0, abs=1e-12)
    changed = np.flatnonzero(np.any(np.abs(d) > 1e-14, axis=0))
    assert red.x[changed].min() >= 2.0 - 2.0 / 7 - 1e-12            # only the contact element's DOFs change


@pytest.mark.parametrize("element", ["P1", "P2"])
def test_contact_carries_only_the_end_mass(element):
    red, _ = _pair(6, element, mu=0.3)
    assert np.all(red.M[-1, :-1] == 0.0) and np.all(red.M[:-1, -1] == 0.0)
    assert red.M[-1, -1] == 0.3
    assert np.linalg.eigvalsh(red.M).min() > 0                       # positive definite with an end mass
    s = plbar.Case(model="fe", n=6, element=element, mass="redistributed", end_mass=0.3).problem().system
    assert s.impact_mass == pytest.approx(0.3 * 1.0, rel=1e-13)       # the plastic impact loses the end mass's energy


def test_block_is_positive_definite():
    assert redistributed_block("P1", 0.25, 2.0) == pytest.approx(np.array([[0.5]]))
    b = redistributed_block("P2", 0.25, 2.0)
    assert np.linalg.eigvalsh(b).min() > 0
    xi = np.array([0.0, 0.125])
    assert (b.sum(), b.sum(axis=0) @ xi, xi @ b @ xi) == pytest.approx((0.5, 0.5 * 0.25 / 2, 2.0 * 0.25**3 / 3))


def _exact(mu, n):
    """The first ``n`` roots of ``kL tan(kL) = 1 / mu``, one in each ``(j pi, j pi + pi / 2)``."""
    return np.array([brentq(lambda z: z * np.sin(z) - np.cos(z) / mu, j * np.pi + 1e-12, (j + 0.5) * np.pi - 1e-12)
                     for j in range(n)])


#: observed orders of the first three frequencies (N = 16 ... 128, each mode's finest pair above round-off):
#: lumped and consistent 2 / 4, redistributed 2 for P1 and one order less for P2 (3)
ORDERS = {("P1", "lumped"): 2, ("P1", "consistent"): 2, ("P1", "redistributed"): 2,
          ("P2", "lumped"): 4, ("P2", "consistent"): 4, ("P2", "redistributed"): 3}


@pytest.mark.parametrize("element, mass", list(ORDERS))
def test_frequencies_converge_to_the_continuum(element, mass):
    exact = _exact(MU, 3)
    err = []
    for n in (16, 32, 64, 128):
        a = assemble(uniform_bar(n, element=element, mass=mass, point_masses=((1.0, MU),)))
        err.append(np.abs(np.sqrt(sla.eigh(a.K, a.M, eigvals_only=True, subset_by_index=[0, 2])) - exact) / exact)
    err = np.array(err)
    for j in range(3):
        i = max(i for i in range(1, 4) if err[i, j] > 1e-10 or i == 1)      # the finest pair above round-off
        order = np.log(err[i - 1, j] / err[i, j]) / np.log(2)
        assert order == pytest.approx(ORDERS[element, mass], abs=0.2), (j, order)
    assert err[-1].max() < (3e-4 if element == "P1" else 2e-7)


def test_refused_without_an_end_mass():
    with pytest.raises(InputError, match="needs an end mass"):
        uniform_bar(8, mass="redistributed")
    with pytest.raises(InputError, match="end_mass > 0"):
        plbar.Case(model="fe", n=8, element="P2", mass="redistributed")
    assert plbar.Case(model="fe", n=8, mass="redistributed", point_masses=((1.0, 0.2),)).bar().mass == "redistributed"


def test_case_file_and_cli(tmp_path):
    from plbar.app.casefile import loads_case

    case = loads_case('[bar]\nmodel = "fe"\nn = 6\nelement = "P2"\nmass = "redistributed"\nend_mass = 0.5\n')[0]
    assert case.mass == "redistributed" and case.bar().point_masses == ((1.0, 0.5),)
    assert main(["survey", "--model", "fe", "--mass", "redistributed", "-N", "16", "--num", "5",
                 "--periods", "200", "--out", str(tmp_path / "a"), "--no-plot", "--quiet"]) == 2      # no end mass


def test_survey_runs(tmp_path):
    """``plbar survey --model fe --mass redistributed --end-mass 0.5 -N 16 --num 5 --periods 200`` (~5 s)."""
    out = tmp_path / "s"
    assert main(["survey", "--model", "fe", "--mass", "redistributed", "--end-mass", "0.5", "-N", "16", "--num", "5",
                 "--periods", "200", "--out", str(out), "--no-plot", "--quiet"]) == 0
    rows = (out / "survey.csv").read_text().splitlines()
    assert len(rows) == 6 and all(",failed," not in r for r in rows)
