"""A gap in a case (issue 41 item 1): the case, its file, the command line, and what refuses it by name.

The motion with a gap is checked against an integrator written in the test in ``tests/motion/test_gap.py``; here
the way in: ``Case(gap=...)``, ``[bar] gap`` read and written, ``--gap``, the commands that take it (``run`` finds
every response by the signature search; ``survey``), and those that say why not (the paper's scan,
``sweep-loads``, ``refine``, the continuum).
"""

import subprocess
import sys

import numpy as np
import pytest

import plbar
from plbar.app import dump_case, load_case
from plbar.errors import InputError


def test_a_case_carries_its_gap(tmp_path):
    c = plbar.Case(gap=-0.25, model="fe", n=6)
    assert c.problem().gap == -0.25 and c.to_dict()["gap"] == -0.25
    assert "gap" not in plbar.Case().to_dict()                 # zero gap: the paper's record, unchanged
    p = tmp_path / "g.toml"
    p.write_text(dump_case(c))
    assert load_case(p)[0].gap == -0.25 and load_case(p)[0] == c
    with pytest.raises(InputError, match="gap"):
        plbar.Case(gap="wide")


def test_the_static_equilibria_hold():
    """State I's equilibrium is the stiffness's solution with the contact held at d, its reaction the Schur
    complement times d (both computed here from K)."""
    prob = plbar.Case(gap=0.3).problem()
    K, st = prob.system.K, prob.statics
    Krr, Krc = K[:-1, :-1], K[:-1, -1]
    assert np.allclose(st.x1[:-1], -np.linalg.solve(Krr, Krc) * 0.3, rtol=1e-13, atol=0)
    schur = K[-1, -1] - Krc @ np.linalg.solve(Krr, Krc)
    assert st.reaction == pytest.approx(0.3 * schur, rel=1e-13)
    assert st.energy[0] == pytest.approx(0.5 * 0.3 ** 2 * schur, rel=1e-12) and st.rest_state == 1
    assert plbar.Case(gap=-0.3).problem().statics.rest_state == 0 and plbar.Case().problem().statics.rest_state == 0


def test_what_does_not_take_a_gap_says_so():
    with pytest.raises(InputError, match="gap"):
        plbar.paths.find_paths(plbar.Case(gap=0.5).problem())
    with pytest.raises(InputError, match="signatures"):
        plbar.solve(plbar.Case(gap=0.5, signatures="paper"))
    with pytest.raises(InputError, match="continuum"):
        plbar.Case(model="continuum", gap=0.1)


def test_run_and_survey_take_a_gap(tmp_path):
    out = subprocess.run([sys.executable, "-m", "plbar", "survey", "--gap", "0.5", "--T-list", "9", "12",
                          "--periods", "200", "--no-plot", "--out", str(tmp_path / "s"), "-q"],
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "s" / "survey.csv").read_text().count("\n") == 3
    res = plbar.solve(plbar.Case(gap=0.5, grid=(40, 40)))
    assert any(b.label == "1P" for b in res.branches)
    assert "search" in res.paths.stats["paper_class"]
