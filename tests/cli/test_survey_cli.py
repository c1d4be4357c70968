"""``plbar survey``: a survey over forcing periods and over meshes (``survey -N``), its continuum row, what it prints
and warns of, the input it refuses or leaves alone, Ctrl-C.

From the newcomer reports (issues 30 and 44). Every test here failed on the code before the fix it covers.
"""

import os
import signal
import time

import numpy as np
import pytest

from plbar.cli import main
from plbar.motion import periodicity

from _helpers import _plbar, _run


# a survey of few periods (one recorded) ran into "solver failure" (issue 44) ----------------------------------------

def test_a_window_of_one_period_has_a_finite_repeat_distance():
    """One recorded period (two boundary states): never periodic, its distance the one repeat it holds."""
    rng = np.random.default_rng(44)
    x, v = rng.normal(size=(3, 2, 4)), rng.normal(size=(3, 2, 4))
    m, d = periodicity(x, v)
    z = np.concatenate([x, v], axis=2)
    want = [np.linalg.norm(z[b, 1] - z[b, 0]) / max(np.linalg.norm(z[b, 0]), np.linalg.norm(z[b, 1]))
            for b in range(3)]
    assert np.all(m == 0) and np.allclose(d, want, rtol=1e-14)
    assert periodicity(x[:, [0, 0]], v[:, [0, 0]])[0][0] == 0        # one repeat is no evidence of a period


def test_survey_of_five_periods_runs(tmp_path, capsys):
    code, out, err = _run(capsys, ["survey", "--periods", "5", "--T-list", "9", "12", "--no-plot", "--no-paths",
                                   "--out", tmp_path / "s"])
    assert code == 0, err
    assert "2 irregular" in out and "1 recorded period cannot show a motion repeat" in out
    text = (tmp_path / "s" / "survey.csv").read_text().splitlines()
    cols = text[0].split(",")
    assert all(np.isfinite(float(r.split(",")[cols.index("distance")])) for r in text[1:])


# the continuum row of a survey over meshes crashed where its march chatters (issue 44) ------------------------------

def test_a_continuum_march_stopped_by_chatter_is_a_failed_row(tmp_path, capsys):
    """The unit continuum at T c/L = 5 chatters after ~79 periods (switches accumulate in one grid step): its row is
    T, kind 'failed' and its status, no number it does not have (before: 'distance = inf is not finite ... please
    report the case')."""
    import csv
    import json

    code, out, err = _run(capsys, ["survey", "--model", "continuum", "--T-list", "5", "--periods", "100",
                                   "--no-plot", "--out", tmp_path / "c"])
    assert code == 0, err
    assert "1 failed" in out
    (row,) = list(csv.DictReader(open(tmp_path / "c" / "survey.csv")))
    assert row["kind"] == "failed" and row["status"] != "0"
    assert all(row[k] == "" for k in ("loss_per_T", "xi_w", "distance", "energy_residual", "impacts_per_T"))
    assert json.loads((tmp_path / "c" / "summary.json").read_text())["loss_per_T"] is None


def test_survey_over_meshes_says_its_continuum_row_stopped(tmp_path, capsys):
    import json

    code, out, err = _run(capsys, ["survey", "--model", "fe", "-N", "4", "8", "--T-list", "5", "--periods", "100",
                                   "--no-plot", "--out", tmp_path / "r"])
    assert code == 0, err
    assert "continuum failed" in out and "march stopped" in out
    d = json.loads((tmp_path / "r" / "survey_refine.json").read_text())["T/L=5"]
    assert d["continuum"] == {"kind": "failed"} and d["loss_per_T"]["against_continuum"]["continuum"] is None


def test_the_continuum_row_of_a_slow_forcing_is_left_out_with_its_cost(tmp_path, capsys):
    """The 3 m column at 0.2 s (T c/L = 236): its continuum row would take hundreds of days; it is left out with a
    note saying so, the meshes' survey runs (before: it ran unannounced into the chatter and the crash)."""
    code, out, err = _run(capsys, ["survey", "--model", "fe", "--length", "3", "--EA", "2.7e9", "--rhoA", "216",
                                   "--load-at", "1.5", "-N", "4", "8", "--T-list", "0.2", "--periods", "50",
                                   "--no-plot", "--out", tmp_path / "col"])
    assert code == 0, err
    assert "continuum's survey would take" in err and "left out" in err
    assert "T c/L = 235.7" in out and "no continuum" in out
    assert not (tmp_path / "col" / "continuum").exists()


def test_the_continuums_estimate_grows_with_the_forcing_period():
    """Its cost per period^2 was measured at T c/L = 2.5; beyond, it grows like (T c/L)^3 (more grid steps and more
    impacts per period), in the case's units (the column: c = 3,536 m/s)."""
    from plbar import Case
    from plbar.app.cost import survey_seconds

    unit = Case(model="continuum")
    col = Case(model="continuum", length=3.0, EA=2.7e9, rhoA=216.0)
    base = survey_seconds(unit, 1, 1000, [2.5])
    assert survey_seconds(unit, 1, 1000) == base
    assert survey_seconds(unit, 1, 1000, [10.0]) == pytest.approx(64 * base, rel=1e-12)
    tau = 3.0 / np.sqrt(2.7e9 / 216.0)
    assert survey_seconds(col, 1, 1000, [10.0 * tau]) == pytest.approx(64 * base, rel=1e-12)


# small numbers are printed with the digits they have (issue 44) -----------------------------------------------------

def test_survey_prints_small_xi_in_significant_digits(tmp_path, capsys):
    """An end mass of 1e-4 on the contact node only (redistributed): xi_eq ~ 1e-5 printed as such, not 0.0000."""
    import csv
    import re

    code, out, err = _run(capsys, ["survey", "--model", "fe", "-N", "4", "--mass", "redistributed", "--end-mass",
                                   "1e-4", "--T-list", "2.5", "3", "--periods", "40", "--no-plot", "--no-paths",
                                   "--out", tmp_path / "s"])
    assert code == 0, err
    rows = list(csv.DictReader((tmp_path / "s" / "survey.csv").open()))
    xi, xw = (np.array([float(r[c]) for r in rows]) for c in ("xi_eq", "xi_w"))
    assert xi.max() < 1e-4                                             # the case is the one of the finding
    num = r"([-+0-9.e]+)"
    m = re.search(rf"xi_eq of every motion: {num} \.\. {num} \(median {num}\); xi_w: {num} \.\. {num}", out)
    assert m, out
    printed = [float(g) for g in m.groups()]
    want = [xi.min(), xi.max(), np.median(xi), xw.min(), xw.max()]
    assert np.allclose(printed, want, rtol=1e-3, atol=0)              # four significant digits


# a survey over meshes (survey -N): one verdict per quantity (issue 44) ----------------------------------------------

#: ``plbar survey --model fe --end-mass 0.5 -N 8 16 32 64 --T-list 3`` (1,000 periods, 100 recorded): its rows
SURVEY_REFINE = [(8, 0.88956402534951695, 0.0019645184353325059, 0.012076878668143474, 6.7359360624607152e-05,
                  0.030062321313453239),
                 (16, 0.6047923929366017, 0.014606381489876386, 0.024211972795888322, 0.0027960561708223592,
                  0.076804549348292075),
                 (32, 0.75819750122332874, 0.037602635221729332, 0.0018385654568636707, 0.00027150675356365736,
                  0.01966970471451682),
                 (64, 0.90579557513921583, 0.22849040924641489, 0.00032680375053910848, 8.5809889867400054e-05,
                  0.0056160819370107383),
                 (0, 0.89890317325441216, 0.18028794990992081, np.nan, np.nan, 0.0012313976869454447)]


def _survey_refine_rates(continuum: bool):
    from plbar.studies.survey.refine import _rates

    rows = [{"N": n, "h": 1.0 / n if n else 0.0, "T": 3.0, "T_L": 3.0, "kind": "irregular", "impacts_per_T": 1.0,
             "loss_per_T": lo, "loss_std": ls, "xi_eq": xi, "xi_std": xs, "xi_w": xw}
            for n, lo, ls, xi, xs, xw in SURVEY_REFINE if continuum or n]
    return _rates(rows, np.array([3.0]), 100, "" if continuum else "none here")


def test_survey_refine_states_no_limit_where_the_values_do_not_converge():
    d = _survey_refine_rates(True)["T/L=3"]
    assert d["loss_per_T"]["limit"] == 0.89890317325441216 and d["loss_per_T"]["method"] == "continuum"
    assert d["xi_w"]["limit"] == 0.0012313976869454447                  # the figure draws |q - continuum|
    assert d["xi_eq"]["caution"]                                         # no continuum value: not stated
    from plbar.cli.survey import _refine_lines

    lines = _refine_lines(_survey_refine_rates(True), [8, 16, 32, 64], True, {})
    text = "\n".join(lines)
    assert "4.657" not in text and "rate 0.06" not in text
    loss = next(ln for ln in lines if ln.strip().startswith("loss_per_T"))
    assert loss.endswith("-> the continuum (N = infinity, below)")
    xi = next(ln for ln in lines if ln.strip().startswith("xi_eq"))      # no continuum value: values that wander
    assert "no limit stated: the successive differences change sign" in xi
    # without a continuum row none of the three has a limit stated (each wanders)
    lines = _refine_lines(_survey_refine_rates(False), [8, 16, 32, 64], False, {})
    assert sum("no limit stated" in ln for ln in lines) == 3 and "4.657" not in "\n".join(lines)


def test_a_richardson_limit_beyond_the_meshes_is_not_stated():
    """q = 1 + h^0.1 (monotone, rate 0.1): its Richardson limit lies further out than the meshes span."""
    from plbar.studies.survey.refine import _rates

    rows = [{"N": n, "h": 1.0 / n, "T": 3.0, "T_L": 3.0, "kind": "periodic", "impacts_per_T": 1.0,
             "loss_per_T": 1 + n ** -0.1, "loss_std": 0.0, "xi_eq": 0.1, "xi_std": 0.0, "xi_w": 0.1}
            for n in (8, 16, 32, 64)]
    c = _rates(rows, np.array([3.0]), 100)["T/L=3"]["loss_per_T"]
    assert c["limit"] == pytest.approx(1.0, rel=1e-6) and c["caution"].startswith("the Richardson limit 1 (rate 0.1)")


# Rayleigh damping evaluated far from its fit: a warning with the ratio there, and xi_total printed (issue 44) -------

def test_outside_fit_names_the_ratio_at_the_forcing_period():
    """The finding's column (L = 3 m, c = sqrt(2.7e9 / 216)): 2 % fitted at its periods, 0.784 at 5 Hz."""
    from plbar.model.damping import outside_fit

    c = np.sqrt(2.7e9 / 216)
    at = (2 * 3 / c, 4 * 3 / c)
    text = outside_fit(0.02, at, [0.2])
    assert "its ratio at T = 0.2 is 0.78" in text and "mass term" in text
    assert outside_fit(0.02, at, [at[0] / 1.9, 1.9 * at[1]]) is None
    assert "stiffness term" in outside_fit(0.02, (4.0, 8.0), [1.0, 5.0])


@pytest.mark.parametrize("T, warned", [("10", True), ("3", False)])
def test_survey_warns_of_damping_far_from_its_fit_and_prints_xi_total(tmp_path, capsys, T, warned):
    code, out, err = _run(capsys, ["survey", "--model", "fe", "-N", "4", "--damping-ratio", "0.02", "--at", "2.05",
                                   "4.03", "--T-list", T, "--periods", "10", "--no-plot", "--no-paths",
                                   "--out", tmp_path / "s"])
    assert code == 0, err
    line = [w for w in err.splitlines() if "Rayleigh damping fitted" in w]
    assert len(line) == warned and all(w.startswith("plbar: warning: ") for w in line)
    if warned:
        assert "its ratio at T = 10 is 0.0356" in line[0]         # alpha / (2 w) + beta w / 2 at T = 10
    assert "xi_total (Rayleigh's ratio at the forcing frequency + xi_eq)" in out


def test_undamped_survey_prints_no_xi_total(tmp_path, capsys):
    code, out, err = _run(capsys, ["survey", "--model", "fe", "-N", "4", "--T-list", "3", "--periods", "10",
                                   "--no-plot", "--no-paths", "--out", tmp_path / "s"])
    assert code == 0, err
    assert "xi_total" not in out and "Rayleigh" not in err


# an FE bar with no mass at its contact: its xi_eq is a mesh artefact, said once (issue 44) --------------------------

@pytest.mark.parametrize("argv, noted", [
    (["--model", "fe", "-N", "4"], True),
    (["--model", "fe", "-N", "4", "--element", "P2", "--mass", "consistent"], True),
    (["--model", "fe", "-N", "4", "--end-mass", "0.5"], False),
    (["--model", "chain", "-N", "4"], False),
])
def test_survey_notes_an_fe_bar_without_contact_mass_once(tmp_path, capsys, argv, noted):
    code, out, err = _run(capsys, ["survey", *argv, "--T-list", "3", "3.5", "--periods", "6", "--no-plot",
                                   "--no-paths", "--out", tmp_path / "s"])
    assert code == 0, err
    assert err.count("xi_eq is a mesh artefact") == noted
    if noted:
        assert "plbar: note: this FE bar has no mass of its own at the contact" in err
        assert "docs/continuum.md" in err and "--end-mass M" in err


def test_no_contact_mass_sees_point_masses_on_the_contact_node():
    import contextlib
    import io
    from types import SimpleNamespace

    import plbar
    from plbar.cli.common import note_no_contact_mass

    for pm, quiet, noted in [((), False, True), (((0.5, 0.2),), False, True), (((1.0, 0.2),), False, False),
                             ((), True, False)]:
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            note_no_contact_mass(SimpleNamespace(quiet=quiet, json=False), plbar.Case(model="fe", n=4, point_masses=pm))
        assert ("mesh artefact" in err.getvalue()) == noted, pm


# input a survey does not use, or used to accept silently (issues 30 and 44) -----------------------------------------

@pytest.mark.parametrize("extra", [[], ["--grid", "50", "50"], ["--method", "grid"], ["--signatures", "all"]])
def test_search_options_do_not_move_the_surveys_periods(tmp_path, capsys, extra):
    """Options a survey does not use leave it alone (before: --grid or --method made the case "not the paper's" and
    moved the default range from [6, 14] to [6.09984, 14.233])."""
    import json

    assert main(["survey", "--num", "3", "--periods", "20", "--no-plot", "--json", "--out", str(tmp_path / "s"),
                 *extra]) == 0
    assert json.loads(capsys.readouterr().out)["summary"]["T"] == [6.0, 10.0, 14.0]


def test_t_list_with_a_range_option_is_refused(tmp_path, capsys):
    for extra in (["--num", "3"], ["--T", "6", "8"]):
        code, _, err = _run(capsys, ["survey", "--T-list", "9", "7", "8", *extra, "--periods", "20", "--no-plot",
                                     "--out", tmp_path / "s"])
        assert code == 2 and f"{extra[0]} conflicts with --T-list" in err and err.count("\n") == 1
    assert not (tmp_path / "s" / "survey.csv").exists()


# Ctrl-C in a survey (issue 30) --------------------------------------------------------------------------------------

SURVEY = ["survey", "--T", "6", "14", "--num", "12", "--periods", "20000", "--chunks", "6", "--no-plot",
          "--executor", "local", "--workers", "2"]


@pytest.mark.slow
def test_ctrl_c_in_a_survey_exits_130_keeps_the_finished_tasks_and_resumes(tmp_path):
    """Ctrl-C once a task has finished: exit 130 with the rerun hint, every finished task kept; the rerun resumes
    (the kept task files untouched) and writes the table an uninterrupted survey writes (before: AttributeError,
    exit 1, after the pool's shutdown forgot its workers)."""
    out = tmp_path / "sv"
    p = _plbar(SURVEY + ["--out", str(out)])
    t0 = time.time()
    while p.poll() is None and time.time() - t0 < 120 and not any((out / "tasks").glob("[!.]*.json")):
        time.sleep(0.05)                       # (a finished task's file, not its temporary .KEY.*.part.json)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    if p.returncode == 0:
        pytest.skip("the survey finished before the interrupt")
    assert p.returncode == 130, err
    assert "interrupted" in err and "rerun" in err and "Error" not in err
    kept = {f.name: f.stat().st_mtime_ns for f in (out / "tasks").glob("*.json")}
    assert kept
    assert main(SURVEY + ["--out", str(out), "-q"]) == 0
    assert all((out / "tasks" / n).stat().st_mtime_ns == t for n, t in kept.items())
    ref = tmp_path / "ref"
    assert main(SURVEY + ["--out", str(ref), "-q"]) == 0
    assert (out / "survey.csv").read_bytes() == (ref / "survey.csv").read_bytes()


def test_a_survey_interrupted_before_any_task_leaves_no_folder(tmp_path):
    """Interrupted before any task finished (each takes seconds here): exit 130 and no folder left (before: the
    folder, made before the claim, stayed with the owner marker)."""
    out = tmp_path / "sv0"
    slow = [a if a != "20000" else "400000" for a in SURVEY]
    p = _plbar(slow + ["--out", str(out)], env=dict(os.environ))
    t0 = time.time()
    while not (out / "study.json").exists() and time.time() - t0 < 60 and p.poll() is None:
        time.sleep(0.01)
    p.send_signal(signal.SIGINT)
    p.communicate(timeout=120)
    if any((out / "tasks").glob("*.json")):
        pytest.skip("a task finished before the interrupt")
    assert p.returncode == 130
    assert not out.exists()
