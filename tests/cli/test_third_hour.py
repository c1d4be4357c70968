"""A newcomer's third hour (issue 30): Ctrl-C in a survey, refused inputs that leave nothing behind."""

import os
import signal
import subprocess
import sys
import time

import pytest

from plbar.cli import main

SURVEY = ["survey", "--T", "6", "14", "--num", "12", "--periods", "20000", "--chunks", "6", "--no-plot",
          "--executor", "local", "--workers", "2"]


def _plbar(args, **kw):
    """``python -m plbar ARGS`` with Ctrl-C's default (a test runner started in the background ignores SIGINT, and a
    child would inherit that: Python then installs no KeyboardInterrupt)."""
    return subprocess.Popen([sys.executable, "-m", "plbar", *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL), **kw)


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


@pytest.mark.parametrize("bad", [["--periods", "1"], ["--record", "2000", "--periods", "100"],
                                 ["--T-list", "-1", "8"], ["--positions", "7"]])
def test_a_refused_survey_leaves_no_folder(tmp_path, capsys, bad):
    out = tmp_path / "a" / "b"
    assert main(["survey", "--num", "3", "--out", str(out), "-q", *bad]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not (tmp_path / "a").exists()


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


@pytest.mark.parametrize("extra", [[], ["--grid", "50", "50"], ["--method", "grid"], ["--signatures", "all"]])
def test_search_options_do_not_move_the_surveys_periods(tmp_path, capsys, extra):
    """Options a survey does not use leave it alone (before: --grid or --method made the case "not the paper's" and
    moved the default range from [6, 14] to [6.09984, 14.233])."""
    import json

    assert main(["survey", "--num", "3", "--periods", "20", "--no-plot", "--json", "--out", str(tmp_path / "s"),
                 *extra]) == 0
    assert json.loads(capsys.readouterr().out)["summary"]["T"] == [6.0, 10.0, 14.0]


def test_errors_say_what_to_give(tmp_path, capsys):
    """``run -N 8 16`` names the one size run takes and where several go (before: "conflicts with the case file
    '16'"); an FE bar too fine for its shortest element says the largest N (before: "element 25005 ... too short")."""
    assert main(["run", "-N", "8", "16", "--out", str(tmp_path / "r"), "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert "one size" in err and "plbar refine -N 8 16" in err and "case file '16'" not in err
    assert main(["run", "--model", "fe", "-N", "100000", "--out", str(tmp_path / "r"), "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert "N <= 99999" in err and "element 25005" not in err
    assert not (tmp_path / "r").exists()


CHEAP_RUN = ["run", "--no-plot", "--signatures", "paper", "-q"]     # about 2 s: two of them overlap


def test_two_cases_into_one_folder_at_once_one_is_refused(tmp_path):
    """Two runs of different cases started together on one folder: one writes, the other is refused with exit 2 and
    one line; the folder holds the winner's case (before: both exited 0, both said "wrote", one case was lost)."""
    import json

    out = str(tmp_path / "same")
    ps = [_plbar(CHEAP_RUN + ["--out", out]), _plbar(CHEAP_RUN + ["--out", out, "--load-node", "3"])]
    res = [(p.wait(timeout=300), p.communicate()[1]) for p in ps]
    assert sorted(rc for rc, _ in res) == [0, 2], res
    won = [rc for rc, _ in res].index(0)
    lost_err = res[1 - won][1]
    assert "error: output folder" in lost_err and lost_err.count("plbar: error") == 1
    load = json.loads((tmp_path / "same" / "summary.json").read_text())["case"]["load_nodes"]
    assert (load == [[3, 1.0]]) == (won == 1)
    assert not (tmp_path / "same" / ".plbar-lock").exists()


def test_the_same_case_twice_at_once_one_is_refused(tmp_path):
    """The same case twice at once on one folder: the second is refused while the first runs (documented in
    docs/cli.md), the results are the first's, whole."""
    out = str(tmp_path / "same")
    ps = [_plbar(CHEAP_RUN + ["--out", out]) for _ in range(2)]
    res = [(p.wait(timeout=300), p.communicate()[1]) for p in ps]
    if sorted(rc for rc, _ in res) == [0, 0]:
        pytest.skip("the two runs did not overlap")
    assert sorted(rc for rc, _ in res) == [0, 2], res
    assert "in use by another plbar command" in "".join(err for _, err in res)
    assert main(CHEAP_RUN + ["--out", out]) == 0


def test_a_folder_locked_by_a_live_process_is_refused_a_dead_ones_lock_is_taken_over(tmp_path, capsys):
    import json
    import socket

    out = tmp_path / "r"
    out.mkdir()
    live = subprocess.Popen(["sleep", "60"])
    try:
        (out / ".plbar-lock").write_text(json.dumps({"pid": live.pid, "host": socket.gethostname()}))
        assert main(CHEAP_RUN + ["--out", str(out)]) == 2
        assert f"in use by another plbar command (pid {live.pid})" in capsys.readouterr().err
        assert not (out / "summary.json").exists()
    finally:
        live.kill()
        live.wait()
    assert main(CHEAP_RUN + ["--out", str(out)]) == 0          # its process is dead: a stale lock
    assert (out / "summary.json").exists() and not (out / ".plbar-lock").exists()


def _stop(*a, **k):
    raise KeyboardInterrupt                                         # the user's Ctrl-C, right at the start


@pytest.mark.parametrize("args, says", [
    (["run", "--model", "fe", "-N", "2000", "--no-plot"], ["days", "12.3 GB", "'plbar refine'", "--yes to start"]),
    (["sweep-loads", "--model", "fe", "-N", "2000", "--no-plot"], ["days", "GB", "--yes to start"]),
    (["survey", "--num", "100000", "--periods", "20000", "--no-plot"],
     ["100,000 motions x 20,000 forcing periods", "hours", "--num", "--yes to start"]),
    (["run", "--model", "fe", "-N", "99999", "--no-plot", "--yes"], ["240.0 GB", "memory", "not started"])],
    ids=["run", "sweep-loads", "survey", "beyond-memory"])
def test_a_costly_job_is_refused_before_anything_is_made(tmp_path, capsys, args, says):
    """Above an hour or half the memory: exit 2, one line with the estimate, what to do instead and --yes (before:
    "about 4 days and 12.3 GB" and it started; a survey of 100,000 periods started without a word; -N 99999 died
    with a MemoryError, a 74.5 GiB dense eigenproblem); larger than the memory: refused even with --yes."""
    assert main([*args, "--out", str(tmp_path / "big")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and all(s in err for s in says), err
    assert not (tmp_path / "big").exists()


def test_yes_starts_a_costly_job_and_the_default_jobs_start_without_it(tmp_path, capsys, monkeypatch):
    import plbar.cli.run as cli_run
    import plbar.studies.survey as survey

    monkeypatch.setattr(cli_run, "solve", _stop)
    monkeypatch.setattr(survey, "run_survey", _stop)
    assert main(["run", "--model", "fe", "-N", "2000", "--no-plot", "--yes", "--out", str(tmp_path / "a")]) == 130
    assert "note: this solve (2000 DOFs" in capsys.readouterr().err
    for args in (["run", "--no-plot"], ["survey", "--no-plot"]):
        assert main([*args, "--out", str(tmp_path / "b")]) == 130
        err = capsys.readouterr().err
        assert "error" not in err and "note" not in err and err.startswith("plbar: interrupted"), err
    assert main(["survey", "--num", "100000", "--no-plot", "--out", str(tmp_path / "c")]) == 130   # a note, then it
    err = capsys.readouterr().err                                                               # starts (14 min)
    assert "note: this survey simulates 100,000 motions x 1,000 forcing periods" in err and "error" not in err, err


def test_an_interrupted_progress_line_says_interrupted(capsys, monkeypatch):
    """The last line of a phase ended by Ctrl-C (before: "scanning: 0/40000 points (0 %), done in 10.0 s")."""
    from plbar.util.progress import progress_bar

    monkeypatch.setenv("PLBAR_PROGRESS_DELAY", "0")
    with pytest.raises(KeyboardInterrupt):
        with progress_bar(40000, True, "scanning", "point") as bar:
            bar.update(5)
            raise KeyboardInterrupt
    with progress_bar(3, True, "scanning", "point") as bar:
        bar.update(3)
    lines = capsys.readouterr().err.splitlines()
    assert lines[-2].startswith("plbar: scanning: 5/40000 points (0 %), interrupted after ") and "done" not in lines[-2]
    assert lines[-1].startswith("plbar: scanning: 3/3 points (100 %), done in ")


CASE_TOML = '[bar]\nmodel = "chain"\nn = 5\n[search]\ngrid = [30, 30]\nsignatures = "paper"\n'


@pytest.fixture(scope="module")
def cheap_run(tmp_path_factory):
    """A run folder (for export and render --from) and a cheap case file (for --case)."""
    d = tmp_path_factory.mktemp("cheap")
    assert main(["run", "--no-plot", "--signatures", "paper", "--grid", "30", "30", "-q", "--out", str(d / "run")]) == 0
    (d / "c.toml").write_text(CASE_TOML)
    return d


REFUSED = {
    "run": [["--T1", "-1", "2"], ["-N", "0"], ["--grid", "1", "1"], ["--load-node", "9"], ["--modes", "0"],
            ["--model", "fe", "-N", "2000"]],
    "refine": [["--workers", "0"], ["--executor", "dask"], ["-N", "0", "4"], ["--window", "-1"], ["--family", "foo"]],
    "sweep-loads": [["--positions", "99"], ["-N", "0"], ["--per-element", "0"], ["--T1", "5", "1"],
                    ["--model", "fe", "-N", "2000"]],
    "export": [["--from", "{run}", "--branch", "999"], ["--from", "{run}", "--steps", "2"],
               ["--from", "{run}", "--periods", "5"], ["--case", "{case}", "--from", "{new}", "--branch", "999"],
               ["--case", "{case}", "--from", "{new}", "--index", "99999"]],
    "render": [["--from", "{run}", "--field", "foo"], ["--from", "{run}", "--snapshots", "0"],
               ["--case", "{case}", "--from", "{new}", "--branch", "999"]],
}


@pytest.mark.parametrize("cmd, bad", [(c, b) for c, bs in REFUSED.items() for b in bs],
                         ids=[f"{c}{' '.join(b)}" for c, bs in REFUSED.items() for b in bs])
def test_a_refused_command_leaves_no_folder(tmp_path, capsys, monkeypatch, cheap_run, cmd, bad):
    """Every command that writes a folder validates before it makes one: a refused input (exit 2, one line) leaves
    neither its --out nor, for export/render --case, the run folder (before: export/render --case solved and
    wrote the run, then refused the --branch or --index; run made its folder before its cost was checked)."""
    import sys

    if cmd in ("export", "render"):
        pytest.importorskip("pyvista")
    monkeypatch.setitem(sys.modules, "dask.distributed", None)         # "--executor dask" without dask installed
    args = [b.format(run=cheap_run / "run", case=cheap_run / "c.toml", new=tmp_path / "a" / "run") for b in bad]
    plot = ["--no-plot"] if cmd in ("run", "refine", "sweep-loads") else []
    assert main([cmd, *args, *plot, "--out", str(tmp_path / "a" / "b"), "-q"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not (tmp_path / "a").exists()


JSON_COMMANDS = {
    "run": ["run", "--no-plot", "--signatures", "paper", "--grid", "30", "30"],
    "mesh": ["mesh"],
    "sweep-loads": ["sweep-loads", "--no-plot", "--grid", "30", "30", "--positions", "1", "2"],
    "refine": ["refine", "-N", "3", "4", "--grid", "30", "30", "--executor", "serial", "--no-plot"],
    "figures": ["figures", "--only", "fig2", "--grid", "20", "20"],
    "survey": ["survey", "--num", "3", "--periods", "20", "--no-plot", "--executor", "serial"],
    "export": ["export", "--from", "{run}", "--steps", "8"],
    "render": ["render", "--from", "{run}", "--steps", "8", "--snapshots", "1", "--no-gif"],
}


@pytest.mark.parametrize("cmd", list(JSON_COMMANDS))
def test_every_commands_json_is_one_shape(tmp_path, capsys, cheap_run, cmd):
    """``--json``: a top-level ``summary`` object and a ``files`` object (name -> path or list of paths), for every
    command (before: refine had no summary, export and render an ``info``, mesh and figures a list of files)."""
    import json

    if cmd in ("export", "render"):
        pytest.importorskip("pyvista")
    if cmd == "figures":
        pytest.importorskip("matplotlib")
    args = [x.format(run=cheap_run / "run") for x in JSON_COMMANDS[cmd]]
    assert main([*args, "--out", str(tmp_path / "o"), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert isinstance(got["summary"], dict) and got["summary"], got
    assert isinstance(got["files"], dict) and got["files"], got
    assert all(isinstance(v, (str, list)) for v in got["files"].values())
    assert "info" not in got


FE_RUN = ["run", "--model", "fe", "-N", "6", "--element", "P2", "--mass", "consistent", "--load-at", "0.37", "--grid",
          "60", "60", "--signatures", "paper", "--no-plot"]


def test_an_fe_run_leads_with_its_stable_responses(tmp_path, capsys):
    """The summary says how many points are stable, lists branches with stable points first and no branch of fewer
    than 3 points (before: a 1-point branch in the top five, the stable ones among the rest)."""
    assert main([*FE_RUN, "--out", str(tmp_path / "f")]) == 0
    out = capsys.readouterr().out.splitlines()
    assert any("points are stable, on 2 branches" in line for line in out)
    listed = [line for line in out if line.startswith("  branch ")]
    stable = [int(line.rsplit(",", 1)[1].split()[0]) > 0 for line in listed]
    assert len(listed) == 5 and stable == sorted(stable, reverse=True) and stable[0]
    assert all(int(line.split(":")[1].split()[0]) >= 3 for line in listed)


def test_a_run_without_a_stable_point_points_to_the_survey(tmp_path, capsys):
    """No stable point: one line says so and names the survey with the same case options."""
    fe = FE_RUN[:FE_RUN.index("--grid")]
    assert main([*fe, "--grid", "40", "40", "--signatures", "paper", "--no-plot", "--T1", "0.08", "0.16", "--T2", "0.6",
                 "0.85", "--out", str(tmp_path / "f")]) == 0
    out = capsys.readouterr().out.splitlines()
    i = next(i for i, line in enumerate(out) if line.startswith("  none of"))        # after the units' lines
    found = next(line for line in out if "admissible path points" in line).split()[2]   # "  1 branches, 385 ..."
    assert out[i].startswith(f"  none of the {found} points is stable") and out[i].endswith(
        "run plbar survey --model fe -N 6 --element P2 --mass consistent --load-at 0.37")
    assert "stable points first" not in out[i + 1]


def test_nothing_found_warns_and_the_plot_covers_the_range_asked(tmp_path, capsys, monkeypatch):
    """A search window with no response: a warning naming it, and a figure over the range asked (before: "0
    branches" without a word, then 'failed: ValueError: Data cannot be log-scaled', exit 1)."""
    pytest.importorskip("matplotlib")
    import plbar.visuals.plots as plots

    seen = {}
    save = plots._save

    def spy(fig, out, name):
        seen[name] = fig.axes[-1].get_xlim()
        return save(fig, out, name)

    monkeypatch.setattr(plots, "_save", spy)
    assert main(["run", "--T1", "0.001", "0.002", "--T2", "0.001", "0.002", "--grid", "40", "40", "--signatures",
                 "paper", "--out", str(tmp_path / "e")]) == 0
    err = capsys.readouterr().err
    assert "warning: no admissible periodic response in T1 = [0.001, 0.002]" in err
    assert seen["frequency_response"] == pytest.approx((0.002, 0.004))


def test_small_inputs_say_what_they_do(tmp_path, capsys):
    """survey --num 1 is refused with what to give (before: only T = 6, a clipped figure); --modes beyond the DOFs is
    refused (before: accepted and recorded as 1000); the FE survey's default periods end where run's search does
    (before: up to 2.25 T0_I, half the figure without exact branches); sweep-loads says "largest xi_eq", not "worst"."""
    import plbar
    from plbar.app.signatures import hybrid_window
    from plbar.paths.branches import default_domain
    from plbar.studies.survey import default_periods

    assert main(["survey", "--num", "1", "--out", str(tmp_path / "s"), "-q"]) == 2
    assert "--T-list" in capsys.readouterr().err and not (tmp_path / "s").exists()
    assert main(["run", "--modes", "1000", "--no-plot", "--out", str(tmp_path / "m")]) == 2
    assert "at most 5" in capsys.readouterr().err and not (tmp_path / "m").exists()
    case = plbar.Case(model="fe", n=8)
    prob = case.problem()
    assert default_periods(case, 5)[-1] == pytest.approx(hybrid_window(prob, default_domain(prob))[1])
    assert main(["sweep-loads", "-N", "4", "--load-at", "1.5", "--grid", "40", "40", "--positions", "1", "2",
                 "--no-plot", "--out", str(tmp_path / "w")]) == 0
    out = capsys.readouterr().out
    assert "largest xi_eq of any load" in out and "worst" not in out.replace("worst_load", "")
