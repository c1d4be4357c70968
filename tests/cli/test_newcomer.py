"""A newcomer's first hour: each item of that issue, through ``main(argv)`` or a subprocess.

Every test here failed on the code before the fix it covers.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import plbar
from plbar.cli import main

PAPER = ["--signatures", "paper"]      # the paper's class only: these runs are not about the other signatures

CASES = Path(__file__).resolve().parents[2] / "examples" / "cases"


def _run(capsys, argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


# 1. a rerun never leaves results of another case beside the new ones -----------------------------------------

def test_overwrite_clears_the_previous_export_and_render(tmp_path, capsys):
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


def test_export_clears_the_other_format(tmp_path, capsys):
    pytest.importorskip("pyvista")
    out = tmp_path / "r"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--grid", "40", "40", "--out", out, "-q", "--no-plot"])[0] == 0
    (out / "vtk").mkdir()
    for name in ("response.xdmf", "response.h5", "response_0099.vtu"):
        (out / "vtk" / name).write_text("stale")
    assert _run(capsys, ["export", "--from", out, "--steps", "8", "-q"])[0] == 0
    names = sorted(p.name for p in (out / "vtk").iterdir())
    assert "response.pvd" in names and "response.xdmf" not in names and "response.h5" not in names
    assert "response_0099.vtu" not in names and len([n for n in names if n.endswith(".vtu")]) == 8


# 2. options given with a case file are refused, not ignored ---------------------------------------------------

def test_option_conflicting_with_case_file_is_exit_2(tmp_path, capsys):
    code, out, err = _run(capsys, ["run", CASES / "fe_p2_consistent.toml", "-N", "6", "--out", tmp_path / "m"])
    assert code == 2 and "-N/--elements conflicts with the case file" in err and err.count("\n") == 1
    assert not (tmp_path / "m" / "paths.csv").exists()


# 3. fine FE output fits on one screen ------------------------------------------------------------------------

@pytest.mark.slow
def test_many_branches_print_a_short_summary(tmp_path, capsys):
    argv = ["run", *PAPER, "--model", "fe", "-N", "8", "--element", "P2", "--grid", "60", "60", "--out", tmp_path / "f",
            "--no-plot"]
    code, out, _ = _run(capsys, argv)
    n = json.loads((tmp_path / "f" / "summary.json").read_text())["n_branches"]
    assert code == 0 and n > 10
    # 16 lines: the case, its periods, its units, the window searched, the count, the stability, five branches, the
    # rest in one line, the note on other signatures, the time, the files
    assert out.count("\n") <= 16 and "--verbose lists all" in out and f"{n - 5} more branches" in out
    code, out, _ = _run(capsys, argv + ["--verbose", "--overwrite"])
    assert out.count("  branch ") == n


# 4. long phases show progress (and are quiet under --quiet / --json) ------------------------------------------

def test_scan_shows_progress(monkeypatch):
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


# 5. an unusable output folder is found before the solve --------------------------------------------------------

@pytest.mark.parametrize("cmd", [["run", *PAPER, "--model", "fe", "-N", "8"], ["sweep-loads"], ["figures"],
                                 ["export", "--case", str(CASES / "chain_N3_node1.toml")]])
def test_bad_destination_exit_2_before_work(tmp_path, capsys, cmd):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    dest = ["--out", blocker / "sub"]
    t0 = time.perf_counter()
    code, out, err = _run(capsys, cmd + dest + (["--from", tmp_path / "run"] if cmd[0] == "export" else []))
    assert code == 2 and err.startswith("plbar: error:") and err.count("\n") == 1, err
    assert "is a file" in err and time.perf_counter() - t0 < 5


def test_unwritable_destination_exit_2(tmp_path, capsys):
    code, _, err = _run(capsys, ["run", *PAPER, "--model", "fe", "-N", "8", "--out", "/proc/plbar_x"])
    assert code == 2 and "cannot be written" in err and err.count("\n") == 1


# 6. a missing optional package names the extra and creates nothing --------------------------------------------

def test_missing_pyvista_names_the_extra(tmp_path, capsys, monkeypatch):
    out = tmp_path / "r"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--grid", "40", "40", "--out", out, "-q", "--no-plot"])[0] == 0
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "pyvista" else real(name, *a))
    code, _, err = _run(capsys, ["export", "--from", out])
    assert code == 2 and 'pip install "plbar[vtk]"' in err and not (out / "vtk").exists()
    code, _, err = _run(capsys, ["render", "--from", out])
    assert code == 2 and 'pip install "plbar[vtk]"' in err and not (out / "render").exists()


def test_missing_matplotlib_is_said_once(tmp_path, capsys, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "matplotlib" else real(name, *a))
    code, _, err = _run(capsys, ["run", *PAPER, "-N", "3", "--grid", "30", "30", "--out", tmp_path / "o"])
    assert code == 0 and err.count('pip install "plbar[plot]"') == 1
    code, _, err = _run(capsys, ["figures", "--out", tmp_path / "f"])
    assert code == 2 and 'pip install "plbar[plot]"' in err and not (tmp_path / "f").exists()


# 7. Ctrl-C ends at once with exit 130 --------------------------------------------------------------------------

def test_ctrl_c_in_sweep_loads_exits_130_at_once(tmp_path):
    """Robust: SIGINT is sent once the command has started (its output folder exists), not after a sleep; the
    child gets SIGINT's default disposition back, as a terminal gives it (a test run started in the background
    by a non-interactive shell ignores SIGINT, and Python then installs no KeyboardInterrupt handler)."""
    out = tmp_path / "s"
    proc = subprocess.Popen([sys.executable, "-m", "plbar", "sweep-loads", "--model", "fe", "-N", "16",
                             "--element", "P2", "--out", str(out), "-q"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=dict(os.environ, MPLBACKEND="agg"),
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    t0 = time.monotonic()
    while not out.exists() and proc.poll() is None and time.monotonic() - t0 < 300:
        time.sleep(0.02)
    assert proc.poll() is None, proc.communicate()
    time.sleep(0.5)                                          # well inside the solve (about 90 s)
    t1 = time.monotonic()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130 and time.monotonic() - t1 < 60
    assert err.decode().strip().splitlines()[-1] == "plbar: interrupted (no results written)"
    assert not out.exists()


# 9. refinement rates: never null without a reason, never nan in a file ------------------------------------------

def test_refine_rates_say_why_and_write_no_nan(tmp_path, capsys):
    out = tmp_path / "r"
    code, text, _ = _run(capsys, ["refine", "-N", "3", "4", "--grid", "40", "40", "--executor", "serial",
                                  "--out", out, "--json"])
    assert code == 0
    rates = json.loads(text)["rates"]
    for fams in rates.values():
        for qs in fams.values():
            for q, r in qs.items():
                if q == "xi_decay":                      # a decay law, or why none
                    assert r["model"] or r["why"], r
                else:
                    assert r["rate"] is not None or r["why"], (q, r)
    for f in ("refine.csv", "refine_rates.json"):
        assert "nan" not in (out / f).read_text().lower()


# 10. one overwrite policy for every command ---------------------------------------------------------------------

def test_mesh_keeps_existing_files_unless_overwrite(tmp_path, capsys):
    """README: 'plbar mesh keeps existing files unless --overwrite' (it used to exit 2): missing ones are written."""
    assert _run(capsys, ["mesh", "--out", tmp_path, "-q"])[0] == 0
    f, g = sorted(tmp_path.glob("*.msh"))[:2]
    f.write_text("edited")
    g.unlink()
    code, out, err = _run(capsys, ["mesh", "--out", tmp_path])
    assert code == 0 and err == "" and f.read_text() == "edited" and g.is_file()
    assert "kept" in out and "--overwrite replaces them" in out and str(g) in out
    assert _run(capsys, ["mesh", "--out", tmp_path, "--overwrite", "-q"])[0] == 0 and f.read_text() != "edited"


# 11. one vocabulary -----------------------------------------------------------------------------------------------

@pytest.mark.parametrize("cmd", ["run", "mesh", "export", "render", "sweep-loads", "refine", "figures"])
def test_every_command_has_quiet_json_out(capsys, cmd):
    assert main([cmd, "--help"]) == 0
    text = capsys.readouterr().out
    for opt in ("--quiet", "--json", "--out"):
        assert opt in text, (cmd, opt)


def test_same_names_for_the_same_things(tmp_path, capsys):
    code, text, _ = _run(capsys, ["sweep-loads", "-N", "4", "--load-at", "1.5", "--grid", "40", "40",
                                  "--positions", "1.0", "2.0", "--out", tmp_path / "s", "--json", "--no-plot"])
    assert code == 0 and json.loads(text)["summary"]["positions"] == 2
    assert _run(capsys, ["refine", "-N", "3", "--grid", "30", "30", "--executor", "serial", "--out",
                         tmp_path / "r", "-q"])[0] == 0
    assert _run(capsys, ["run", *PAPER, "-N", "3", "--grid", "30", "30", "--out", tmp_path / "o", "-q",
                         "--no-plot"])[0] == 0
    if __import__("importlib").util.find_spec("pyvista"):
        code, text, _ = _run(capsys, ["export", "--from", tmp_path / "o", "--out", tmp_path / "v", "--steps", "8",
                                      "--json"])
        assert code == 0 and (tmp_path / "v" / "response.pvd").is_file()


# 12. smaller ------------------------------------------------------------------------------------------------------

def test_default_fe_load_is_a_fixed_position():
    for n in (4, 8, 16):
        case = plbar.Case(model="fe", n=n)
        assert case.load_points == ((0.5, 1.0),) and not case.load_nodes


def test_summary_length_of_the_chain_is_N(tmp_path, capsys):
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--grid", "30", "30", "--out", tmp_path / "o", "-q",
                         "--no-plot"])[0] == 0
    assert json.loads((tmp_path / "o" / "summary.json").read_text())["case"]["length"] == 4.0


def test_output_folders_are_ignored_by_git():
    text = (Path(__file__).resolve().parents[2] / ".gitignore").read_text().split()
    for pat in ("plbar-out/", "plbar-*/", "results/"):
        assert pat in text


def test_paths_csv_has_amplitude_and_frequency(tmp_path, capsys):
    assert _run(capsys, ["run", *PAPER, "-N", "5", "--grid", "60", "60", "--out", tmp_path / "o", "-q",
                         "--no-plot"])[0] == 0
    cols = plbar.app.read_paths(tmp_path / "o" / "paths.csv")
    assert np.allclose(cols["omega"], 2 * np.pi / cols["T"], rtol=1e-15)
    assert np.all(cols["max_abs_xc"] > 0)


# 8. short reprs ---------------------------------------------------------------------------------------------------

def test_result_repr_is_short():
    res = plbar.solve(plbar.Case(signatures="paper", model="fe", n=8, grid=(60, 60)))
    text = repr(res)
    assert len(text) < 3000 and text.startswith("Result(") and f"{len(res.branches)} branches" in text
    assert len(repr(res.case)) < 500 and len(repr(res.paths.prob)) < 2000
