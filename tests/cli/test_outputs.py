"""What every command writes: one owner per output folder (refused, overwritten, locked while in use), a destination
checked before the work, --json of one shape, progress in whole lines.

From the newcomer reports (the first hour, issues 22 and 30). Where a test failed on the code before the fix it
covers, its docstring says so (or says what happened before).
"""

import io
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

import plbar
from plbar.cli import main
from plbar.errors import OutputExistsError

from _helpers import CASES, FAST, PAPER, _plbar, _refused, _run


# one owner per output folder, one overwrite rule for every command --------------------------------------------------

def test_run_then_sweep_loads_into_one_folder_is_refused(tmp_path, capsys):
    """Failed on the code before the fix it covers (issue 22)."""
    out = tmp_path / "Y"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", out, *FAST])[0] == 0
    before = (out / "summary.json").read_text()
    _refused(capsys, ["sweep-loads", "-N", "4", "--out", out, *FAST], "'plbar run'", "--overwrite")
    assert (out / "summary.json").read_text() == before
    _refused(capsys, ["refine", "-N", "3", "4", "--grid", "30", "30", "--out", out, "-q"], "'plbar run'")
    assert not (out / "study.json").exists() and not (out / "levels").exists()


def test_run_into_a_refine_folder_is_refused_and_overwrite_clears_only_the_owners_files(tmp_path, capsys):
    """Failed on the code before the fix it covers (issue 22)."""
    out = tmp_path / "R"
    assert _run(capsys, ["refine", "-N", "3", "4", "--grid", "30", "30", "--executor", "serial", "--out", out,
                         "-q", "--no-plot"])[0] == 0
    (out / "notes.txt").write_text("mine")
    _refused(capsys, ["run", *PAPER, "-N", "4", "--out", out, *FAST], "'plbar refine'")
    _refused(capsys, ["sweep-loads", "-N", "4", "--out", out, *FAST], "'plbar refine'")
    assert (out / "study.json").is_file() and (out / "levels").is_dir()
    assert _run(capsys, ["sweep-loads", "-N", "4", "--out", out, *FAST, "--overwrite"])[0] == 0
    names = {p.name for p in out.iterdir()}
    assert not {"study.json", "tasks", "levels", "refine.csv"} & names and "notes.txt" in names
    owner = json.loads((out / ".plbar-owner.json").read_text())
    assert owner["command"] == "sweep-loads" and owner["plbar"] == plbar.__version__


def test_the_marker_names_command_case_and_owned_files(tmp_path, capsys):
    """Failed on the code before the fix it covers (issue 22)."""
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", tmp_path, *FAST])[0] == 0
    m = json.loads((tmp_path / ".plbar-owner.json").read_text())
    assert set(m) == {"command", "fingerprint", "owned", "plbar"} and m["command"] == "run"
    assert m["fingerprint"] == plbar.app.case_fingerprint(plbar.Case(n=4, grid=(30, 30), signatures="paper"))
    assert {"paths.csv", "summary.json", "vtk", "render"} <= set(m["owned"])


def test_claim_folder_is_one_rule_for_every_command(tmp_path):
    """Failed on the code before the fix it covers (issue 22)."""
    from plbar.util.outputs import check_folder, claim_folder, read_owner

    d = tmp_path / "a" / "b"
    claim_folder(d, "survey", "f1", ("survey.csv", "parts"), False)
    (d / "survey.csv").write_text("x")
    claim_folder(d, "survey", "f1", ("survey.csv",), False)                  # the same study: resumes
    with pytest.raises(OutputExistsError, match="another case"):
        claim_folder(d, "survey", "f2", ("survey.csv",), False)
    with pytest.raises(OutputExistsError, match="'plbar survey'"):
        claim_folder(d, "run", "f1", ("paths.csv",), False)
    claim_folder(d, "export", "f1", ("response.pvd",), False, joins=("survey",))   # joins the same case
    assert read_owner(d).command == "survey" and "response.pvd" in read_owner(d).owned
    (d / "response.pvd").write_text("x")
    claim_folder(d, "run", "f3", ("paths.csv",), True)                       # overwrite: the old owner's files go
    assert not (d / "survey.csv").exists() and not (d / "response.pvd").exists()
    e = tmp_path / "new" / "deep"
    with pytest.raises(KeyboardInterrupt), check_folder(e, "run", "f", ("paths.csv",)) as claim:
        claim.take()
        raise KeyboardInterrupt                                         # nothing written: the claim is undone
    assert not (tmp_path / "new").exists()


def test_export_into_the_run_folder_then_run_overwrite_leaves_no_stale_paraview_data(tmp_path, capsys):
    """Failed on the code before the fix it covers (issue 22)."""
    pytest.importorskip("pyvista")
    R = tmp_path / "R"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", R, *FAST])[0] == 0
    assert _run(capsys, ["export", "--from", R, "--out", R, "--steps", "8", "-q"])[0] == 0
    assert (R / "response.pvd").is_file() and (R / "response.json").is_file()
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--load-node", "3", "--out", R, *FAST, "--overwrite"])[0] == 0
    left = sorted(p.name for p in R.iterdir() if p.name.startswith("response"))
    assert left == [] and json.loads((R / "summary.json").read_text())["case"]["load_nodes"] == [[3, 1.0]]


def test_overwrite_clears_the_previous_export_and_render(tmp_path, capsys):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    out = tmp_path / "X"
    assert _run(capsys, ["run", *PAPER, "-N", "5", "--grid", "40", "40", "--out", out, "-q", "--no-plot"])[0] == 0
    (out / "vtk").mkdir()
    (out / "vtk" / "response.pvd").write_text("old")
    (out / "vtk" / "response.xdmf").write_text("old")
    (out / "render").mkdir()
    (out / "render" / "snapshot_00.png").write_text("old")
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--grid", "40", "40", "--out", out, "-q", "--no-plot",
                         "--overwrite"])[0] == 0
    assert not (out / "vtk").exists() and not (out / "render").exists()
    assert json.loads((out / "summary.json").read_text())["dofs"] == 4


def test_mesh_keeps_existing_files_unless_overwrite(tmp_path, capsys):
    """README: 'plbar mesh keeps existing files unless --overwrite' (it used to exit 2): missing ones are written.
    Failed on the code before the fix it covers (a newcomer's first hour)."""
    assert _run(capsys, ["mesh", "--out", tmp_path, "-q"])[0] == 0
    f, g = sorted(tmp_path.glob("*.msh"))[:2]
    f.write_text("edited")
    g.unlink()
    code, out, err = _run(capsys, ["mesh", "--out", tmp_path])
    assert code == 0 and err == "" and f.read_text() == "edited" and g.is_file()
    assert "kept" in out and "--overwrite replaces them" in out and str(g) in out
    assert _run(capsys, ["mesh", "--out", tmp_path, "--overwrite", "-q"])[0] == 0 and f.read_text() != "edited"


def test_output_folders_are_ignored_by_git():
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    text = (Path(__file__).resolve().parents[2] / ".gitignore").read_text().split()
    for pat in ("plbar-out/", "plbar-*/", "results/"):
        assert pat in text


# two commands on one folder at once: one is refused (issue 30) ------------------------------------------------------

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


# an unusable output folder is found before the work -----------------------------------------------------------------

@pytest.mark.parametrize("cmd", [["run", *PAPER, "--model", "fe", "-N", "8"], ["sweep-loads"], ["figures"],
                                 ["export", "--case", str(CASES / "chain_N3_node1.toml")]])
def test_bad_destination_exit_2_before_work(tmp_path, capsys, cmd):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    blocker = tmp_path / "file"
    blocker.write_text("x")
    dest = ["--out", blocker / "sub"]
    t0 = time.perf_counter()
    code, out, err = _run(capsys, cmd + dest + (["--from", tmp_path / "run"] if cmd[0] == "export" else []))
    assert code == 2 and err.startswith("plbar: error:") and err.count("\n") == 1, err
    assert "is a file" in err and time.perf_counter() - t0 < 5


def test_unwritable_destination_exit_2(tmp_path, capsys):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    code, _, err = _run(capsys, ["run", *PAPER, "--model", "fe", "-N", "8", "--out", "/proc/plbar_x"])
    assert code == 2 and "cannot be written" in err and err.count("\n") == 1


# --json: one shape for every command (issue 30) ---------------------------------------------------------------------

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


# progress: whole lines when stderr is not a terminal, in every long phase, and where Ctrl-C ended it ----------------

def test_progress_is_whole_lines_and_messages_start_on_a_new_line(monkeypatch):
    """Failed on the code before the fix it covers (issue 22)."""
    from plbar.util import progress as prog

    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr(prog, "EVERY", 0.0)
    with prog.progress_bar(4, True, "scanning", "point", delay=0.0) as bar:
        bar.update(1)
        prog.message("plbar: warning: something")
        bar.update(3)
    text = err.getvalue()
    assert "\r" not in text and text.endswith("\n")
    lines = text.splitlines()
    assert all(line.startswith("plbar: ") for line in lines), lines
    assert "plbar: warning: something" in lines and lines[-1].startswith("plbar: scanning: 4/4 points (100 %), done")


def test_a_piped_run_writes_whole_lines(tmp_path):
    """A real run with progress on and stderr a pipe: no carriage return, every line a plbar message.
    Failed on the code before the fix it covers (issue 22)."""
    r = subprocess.run([sys.executable, "-m", "plbar", "run", *PAPER, "--model", "fe", "-N", "6", "--element", "P2",
                        "--grid", "40", "40", "--out", str(tmp_path / "o"), "--no-plot"],
                       capture_output=True, text=True, env=dict(os.environ, PLBAR_PROGRESS_DELAY="0"), timeout=600)
    assert r.returncode == 0, r.stderr
    assert "\r" not in r.stderr and r.stderr.endswith("\n")
    lines = r.stderr.splitlines()
    assert lines and all(line.startswith("plbar: ") for line in lines), lines
    assert any("warning" in line for line in lines) and any("scanning" in line for line in lines)


def test_scan_shows_progress(monkeypatch):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    import plbar.util.progress as prog

    seen = []
    real = prog.progress_bar

    def spy(total, enabled, desc, unit="it", delay=1.0):
        seen.append((desc, enabled))
        return real(total, False, desc, unit, delay)

    monkeypatch.setattr(prog, "progress_bar", spy)
    monkeypatch.setattr(sys.modules["plbar.paths.scan"], "progress_bar", spy)
    plbar.find_paths(plbar.Case(n=3).problem(), grid=(30, 30), progress=True)
    assert ("scanning", True) in seen


def test_edge_refinement_shows_progress(monkeypatch):
    """Failed on the code before the fix it covers (issue 22)."""
    import plbar.util.progress as prog

    seen = []
    real = prog.progress_bar

    def spy(total, enabled, desc, unit="it", delay=1.0, initial=0):
        seen.append((desc, enabled))
        return real(total, False, desc, unit, delay)

    monkeypatch.setattr(sys.modules["plbar.paths.scan"], "progress_bar", spy)
    plbar.find_paths(plbar.Case(n=3).problem(), grid=(30, 30), progress=True)
    assert ("refining crossings", True) in seen


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
