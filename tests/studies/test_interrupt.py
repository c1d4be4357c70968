"""A ``plbar run`` killed with SIGKILL never leaves a partial file under its final name; a rerun completes.

``paths.csv`` and ``summary.json`` are written to a hidden temporary beside
their final name and renamed when complete (:func:`plbar.io.atomic_path`).
The kill is timed two ways: as soon as the output folder appears (the real,
unmodified command), and deterministically in the middle of a write (the
command run through a wrapper that slows the writes down).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from slow_writes import RUNNER

from plbar.app import CSV_HEADER, TEXT_COLUMNS

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL")

PAPER = ["--signatures", "paper"]      # the paper's class only: these runs are not about the other signatures
ARGS = ["run", *PAPER, "--no-plot", "-q", "--method", "grid", "--grid", "150", "150"]


def _start(out: Path, slow: str | None = None) -> subprocess.Popen:
    env = dict(os.environ, MPLBACKEND="agg")
    env.pop("PLBAR_TEST_SLOW", None)
    if slow:
        env["PLBAR_TEST_SLOW"] = slow
    return subprocess.Popen([sys.executable, "-c", RUNNER, *ARGS, "--out", str(out)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def _wait_for(cond, proc, timeout=120.0):
    t0 = time.monotonic()
    while not cond():
        if proc.poll() is not None or time.monotonic() - t0 > timeout:
            return False
        time.sleep(0.001)
    return True


def _kill(proc):
    if proc.poll() is None:
        os.kill(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=60)


def _csv_ok(path: Path) -> int:
    """``paths.csv`` is complete: the right header, full rows (numbers but the text columns), a final newline;
    returns the rows."""
    text = path.read_text()
    assert text.endswith("\n")
    lines = text.splitlines()
    assert lines[0] == ",".join(CSV_HEADER)
    for line in lines[1:]:
        vals = line.split(",")
        assert len(vals) == len(CSV_HEADER)
        [float(x) for c, x in zip(CSV_HEADER, vals) if c not in TEXT_COLUMNS]
    return len(lines) - 1


def _invariants(out: Path):
    """Whatever the moment of the kill: final names hold complete files only."""
    if (out / "paths.csv").exists():
        _csv_ok(out / "paths.csv")
    if (out / "summary.json").exists():
        s = json.loads((out / "summary.json").read_text())
        assert (out / "paths.csv").exists() and s["n_points"] == _csv_ok(out / "paths.csv")


def _rerun_completes(out: Path):
    r = subprocess.run([sys.executable, "-c", RUNNER, *ARGS, "--out", str(out)], capture_output=True, text=True,
                       env=dict(os.environ, MPLBACKEND="agg"), timeout=300)
    assert r.returncode == 0, r.stderr
    n = _csv_ok(out / "paths.csv")
    assert n > 0 and json.loads((out / "summary.json").read_text())["n_points"] == n
    assert sorted(p.name for p in out.iterdir()) == [".plbar-owner.json", "paths.csv", "summary.json"]  # no temps


def test_kill_when_output_appears(tmp_path):
    out = tmp_path / "o"
    proc = _start(out)
    try:
        assert _wait_for(out.exists, proc), proc.communicate()
    finally:
        _kill(proc)
    _invariants(out)
    _rerun_completes(out)


def test_kill_in_the_middle_of_writing_paths_csv(tmp_path):
    out = tmp_path / "o"
    proc = _start(out, slow="paths.csv")

    def writing():
        return any(p.stat().st_size > 0 for p in out.glob(".paths.*.part.csv")) if out.exists() else False
    try:
        assert _wait_for(writing, proc), proc.communicate()
        time.sleep(0.1)                               # well inside the write
    finally:
        _kill(proc)
    assert not (out / "paths.csv").exists() and not (out / "summary.json").exists()
    partial = list(out.glob(".paths.*.part.csv"))
    assert partial and partial[0].read_text().count("\n") >= 1    # the half-written data is only in a temporary
    _rerun_completes(out)


@pytest.mark.slow
def test_kill_in_the_middle_of_writing_summary(tmp_path):
    out = tmp_path / "o"
    _rerun_completes(out)                             # an earlier complete run of the same case
    before = (out / "paths.csv").read_text()
    proc = _start(out, slow="summary.json")
    try:
        assert _wait_for(lambda: any(out.glob(".summary.*.part.json")), proc), proc.communicate()
        time.sleep(0.1)
    finally:
        _kill(proc)
    _invariants(out)
    assert (out / "paths.csv").read_text() == before   # the same case: identical rows
    _rerun_completes(out)
