"""ParaView and pictures of any simulated motion (issue 28): a survey's motion exported, checked against the run."""

import json

import numpy as np
import pytest

import plbar
from plbar.cli import main
from plbar.errors import InputError
from plbar.io import load_pvd, motion_data, write_data
from plbar.motion import boundary_mismatch, motion_series, padded, run
from plbar.studies.survey import run_survey, survey_motion

PERIODS, RECORD = 300, 30


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("survey")
    run_survey(plbar.Case(), [6.9, 7.0, 9.6], PERIODS, RECORD, out, modes=("rest", "up"), plot=False)
    return out


def test_the_exported_motion_is_the_surveys(folder):
    """The motion of ``--from SURVEY --T 7`` is the survey's simulation: over its whole record, the impact losses
    per period are survey.csv's loss_per_T (1e-12), from rest and from the sweep up."""
    rows = {(r["start"], float(r["T"])): r for r in _csv(folder / "survey.csv")}
    for start in ("rest", "up"):
        sm = survey_motion(folder, 7.0, RECORD, start)
        d = motion_data(sm.series, 8)
        loss = d.field_data["impact_loss"].sum() / RECORD
        assert loss == pytest.approx(float(rows[(start, 7.0)]["loss_per_T"]), rel=1e-12)
        assert sm.info["survey_kind"] == rows[(start, 7.0)]["kind"] and sm.info["start"] == start


def test_boundaries_are_the_stroboscopic_states_and_the_energy_integrates(folder):
    """At every period boundary the exported displacement and velocity are the run's stroboscopic states (1e-12);
    the flows carry each boundary state to the next to 1e-12; the energy fields (element strain energies and
    nodal kinetic shares) integrate to the mechanical energy at every step (1e-10), and at the window's end to
    the run's final energy (1e-10)."""
    case = plbar.Case()
    prob = case.problem()
    for T in (7.0, 9.6):
        r = run(padded(prob), np.array([T]), 0.0, PERIODS, RECORD)       # the survey's simulation, again
        P, steps = 20, 10
        ms = motion_series(prob, r, 0, P)
        assert boundary_mismatch(ms, r, 0) <= 1e-12
        d = motion_data(ms, steps)
        reg = np.flatnonzero(d.field_data["event"] == 0)
        at = reg[::steps]                                           # the P + 1 boundaries
        assert at.size == P + 1
        np.testing.assert_allclose(d.times[at], np.arange(P + 1) * T, rtol=0, atol=1e-9 * T)
        scale = np.abs(r.strobe_x[0]).max()
        u = d.point_data["displacement"][at][:, 1:]
        v = d.point_data["velocity"][at][:, 1:]
        assert np.abs(u - r.strobe_x[0, -P - 1:]).max() <= 1e-12 * scale
        assert np.abs(v - r.strobe_v[0, -P - 1:]).max() <= 1e-12 * np.abs(r.strobe_v[0]).max()
        total = d.point_data["kinetic_energy_nodal"].sum(axis=1) + d.cell_data["strain_energy"].sum(axis=1)
        e = d.field_data["kinetic_energy"] + d.field_data["potential_energy"]
        assert np.abs(total - e).max() <= 1e-10 * e.max()
        assert total[-1] == pytest.approx(float(r.energy_end[0]), rel=1e-10)
        # the impacts: one marked step each, their losses the run's
        ev, st = d.field_data["event"], d.field_data["state"]
        assert np.sum(ev >= 2) == r.impacts[0, -P:].sum() and np.sum(ev % 2 == 1) == r.openings[0, -P:].sum()
        assert d.field_data["impact_loss"].sum() == pytest.approx(r.loss[0, -P:].sum(), rel=1e-12)
        assert np.all(np.diff(d.times) > 0)                          # a time series: times increase strictly
        # just after an impact the contact is stuck; after an impact with a zero dwell (3) the gap is open
        assert np.all(st[ev == 2] == 1) and np.all(st[ev == 3] == 2) and np.all(st[ev == 1] == 2)


def test_both_formats_are_read_back_by_pyvista_and_meshio(folder, tmp_path):
    meshio = pytest.importorskip("meshio")
    pytest.importorskip("pyvista")
    d = motion_data(survey_motion(folder, 9.6, 3).series, 8)
    f = write_data(d, tmp_path, format="both")
    back = load_pvd(f.pvd)                                   # pyvista's PVDReader
    assert back.n_steps == d.n_steps
    np.testing.assert_allclose(back.point_data["displacement"], d.point_data["displacement"], rtol=0, atol=1e-14)
    np.testing.assert_array_equal(back.field_data["event"], d.field_data["event"])
    with meshio.xdmf.TimeSeriesReader(str(f.xdmf)) as rd:
        rd.read_points_cells()
        assert rd.num_steps == d.n_steps
        for k in (0, d.n_steps // 2, d.n_steps - 1):
            t, pd, cd = rd.read_data(k)
            assert t == pytest.approx(d.times[k], abs=1e-12 * d.times[-1])
            np.testing.assert_allclose(pd["displacement"], d.point_data["displacement"][k], rtol=0, atol=1e-14)
            assert pd["event"][0] == d.field_data["event"][k]
    info = json.loads(f.info_json.read_text())
    assert info["motion"] and info["T_forcing"] == 9.6 and info["periods"] == 3


def test_cli_export_and_render_of_a_survey_motion(folder, capsys):
    pytest.importorskip("pyvista")
    assert main(["export", "--from", str(folder), "--T", "7", "--periods", "4", "--steps", "8", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["summary"]["T_forcing"] == 7.0 and got["summary"]["survey_kind"] in ("irregular", "periodic")
    assert (folder / "vtk" / "response.pvd").is_file()
    assert main(["render", "--from", str(folder), "--T", "9.6", "--periods", "3", "--steps", "8", "--no-gif",
                 "-q"]) == 0
    assert (folder / "render" / "spacetime.png").is_file()
    # what the survey did not simulate is refused in one line
    assert main(["export", "--from", str(folder), "--T", "8", "-q"]) == 2
    assert "not a forcing period of this survey" in capsys.readouterr().err
    assert main(["export", "--from", str(folder), "--T", "7", "--start", "down", "-q"]) == 2
    assert main(["export", "--from", str(folder), "--T", "7", "--periods", str(PERIODS + 1), "-q"]) == 2
    with pytest.raises(InputError, match="not the folder of a 'plbar survey'"):
        survey_motion(folder / "vtk", 7.0)


def _csv(path):
    import csv

    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("e, T", [(0.3, 10.0), (0.3, 7.0), (0.6, 9.65)])
def test_motion_with_rebounds_and_chattering(e, T):
    """With a coefficient of restitution (issue 31): the series carries each boundary state to the next through
    the rebounds and the chattering sequences' ends (whose switch precedes their recorded accumulation point)
    to 1e-12; the exported losses are the run's (1e-12); rebounds (4) and chatter ends (5) are marked steps."""
    prob = plbar.Case(restitution=e).problem()
    r = run(padded(prob), np.array([T]), 0.0, 200, 10)
    ms = motion_series(prob, r, 0)
    assert boundary_mismatch(ms, r, 0) <= 1e-12
    d = motion_data(ms, 8)
    ev = d.field_data["event"]
    kinds = r.events["kind"][r.events["time"] < ms.t0 + ms.span]
    assert np.sum(ev == 4) == np.sum(kinds == 3) > 0 and np.sum(ev == 5) == np.sum(kinds == 4)
    assert d.field_data["impact_loss"].sum() == pytest.approx(r.loss[0].sum(), rel=1e-12)
    assert np.all(d.field_data["state"][ev == 4] == 2) and np.all(d.field_data["state"][ev == 5] == 1)

    _each_sample_alone(ms, d.times + ms.t0)


def _each_sample_alone(series, t):
    """The series evaluates all times at once (vectorised) to the same bits as each time alone."""
    together = (*series.response(t), series.reaction(t), *series.energies(t))
    for i in np.linspace(0, t.size - 1, 25).astype(int):
        alone = (*series.response(t[i:i + 1]), series.reaction(t[i:i + 1]), *series.energies(t[i:i + 1]))
        assert all(np.array_equal(a[i], b[0]) for a, b in zip(together, alone))


def test_a_period_near_a_surveyed_one_is_taken_and_says_so(folder, capsys):
    """Issue 44: ``--T`` within 1e-3 of a surveyed period (and nearer it than half the spacing to the next) shows
    that period and says so; farther off it is refused, naming the surveyed periods on either side."""
    pytest.importorskip("pyvista")
    assert main(["export", "--from", str(folder), "--T", "7.004", "--periods", "2", "--steps", "8", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["summary"]["T_forcing"] == 7.0
    assert main(["render", "--from", str(folder), "--T", "9.5921", "--periods", "2", "--steps", "8",
                 "--no-gif"]) == 0
    assert "--T 9.5921 is taken as the survey's forcing period T = 9.6" in capsys.readouterr().err
    assert main(["export", "--from", str(folder), "--T", "7.02", "-q"]) == 2
    assert "the nearest: 7 and 9.6" in capsys.readouterr().err
    assert survey_motion(folder, 6.9999, 2).T == 7.0


def test_surveyed_period_tolerance():
    from plbar.studies.survey.motion import surveyed_period

    Ts = [2.4, 2.499581703, 3.0]
    assert surveyed_period(Ts, 2.4) == 2.4
    assert surveyed_period(Ts, 2.3981) == 2.4                       # within 1e-3 T
    assert surveyed_period(Ts, 2.5) == 2.499581703
    with pytest.raises(InputError, match=r"the nearest: 2.499581703 and 3\)"):
        surveyed_period(Ts, 2.5028)                                 # beyond 1e-3 T
    close = [2.4995, 2.5, 2.6]                                      # 5e-4 apart: half of it is the tolerance
    assert surveyed_period(close, 2.5002) == 2.5
    with pytest.raises(InputError, match=r"the nearest: 2.5 and 2.6\)"):
        surveyed_period(close, 2.5003)
    with pytest.raises(InputError, match=r"the nearest: 2.4\)"):
        surveyed_period(Ts, 2.39)
    with pytest.raises(InputError, match=r"the nearest: 3\)"):
        surveyed_period(Ts, 3.1)
