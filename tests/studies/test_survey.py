"""The survey: the values against the exact responses of plbar run, the energy budget, reproducibility, the CLI."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import plbar
from plbar.cli import main
from plbar.response import find_response
from plbar.studies import get_executor
from plbar.studies.survey import run_survey, survey

PAPER = ["--signatures", "paper"]      # the paper's class only: these runs are not about the other signatures

#: forcing periods of the default case where the bar settles from rest on responses of the paper's class
CLASS_T = np.linspace(11.5, 12.1, 7)


@pytest.fixture(scope="module")
def class_survey():
    return survey(plbar.Case(), CLASS_T, periods=1000, record=100)


def test_periodic_one_impact_equals_the_paths_of_plbar_run(class_survey, default_result):
    """Where the survey says periodic, m = 1, one impact: loss and xi_eq equal the exact response on a branch of
    ``plbar run`` at that T (1e-6), the simulated values being means over the recorded periods."""
    t = class_survey.rows("rest")
    prob = default_result.prob
    checked = 0
    for i in np.flatnonzero((t["kind"] == "periodic") & (t["m"] == 1) & (t["impacts_per_T"] == 1)):
        T, loss = t["T"][i], t["loss_per_T"][i]
        # the branch point of plbar run nearest in (T, loss), carried to T along the branch by find_response
        best = None
        for b in default_result.paths.branches:
            j = np.argmin(np.abs(b.T - T) / T + np.abs(b.dPL - loss) / max(loss, 1e-12))
            d = abs(b.T[j] - T) / T + abs(b.dPL[j] - loss) / loss
            if best is None or d < best[0]:
                best = (d, b, j)
        _, b, j = best
        assert abs(b.T[j] - T) < 0.02 * T
        r = find_response(prob, T, b.T1[j] * T / b.T[j])
        assert t["exact_loss"][i] == pytest.approx(r.dPL, rel=1e-12)          # the survey's own polish
        assert t["exact_xi"][i] == pytest.approx(r.xi, rel=1e-10)
        # the window's means: on the orbit (1e-6), or still settling on it (about its distance from it)
        tol = max(1e-6, 3 * t["orbit_distance"][i])
        assert r.dPL == pytest.approx(loss, rel=tol)
        assert r.xi == pytest.approx(t["xi_eq"][i], rel=tol)
        assert t["xi_w"][i] == pytest.approx(_xi_w(r), rel=tol)
        checked += 1
    assert checked >= 5


def _xi_w(r):
    from plbar.response import damping

    return float(damping(r.orbit).xi_w[0])


def test_energy_budget_closes_everywhere(class_survey):
    assert np.all(np.abs(class_survey.table["energy_residual"]) <= 1e-9)


def test_the_survey_reports_irregular_motion_as_such():
    s = survey(plbar.Case(), [6.8, 7.0], periods=300, record=60)
    t = s.table
    assert set(t["kind"]) == {"irregular"} and np.all(t["m"] == 0)
    assert np.all(t["loss_max"] > t["loss_min"])


def _files(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file() and p.name != "summary.json"}


def _table_bytes(folder):
    return (folder / "survey.csv").read_bytes()


@pytest.mark.slow
def test_same_command_twice_and_dask_give_identical_files(tmp_path):
    pytest.importorskip("dask.distributed")
    T = np.linspace(8.3, 9.3, 6)
    out = {}
    for kind in ("local", "local2", "dask"):
        with get_executor("dask" if kind == "dask" else "local", workers=2) as ex:
            run_survey(plbar.Case(), T, 120, 20, tmp_path / kind, ("rest", "up"), executor=ex, plot=False)
        out[kind] = _table_bytes(tmp_path / kind)
    assert out["local"] == out["local2"] == out["dask"]
    s = json.loads((tmp_path / "local" / "summary.json").read_text())
    assert s["rows"] == 12 and s["plbar_version"] == plbar.__version__


#: the survey of the kill test; with PLBAR_TEST_PAUSE set, a sweep pauses after its second checkpoint (so that the
#: kill lands mid-sweep however fast the machine: the whole sweep takes less than the test's polling interval)
SCRIPT = """
import os, sys, time, numpy as np, plbar
import plbar.studies.survey.tasks as tasks
from plbar.studies.survey import run_survey
if os.environ.get("PLBAR_TEST_PAUSE"):
    _write = tasks.write_json
    def write_json(path, data):
        out = _write(path, data)
        if os.path.basename(str(path)).startswith("T") and len(list(os.scandir(os.path.dirname(str(path))))) >= 2:
            time.sleep(60)
        return out
    tasks.write_json = write_json
run_survey(plbar.Case(), np.linspace(8.0, 9.0, 8), 150, 20, sys.argv[1], ("rest", "down"), plot=False)
"""


@pytest.mark.slow
def test_kill_and_resume(tmp_path):
    """kill -9 in the middle of a sweep: checkpoints are whole files; the rerun resumes and gives the same table."""
    killed = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT, str(killed)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, env=dict(os.environ, PLBAR_TEST_PAUSE="1"),
                            start_new_session=True)
    sweeps = killed / "sweeps"
    t0 = time.time()
    while time.time() - t0 < 120:
        if sweeps.is_dir() and len(list(sweeps.rglob("T*.json"))) >= 2:
            break
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)                # its workers too: none writes after the kill
    proc.wait()
    done = list(sweeps.rglob("T*.json"))
    assert 2 <= len(done) < 8, "the kill should land mid-sweep"
    for p in done:
        json.loads(p.read_text())                     # complete JSON, never a partial file
    assert not (killed / "survey.csv").exists()
    for folder in (killed, tmp_path / "fresh"):
        r = subprocess.run([sys.executable, "-c", SCRIPT, str(folder)], capture_output=True, timeout=600)
        assert r.returncode == 0, r.stderr.decode()
    assert _table_bytes(killed) == _table_bytes(tmp_path / "fresh")


def test_cli_survey_vocabulary(tmp_path, capsys):
    out = tmp_path / "s"
    args = ["survey", "--T", "11.6", "11.9", "--num", "3", "--periods", "200", "--record", "20", "--out", str(out),
            "--no-plot"]
    assert main(args + ["--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["summary"]["rows"] == 3 and set(payload["files"]) == {"table", "summary"}
    header = (out / "survey.csv").read_text().splitlines()[0].split(",")
    assert header[:13] == ("T,kind,m,impacts_per_T,loss_per_T,loss_min,loss_max,xi_eq,xi_min,xi_max,xi_w,amp_c,"
                           "stuck_fraction").split(",")
    assert main(args + ["--quiet"]) == 0 and capsys.readouterr().out == ""          # resumes, same files
    assert main(args[:-1] + ["--num", "4", "-q"]) == 2                             # another survey: refused
    assert "another case (written by 'plbar survey')" in capsys.readouterr().err
    assert main(args + ["--num", "4", "-q", "--overwrite"]) == 0
    assert main(["survey", "--T", "3", "1", "--out", str(tmp_path / "b")]) == 2
    assert main(["survey", "--periods", "10", "--record", "10", "--out", str(tmp_path / "c")]) == 2


def test_short_survey_without_record(tmp_path, capsys):
    """--periods below 100 needs no --record: the last tenth is recorded (it was an error: record 100 > periods)."""
    from plbar.studies.survey import default_record

    assert [default_record(p) for p in (2, 30, 999, 1000, 5000)] == [1, 3, 99, 100, 100]
    out = tmp_path / "short"
    assert main(["survey", "--T-list", "11.7", "--periods", "30", "--out", str(out), "--no-plot", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["summary"]["record"] == 3


def test_run_and_survey_do_not_share_a_folder(tmp_path, capsys):
    assert main(["run", *PAPER, "--out", str(tmp_path), "--no-plot", "-q"]) == 0
    assert main(["survey", "--T-list", "10", "--periods", "50", "--record", "5", "--out", str(tmp_path), "-q"]) == 2
