"""A beam through the front door (issue 41 item 2): ``Case(model="beam")``, ``--model beam``, ``[bar] model =
"beam"``. The beam itself is checked against its closed forms and the test's integrator in
``tests/model/test_beam.py``; here the case is that beam (the same structure as ``beam_structure``, bit for bit),
it round-trips (its dict, its file), a survey's tasks rebuild it, and what does not apply to a beam is refused."""

import numpy as np
import pytest

import plbar
from plbar.app import dump_case, loads_case
from plbar.cli import main
from plbar.errors import InputError
from plbar.model.beam import beam_structure, uniform_beam
from plbar.studies.survey import survey

CASE = dict(model="beam", n=6, EI=1.0, supports="clamped-free", end_mass=0.5, end_mass_absolute=True, gap=0.05,
            load_points=((0.5, 0.2),))


def test_the_case_is_the_beam():
    c = plbar.Case(**CASE)
    ref = beam_structure(uniform_beam(6, EI=1.0, point_masses=((1.0, 0.5),)), forces=((0.5, 0.2),), gap=0.05)
    st = c.structure
    for k in ("M", "K", "contact", "q"):
        assert np.array_equal(getattr(st, k), getattr(ref, k)), k
    assert st.gap == 0.05 and c.contact_at == 1.0 and c.n_eff == 6
    assert plbar.Case(**c.to_dict()) == c and loads_case(dump_case(c))[0] == c
    both = plbar.Case(model="beam", base=0.5, load_points=((0.5, 2.0),))     # a base and a force: both act
    assert both.load_points == ((0.5, 2.0),) and plbar.Case(model="beam", base=0.5).load_points == ()
    b = uniform_beam(8)
    assert np.array_equal(both.structure.q, beam_structure(b, forces=((0.5, 2.0),), base=0.5).q)
    pinned = plbar.Case(model="beam", supports="pinned-pinned")
    assert pinned.contact_at == 0.5 and pinned.load_points == ((0.25, 1.0),)    # the defaults off the stop


def test_a_survey_rebuilds_the_beam_in_its_tasks():
    s = survey(plbar.Case(**CASE), [3.0, 3.5], periods=100, record=10)
    assert s.table["kind"].size == 2 and np.all(s.table["impacts_per_T"] > 0)
    assert np.max(np.abs(s.table["energy_residual"])) < 1e-10     # hundreds of chattering impacts a window


def test_the_command_line(tmp_path):
    args = ["--model", "beam", "-N", "4", "--EI", "2", "--end-mass", "0.5", "--end-mass-absolute", "--gap", "0.05",
            "--load-at", "0.5", "--amplitude", "0.2", "--no-plot", "--quiet"]
    assert main(["run", *args, "--out", str(tmp_path / "r")]) == 0
    assert main(["survey", *args, "--T-list", "3", "--periods", "100", "--out", str(tmp_path / "s")]) == 0


@pytest.mark.parametrize("bad, why", [(dict(element="P2"), "element does not apply to model = 'beam'"),
                                      (dict(load_nodes=((1, 1.0),)), "load_nodes does not apply"),
                                      (dict(supports="free-free"), "supports"),
                                      (dict(contact_at=0.0), "on a support")])
def test_what_a_beam_refuses(bad, why):
    with pytest.raises(InputError, match=why):
        plbar.Case(model="beam", **bad)


def test_the_amplitude_study_of_a_beam_depends_on_the_amplitude_over_the_gap():
    """Homogeneity on the beam (FORMULATION §9): the cells (d, A) and (4 d, 4 A) are one motion, xi_eq equal and the
    loss times 16 (1e-9)."""
    from dataclasses import replace

    from plbar.studies.survey import AMPLITUDES, survey_loads

    c = plbar.Case(**CASE)
    a = survey_loads(c, [3.0, 3.5], [1.0, 4.0], periods=100, record=10, axis=AMPLITUDES).table
    b = survey_loads(replace(c, gap=0.2), [3.0, 3.5], [4.0, 16.0], periods=100, record=10, axis=AMPLITUDES).table
    assert list(a["kind"]) == list(b["kind"])
    assert np.allclose(b["xi_eq"], a["xi_eq"], rtol=1e-9, atol=1e-15)
    assert np.allclose(b["loss_per_T"], 16 * a["loss_per_T"], rtol=1e-9, atol=1e-15)
