"""A case's given start (``[start] x, v``; ``Case(start_x=, start_v=)``): the survey's motions begin there.

Checked against plbar's simulator started by hand from the same physical state (``plbar.motion.given``), which
tests/motion/test_falling_bar.py and tests/motion/test_free_body.py hold to the test's own integrator.
"""

from __future__ import annotations

import numpy as np
import pytest

import plbar
from plbar.app import dump_case, loads_case
from plbar.errors import CaseFileError, InputError
from plbar.model.structure import contact_coordinates
from plbar.motion import given, run, steady
from plbar.studies.survey import survey

DROP = """
title = "a bar dropped on the ground"
[bar]
model = "fe"
n = 10
length = 10.0
EA = 900.0
supports = "free-free"
gravity = 10.0
[[load]]
at = 5.0
amplitude = 0.5
[start]
x = -5.0
"""


def test_a_start_round_trips_through_the_case_file_and_the_case_record():
    case, _ = loads_case(DROP)
    assert case.start_x == -5.0 and case.start_v is None
    assert loads_case(dump_case(case))[0] == case
    assert plbar.Case(**case.to_dict()) == case
    per_dof = plbar.Case(model="fe", n=4, start_x=[-0.1, -0.2, -0.3, -0.4], start_v=0.5)
    assert per_dof.start_x == (-0.1, -0.2, -0.3, -0.4) and loads_case(dump_case(per_dof))[0] == per_dof
    assert plbar.Case(model="fe", n=4) == plbar.Case(**plbar.Case(model="fe", n=4).to_dict())   # none: at rest
    assert "start" not in dump_case(plbar.Case(model="fe", n=4))


@pytest.mark.parametrize("kw, match", [
    (dict(model="fe", n=4, start_x=[0.0, 0.1]), "one per DOF"),
    (dict(model="fe", n=4, start_v=float("nan")), "finite"),
    (dict(model="fe", n=4, start_x="far"), "one per DOF"),
    (dict(model="continuum", start_x=-0.1), "plbar.continuum.Field"),
])
def test_a_bad_start_is_refused_by_name(kw, match):
    with pytest.raises(InputError, match=match):
        plbar.Case(**kw)


def test_a_bad_start_in_a_case_file_names_the_section():
    with pytest.raises(CaseFileError, match=r"\[start\] x = \[1, true\]"):
        loads_case(DROP.replace("x = -5.0", "x = [1, true]"))


def test_the_survey_from_a_start_is_the_simulator_s_from_the_same_state():
    case, _ = loads_case(DROP)
    T = np.array([16 / 3, 3.0])
    s = survey(case, T, periods=12, record=6)
    prob = case.problem()
    n = prob.system.n
    ref = steady(run(prob, np.array([T[0]]), periods=12, record=6,
                     start=given(prob, np.full(n, -5.0), np.zeros(n))))
    t = s.table
    i = int(np.argmin(np.abs(np.asarray(t["T"]) - T[0])))
    assert t["loss_per_T"][i] == ref.loss_per_T[0] and t["impacts_per_T"][i] == ref.impacts_per_T[0]
    rest = survey(plbar.Case(**{k: v for k, v in case.to_dict().items() if k != "start_x"}), T[:1], periods=12,
                  record=6)
    assert rest.table["loss_per_T"][0] != t["loss_per_T"][i]           # at rest on the ground: another motion


def test_a_start_in_the_structure_s_own_dofs_goes_through_its_contact_coordinates():
    """A cracked bar's contact coordinate is the faces' difference (``x = B y``, ``B`` not the identity): the start is
    given in its DOFs and reaches the simulator as ``given(prob, B^-1 x, B^-1 v)``."""
    from plbar.app import case_start

    case = plbar.Case(model="fe", n=6, crack_at=0.5, supports="clamped-clamped", load_points=((1 / 6, 1.0),),
                      start_x=[0.0, -0.005, -0.01, 0.0, 0.0, 0.0], start_v=0.0)      # the crack open: u_i < u_o
    prob = case.problem()
    B = contact_coordinates(prob.structure).B
    assert not np.allclose(B, np.eye(B.shape[0]))
    x = np.asarray(case.start_x)
    ref = given(prob, np.linalg.solve(B, x), np.zeros(x.size))
    got = case_start(case, prob, 3)
    assert np.array_equal(got.state, np.repeat(ref.state, 3)) and np.array_equal(got.eta[2], ref.eta[0])
