"""``plbar sweep-loads``: its positions table (.npz, CSV behind a switch), a warning above a size, bad positions
refused before the solve, Ctrl-C.

From the newcomer reports (the first hour and issue 22). Every test here failed on the code before the fix it covers.
"""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import plbar

from _helpers import FAST, _refused, _run


def test_sweep_positions_are_npz_and_csv_behind_a_switch(tmp_path, capsys):
    out = tmp_path / "s"
    assert _run(capsys, ["sweep-loads", "-N", "4", "--per-element", "3", "--out", out, *FAST])[0] == 0
    z = np.load(out / "xi_positions.npz")
    assert z["xi"].shape == (z["T"].size, 12) and not (out / "xi_positions.csv").exists()
    s = json.loads((out / "summary.json").read_text())
    assert s["plbar_version"] == plbar.__version__
    assert _run(capsys, ["sweep-loads", "-N", "4", "--per-element", "3", "--positions-csv", "--out", out,
                         *FAST])[0] == 0
    rows = (out / "xi_positions.csv").read_text().splitlines()
    assert rows[0] == "branch,point,T,s,xi,dPL" and len(rows) - 1 == z["xi"].size


def test_sweep_warns_above_a_size(tmp_path, capsys, monkeypatch):
    import plbar.studies.loads.write as loads

    monkeypatch.setattr(loads, "WARN_BYTES", 1000.0)
    code, _, err = _run(capsys, ["sweep-loads", "-N", "4", "--out", tmp_path / "s", *FAST])
    assert code == 0 and "plbar: warning: the positions table holds" in err and "--per-element" in err


@pytest.mark.parametrize("argv, word", [(["--model", "fe", "-N", "10", "--per-element", "0"], "per_element = 0"),
                                        (["--positions", "7.5"], "outside the bar (0, 5]")])
def test_sweep_bad_positions_refused_before_the_solve(tmp_path, capsys, monkeypatch, argv, word):
    import plbar.app as app

    monkeypatch.setattr(app, "solve", lambda *a, **k: pytest.fail("solved before checking the positions"))
    _refused(capsys, ["sweep-loads", *argv, "--out", tmp_path / "s", "-q"], word)
    assert not (tmp_path / "s").exists()


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
