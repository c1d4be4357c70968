"""The survey of the continuum bar (``--model continuum``) and the continuum as the N = infinity row of
``survey -N``."""

import json
import subprocess
import sys

import numpy as np
import pytest

import plbar
import plbar.continuum as pc
from plbar.errors import InputError
from plbar.model import rayleigh_ratio
from plbar.studies.survey import run_survey, survey
from plbar.studies.survey.refine import continuum_case, run_survey_refine

CASE = plbar.Case(model="continuum", n=16, end_mass=0.5, load_points=((0.37, 1.0),))


@pytest.fixture(scope="module")
def rows():
    return survey(CASE, [2.5, 3.5], periods=30, record=10).rows()


def test_survey_rows_are_the_continuum_runs_accounts(rows):
    """Every number of a row against the run of :func:`plbar.continuum.simulate` (same bar, T, steps)."""
    for i, T in enumerate(rows["T"]):
        cr = pc.simulate(pc.ContinuumBar(end_mass=0.5, s=0.37), T, periods=30, steps_per_L=16, record=10)
        assert rows["loss_per_T"][i] == pytest.approx(cr.loss[-10:].mean(), rel=1e-13)
        assert rows["impacts_per_T"][i] == pytest.approx(cr.impacts[-10:].mean(), rel=1e-13)
        assert rows["work_per_T"][i] == pytest.approx(cr.work[-10:].mean(), rel=1e-13)
        assert rows["xi_w"][i] == pytest.approx(cr.xi_omega, rel=1e-12)
        assert rows["amp_c"][i] == pytest.approx(cr.amp[-10:].mean(), rel=1e-13)
        assert abs(rows["energy_residual"][i]) <= 1e-9
        # time stuck: the end's state at the period boundaries and the switches, integrated independently on a fine
        # time grid (a right-continuous state from the event list)
        ev = cr.events
        t = np.linspace(20 * T, 30 * T, 200001)[:-1]
        state = np.full(t.size, cr.end[20, 2] > 0)
        for te, k in zip(ev["time"], ev["kind"]):
            if 20 * T <= te < 30 * T:
                state[t >= te] = k == 2
        assert rows["stuck_fraction"][i] == pytest.approx(state.mean(), abs=2e-4)


def test_xi_eq_is_blank_and_the_motion_irregular(rows):
    assert np.all(np.isnan(rows["xi_eq"])) and np.all(np.isnan(rows["xi_std"]))
    assert set(rows["kind"]) <= {"irregular", "periodic"}
    assert np.all(rows["status"] == 0) and np.all(rows["signature"] == "")


def test_natural_periods_are_the_fe_limit():
    """T0^I = 2L/c, T0^II from kL tan kL = rhoA L / m_e: the FE bar's periods converge to them (P2, order 4)."""
    TI, TII = pc.natural_periods(pc.ContinuumBar(end_mass=0.5))
    assert TI == 2.0
    fe = plbar.Case(model="fe", n=32, element="P2", mass="consistent", end_mass=0.5).problem().system.T0
    assert abs(fe[0] - TI) < 1e-6 and abs(fe[1] - TII) < 1e-6
    assert pc.natural_periods(pc.ContinuumBar(end_mass=0.0)) == (2.0, 4.0)


@pytest.mark.parametrize("kw, words", [
    (dict(element="P2"), "element"),
    (dict(restitution=0.3), "plastic"), (dict(load_nodes=((1, 1.0),)), "one point load"),
    (dict(modes=3), "modes"), (dict(load_points=((0.3, 1.0), (0.6, 1.0))), "one point load")])
def test_what_the_continuum_refuses(kw, words):
    with pytest.raises(InputError, match=words):
        plbar.Case(model="continuum", **kw)


RAY = plbar.rayleigh_from_ratio(0.01, 2.0, 4.0)
DAMPED = plbar.Case(model="continuum", n=16, end_mass=0.5, load_points=((0.37, 1.0),), rayleigh=RAY, modes=512)


def test_damped_continuum_survey_rows_are_the_modal_runs_accounts(tmp_path):
    """With Rayleigh damping the survey runs :func:`plbar.continuum.simulate_modal`: every number of the row against
    the run itself, xi_eq filled (defined with damping), the balance closed with the Rayleigh dissipation."""
    s = survey(DAMPED, [2.5], periods=12, record=4)
    r = s.rows()
    mr = pc.simulate_modal(pc.ContinuumBar(end_mass=0.5, s=0.37), 2.5, 12, RAY, modes=512, record=4, grid=16)
    assert r["loss_per_T"][0] == pytest.approx(mr.loss[-4:].mean(), rel=1e-13)
    assert r["xi_eq"][0] == pytest.approx(mr.xi_eq, rel=1e-12)
    assert r["xi_w"][0] == pytest.approx(mr.xi_omega, rel=1e-12)
    assert r["amp_c"][0] == pytest.approx(mr.amp[-4:].mean(), rel=1e-13)
    assert r["impacts_per_T"][0] == pytest.approx(mr.impacts[-4:].mean(), rel=1e-13)
    assert abs(r["energy_residual"][0]) < 1e-12 and r["viscous_per_T"][0] > 0
    assert r["xi_total"][0] == pytest.approx(r["xi_eq"][0] + rayleigh_ratio(*RAY, 2 * np.pi / 2.5), rel=1e-14)
    assert 0.01 < r["xi_eq"][0] < 0.04          # a ratio of a few percent, finite: no jump survives the damping
    with pytest.raises(InputError, match="modes does not apply"):
        plbar.Case(model="continuum", modes=64)
    from plbar.app.cost import survey_seconds
    assert survey_seconds(DAMPED, 161, 1000) > 3600         # announced: the default survey takes hours
    from plbar.studies.survey.motion import survey_motion
    run_survey(DAMPED, [2.5], periods=4, record=2, out=tmp_path / "d", plot=False)
    with pytest.raises(InputError, match="not built"):
        survey_motion(tmp_path / "d", 2.5, periods=2)


def test_commands_without_a_continuum_refuse_it_in_one_line(tmp_path):
    with pytest.raises(InputError, match="no matrices"):
        CASE.problem()
    with pytest.raises(InputError, match="from rest only"):
        survey(CASE, [2.5], periods=10, record=2, modes=("rest", "up"))
    p = subprocess.run([sys.executable, "-m", "plbar", "run", "--model", "continuum", "--out", str(tmp_path / "r")],
                       capture_output=True, text=True)
    assert p.returncode == 2 and "no matrices" in p.stderr and "Traceback" not in p.stderr


def test_survey_refine_has_the_continuum_row(tmp_path):
    fe = plbar.Case(model="fe", end_mass=0.5, load_points=((0.37, 1.0),))
    r = run_survey_refine(fe, [8, 16], [2.5], periods=20, record=10, out=tmp_path / "sr", plot=False)
    assert 0 in r.surveys and (tmp_path / "sr" / "continuum" / "survey.csv").is_file()
    d = r.rates["T/L=2.5"]
    cont = r.surveys[0].rows()
    for q in ("loss_per_T", "xi_w"):
        ac = d[q]["against_continuum"]
        assert ac["continuum"] == pytest.approx(cont[q][0], rel=1e-15)
        assert np.allclose(ac["error"], np.array(d[q]["values"]) - cont[q][0], rtol=0, atol=1e-15)
    assert d["xi_eq"]["against_continuum"]["continuum"] is None
    rows = [row for row in r.rows if row["N"] == 0]
    assert len(rows) == 1 and rows[0]["h"] == 0.0
    # a damped case has its damped continuum (exact modes per contact state)
    damped = plbar.Case(model="fe", end_mass=0.5, load_points=((0.37, 1.0),), rayleigh=(0.01, 0.001))
    c, why = continuum_case(damped)
    assert c.model == "continuum" and c.rayleigh == damped.rayleigh and why == ""
    r = run_survey_refine(damped, [8, 16], [2.5], periods=12, record=4, out=tmp_path / "srd", plot=False)
    d = r.rates["T/L=2.5"]
    cont = r.surveys[0].rows()
    for q in ("loss_per_T", "xi_eq", "xi_w"):               # xi_eq is defined in the damped continuum
        assert d[q]["against_continuum"]["continuum"] == pytest.approx(cont[q][0], rel=1e-15)
        err = np.abs(d[q]["against_continuum"]["error"])
        assert np.all(np.isfinite(err)) and err[1] < err[0]  # N = 16 nearer than N = 8


def test_cli_survey_continuum_writes_its_table(tmp_path):
    p = subprocess.run([sys.executable, "-m", "plbar", "survey", "--model", "continuum", "-N", "16", "--end-mass",
                        "0.5", "--load-at", "0.37", "--T-list", "2.5", "--periods", "12", "--record", "4", "--out",
                        str(tmp_path / "s"), "--no-plot", "--json"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert out["summary"]["case"]["model"] == "continuum" and out["summary"]["rows"] == 1
    assert "xi_eq" in (tmp_path / "s" / "survey.csv").read_text().splitlines()[0]
    run_survey(CASE, [2.5], periods=12, record=4, out=tmp_path / "s", plot=False)    # the same survey resumes


def test_refine_says_why_it_has_no_continuum_row():
    from plbar.cli.studies import _no_continuum_row

    fe = dict(model="fe", load_points=((0.37, 1.0),))
    assert "no periodic response with an impact loss" in _no_continuum_row(plbar.Case(end_mass=0.5, **fe))
    assert "tend to 0" in _no_continuum_row(plbar.Case(**fe))
    assert "Kelvin-Voigt" in _no_continuum_row(plbar.Case(end_mass=0.5, rayleigh=(0.01, 0.001), **fe))
    assert _no_continuum_row(plbar.Case()) == ""
