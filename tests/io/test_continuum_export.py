"""ParaView and pictures of a continuum survey's motion (``--model continuum``), checked against its run."""

import numpy as np
import pytest

import plbar
import plbar.continuum as pc
from plbar.cli import main
from plbar.io import load_pvd, motion_data
from plbar.studies.survey import run_survey, survey_motion

CASE = plbar.Case(model="continuum", n=32, end_mass=0.5, load_points=((0.37, 1.0),))
PERIODS, RECORD, T = 24, 6, 2.5


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("survey")
    run_survey(CASE, [T], PERIODS, RECORD, out, plot=False)
    return out


def test_the_motion_is_the_runs(folder):
    """Period boundaries: the exported u, v are the run's strobes (1e-13); the bar's energy is the run's there
    (1e-12, another quadrature of the same line), the end mass's velocity is the line's ``v(L)``, which is the mass's
    closed-form velocity to the line's order (the transient is stored linearly per piece, so the line has
    small jumps at the joins of its pieces: within 10 % of the largest end velocity at n = 32); the impact losses
    over the window are the row's loss."""
    sm = survey_motion(folder, T, RECORD)
    d = motion_data(sm.series, 8)
    cr = pc.simulate(CASE.continuum(), T, periods=PERIODS, steps_per_L=32, record=RECORD)
    reg = np.flatnonzero(d.field_data["event"] == 0)[::8]
    assert reg.size == RECORD + 1
    u, v = d.point_data["displacement"][reg], d.point_data["velocity"][reg]
    assert np.abs(u - cr.strobe_u).max() <= 1e-13 * np.abs(cr.strobe_u).max()
    assert np.abs(v - cr.strobe_v).max() <= 1e-13 * np.abs(cr.strobe_v).max()
    e = d.field_data["kinetic_energy"][reg] + d.field_data["potential_energy"][reg]
    v_line, v_mass = v[:, -1], cr.end[-RECORD - 1:, 1]
    bar = cr.energy[-RECORD - 1:] - 0.25 * v_mass ** 2
    np.testing.assert_allclose(e - 0.25 * v_line ** 2, bar, rtol=1e-12)
    assert 0 < np.abs(v_line - v_mass).max() <= 0.1 * np.abs(cr.end[:, 1]).max()
    assert d.field_data["impact_loss"].sum() / RECORD == pytest.approx(sm.row["loss_per_T"], rel=1e-12)
    # at an impact the gap is closed, and while the gap is open the wall holds nothing
    imp = d.field_data["event"] == 2
    assert imp.any() and np.all(np.abs(d.field_data["gap"][imp]) <= 1e-12)
    assert np.all(d.field_data["contact_reaction"][d.field_data["state"] == 2] == 0)
    assert np.all(d.field_data["contact_reaction"] >= -1e-9)


def test_cli_export_and_render(folder, capsys):
    assert main(["export", "--from", str(folder), "--T", str(T), "--periods", "2", "--quiet"]) == 0
    back = load_pvd(folder / "vtk" / "response.pvd")
    assert back.n_steps > 2 * 40 and back.points.size == 33
    assert main(["render", "--from", str(folder), "--T", str(T), "--periods", "2", "--quiet", "--no-gif"]) == 0
    assert (folder / "render" / "spacetime.png").is_file()
