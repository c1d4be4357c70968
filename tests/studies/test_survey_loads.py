"""The load study of the real motion (issue 28): cells against the plain survey, the scale law, the exact responses."""

import json
from dataclasses import replace

import numpy as np
import pytest

import plbar
from plbar.cli import main
from plbar.errors import InputError
from plbar.response import find_response
from plbar.studies.survey import load_positions, run_survey_loads, survey, survey_loads

T = [9.0, 11.8, 12.4]


@pytest.fixture(scope="module")
def small():
    return survey_loads(plbar.Case(), T, positions=[0.5, 1.0, 2.5], periods=400, record=40)


def test_the_cell_of_the_default_load_is_the_survey(small):
    """A unit force at s = 1 is the default case's load (DOF 1): the same simulation, the same row."""
    ref = survey(plbar.Case(), T, periods=400, record=40).table
    sel = small.table["s"] == 1.0
    for c in ("kind", "m", "loss_per_T", "xi_eq", "xi_w", "exact_loss", "signature", "energy_residual"):
        a, b = small.table[c][sel], ref[c]
        if a.dtype == float:
            assert np.array_equal(a, b, equal_nan=True), c
        else:
            assert list(a) == list(b), c


def test_a_parallel_load_is_the_same_motion_scaled(small):
    """Positive homogeneity: the chain's first spring carries the force at s = 0.5 to DOF 1 alone, half of it,
    so the motion from rest is the s = 1 motion times 0.5: the same kind, period, signature and damping ratios,
    loss and work times 0.25, amplitude times 0.5 (1e-9)."""
    t = small.table
    a, b = t["s"] == 0.5, t["s"] == 1.0
    assert list(t["kind"][a]) == list(t["kind"][b]) and list(t["signature"][a]) == list(t["signature"][b])
    per = t["kind"][b] == "periodic"
    assert per.sum() >= 2
    for c in ("xi_eq", "xi_w", "impacts_per_T", "stuck_fraction"):
        assert np.allclose(t[c][a][per], t[c][b][per], rtol=1e-9, atol=0), c
    for c, p in (("loss_per_T", 2), ("work_per_T", 2), ("exact_loss", 2), ("amp_c", 1)):
        assert np.allclose(t[c][a][per], 0.5 ** p * t[c][b][per], rtol=1e-9, atol=0), c


def test_periodic_cells_are_the_exact_responses_at_their_load(small):
    """A 1P cell's loss is the paper's closed-form response at that T and load (its stuck time from the table:
    on the orbit the mean time stuck per period is T^I), to 1e-8; the budget closes to 1e-12."""
    t = small.table
    assert np.max(np.abs(t["energy_residual"])) <= 1e-12
    checked = 0
    # on the orbit at the window's end (its distance from the polished orbit; the row's repeat distance at m = 1
    # is still 3e-6 at T = 11.8: the motion settles on the orbit more slowly than the window repeats at m = 7)
    for i in np.flatnonzero((t["signature"] == "1P") & (t["orbit_distance"] <= 1e-6)):
        prob = replace(plbar.Case(), load_nodes=(), load_points=((float(t["s"][i]), 1.0),)).problem()
        r = find_response(prob, float(t["T"][i]), float(t["stuck_fraction"][i] * t["T"][i]))
        assert r.dPL == pytest.approx(t["exact_loss"][i], rel=1e-8)
        checked += 1
    assert checked >= 2


def test_grid_and_worst_position(small):
    g = small.grid("xi_eq")
    assert g.shape == (3, 3) and np.all(np.isfinite(g))
    s, v = small.worst("xi_eq")
    assert np.all(v == g.max(axis=0)) and set(s) <= {0.5, 1.0, 2.5}


def test_default_positions():
    assert np.allclose(load_positions(plbar.Case()), np.arange(1, 21) * 0.25)          # every quarter spring
    s = load_positions(plbar.Case(model="fe", n=16))
    assert s.size == 32 and np.isclose(s[-1], 1.0) and np.isclose(s[0], 1 / 32)
    with pytest.raises(InputError, match="per_element"):
        load_positions(plbar.Case(), 0)
    with pytest.raises(InputError, match="outside the bar"):
        survey_loads(plbar.Case(), [10.0], positions=[6.0], periods=10)


def test_run_writes_resumes_and_cli(tmp_path, capsys):
    out = tmp_path / "sl"
    r = run_survey_loads(plbar.Case(), [11.8, 12.4], positions=[1.0, 3.0], periods=200, out=out, plot=False)
    header = (out / "survey_loads.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["N", "s", "T"] and "orbit_distance" in header and len(r) == 4
    stamps = {p.name: p.stat().st_mtime_ns for p in (out / "tasks").iterdir()}
    assert main(["survey", "--T-list", "11.8", "12.4", "--periods", "200", "--positions", "1", "3",
                 "--out", str(out), "--no-plot", "--json", "--executor", "serial"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["summary"]["cells"] == 4 and got["summary"]["positions"] == [1.0, 3.0]
    assert {p.name: p.stat().st_mtime_ns for p in (out / "tasks").iterdir()} == stamps      # resumed: no task rerun
    # the plain survey refuses the folder (another study's files), and takes it with --overwrite
    assert main(["survey", "--T-list", "12", "--periods", "50", "--out", str(out), "--no-plot", "-q"]) == 2
    assert main(["survey", "--T-list", "12", "--periods", "50", "--out", str(out), "--no-plot", "-q",
                 "--overwrite"]) == 0
    assert not (out / "survey_loads.csv").exists() and (out / "survey.csv").exists()


def test_sizes_share_the_physical_positions():
    """Under refinement (several N) every mesh gets the same physical positions; a cell of each N is that
    mesh's own survey with a unit force at s."""
    case = plbar.Case(model="fe", n=4, end_mass=0.5)
    sl = survey_loads(case, [2.0, 3.0], positions=[0.25, 0.5, 1.0], sizes=[4, 8], periods=60, record=6)
    t = sl.table
    assert list(sl.sizes) == [4, 8] and list(sl.positions) == [0.25, 0.5, 1.0] and len(sl) == 12
    ref = survey(replace(case, n=8, load_points=((0.5, 1.0),)), [2.0, 3.0], periods=60, record=6).table
    sel = (t["N"] == 8) & (t["s"] == 0.5)
    assert np.array_equal(t["loss_per_T"][sel], ref["loss_per_T"]) and list(t["kind"][sel]) == list(ref["kind"])
    assert sl.grid("xi_eq", 8).shape == (3, 2)


def test_a_study_reuses_only_what_the_same_code_computed(tmp_path, monkeypatch):
    """A finished task is reused by the same code (its key covers plbar's code): after plbar changed, a rerun in
    the same folder computes every task again and removes the old task files (found in issue 28: a kernel change
    had silently kept the old cells)."""
    from plbar.studies.execution import study as st

    out = tmp_path / "sl"
    kw = dict(positions=[1.0, 3.0], periods=40, out=out, plot=False)
    run_survey_loads(plbar.Case(), [11.8], **kw)
    first = {p.name for p in (out / "tasks").iterdir()}
    run_survey_loads(plbar.Case(), [11.8], **kw)
    assert {p.name for p in (out / "tasks").iterdir()} == first                    # resumed
    monkeypatch.setattr(st, "code_hash", lambda: "another-plbar")
    r = run_survey_loads(plbar.Case(), [11.8], **kw)
    again = {p.name for p in (out / "tasks").iterdir()}
    assert len(again) == 2 and not again & first and len(r) == 2
