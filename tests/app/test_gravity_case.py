"""A constant load in a case (issue 41 item 1, "constant loads beside the harmonic ones"): gravity along the bar.

The motion with a constant load is checked against an integrator written in the test in
``tests/motion/test_gap.py`` (``test_a_constant_load_is_the_integrators``) and its periodic responses in
``tests/periodic/test_affine_orbits.py``; here the way in (``Case(gravity=...)``, ``[bar] gravity``,
``--gravity``), the static equilibria against the bar's closed forms, and what refuses it by name.
"""

import subprocess
import sys

import numpy as np
import pytest

import plbar
from plbar.app import dump_case, load_case
from plbar.errors import InputError


def test_a_case_carries_its_gravity(tmp_path):
    c = plbar.Case(gravity=0.02, gap=0.01, model="fe", n=6, mass="consistent")
    st = c.problem().structure
    # the bar's weight rhoA L g, less the clamped node's share (h / 2: its shape function's integral)
    assert st.q_s.sum() == pytest.approx(0.02 * (1.0 - 1.0 / 12), rel=1e-12)
    assert np.all(st.q_s > 0)
    assert c.to_dict()["gravity"] == 0.02 and "gravity" not in plbar.Case().to_dict()
    p = tmp_path / "g.toml"
    p.write_text(dump_case(c))
    assert load_case(p)[0] == c
    assert plbar.Case(gravity=0.0).problem().structure.q_s is None      # zero: the paper's record, unchanged
    with pytest.raises(InputError, match="gravity"):
        plbar.Case(gravity=float("nan"))


@pytest.mark.parametrize("element", ["P1", "P2"])
@pytest.mark.parametrize("mass", ["lumped", "consistent"])
def test_the_static_equilibria_are_the_bars(element, mass):
    """A uniform bar (EA = rhoA = L = 1) with an end mass m under g: free, its end sinks by g (1/2 + m) (the
    exact u(L) = g (rhoA L^2 / 2 + m L) / EA, which 1D elements reproduce at their nodes); held at its end, the
    stop carries g (1/2 + m) (the end's share of the weight, the end mass all of its own)."""
    g, m = 0.3, 0.25
    c = plbar.Case(model="fe", n=6, element=element, mass=mass, gravity=g, end_mass=m, end_mass_absolute=True)
    st = c.problem().statics
    assert st.x2[-1] == pytest.approx(g * (0.5 + m), rel=1e-12)
    assert -st.reaction == pytest.approx(g * (0.5 + m), rel=1e-12)         # the stop pushes: -R > 0
    assert st.rest_state == 0                                               # pressed on the stop at zero gap
    away = plbar.Case(model="fe", n=6, element=element, mass=mass, gravity=-g).problem().statics
    assert away.rest_state == 1 and away.x2[-1] == pytest.approx(-g / 2, rel=1e-12)


@pytest.mark.slow                    # long: with the slow tests (the default suite under 10 minutes)
def test_the_commands_take_it_or_say_why_not(tmp_path):
    run = [sys.executable, "-m", "plbar"]
    ok = subprocess.run(run + ["run", "--gravity", "0.05", "--no-plot", "--quiet", "--out", str(tmp_path / "r")],
                        capture_output=True, text=True)
    assert ok.returncode == 0, ok.stderr
    assert "1P" in (tmp_path / "r" / "paths.csv").read_text()
    for args, why in ((["run", "--gravity", "0.05", "--signatures", "paper"], "signature search"),
                      (["refine", "--gravity", "0.05", "-N", "4", "8"], "constant load"),
                      (["sweep-loads", "--gravity", "0.05"], "constant load"),
                      (["run", "--model", "continuum", "--gravity", "0.05"], "no constant load")):
        out = subprocess.run(run + args + ["--no-plot", "--out", str(tmp_path / "x")], capture_output=True,
                             text=True)
        assert out.returncode == 2 and why in out.stderr, (args, out.stderr)
    with pytest.raises(InputError, match="gravity does not apply to model = 'matrices'"):
        st = plbar.Case().problem().structure
        from plbar.io import write_structure
        f = write_structure(tmp_path / "s.npz", st)
        plbar.Case(model="matrices", matrices=str(f), gravity=0.1)
