"""Ctrl-C honoured at once: a command interrupted in any phase exits 130 within 2 s, leaves no partial file, says
what it kept, and a rerun resumes.

Each test waits for the phase to be under way (a line on stderr, or a file), then sends SIGINT: no race on timing.
The child restores SIGINT's default handler (a test runner started in the background ignores SIGINT, and a child
would inherit that: Python then installs no KeyboardInterrupt).
"""

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from slow_writes import RUNNER

LIMIT = 2.0   #: seconds from SIGINT to exit


class Child:
    """``python -m plbar ARGS``, its stderr read as it comes."""

    def __init__(self, args, env=None):
        self.p = subprocess.Popen([sys.executable, "-m", "plbar", *args], stdout=subprocess.DEVNULL,
                                  stderr=subprocess.PIPE, text=True, env=env, start_new_session=True,
                                  preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        self.err = ""
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for ch in iter(lambda: self.p.stderr.read(1), ""):
            self.err += ch

    def wait_for(self, ready, timeout=300.0):
        t0 = time.time()
        while not ready() and self.p.poll() is None and time.time() - t0 < timeout:
            time.sleep(0.01)
        assert self.p.poll() is None, f"ended before the phase: {self.err[-500:]}"
        assert ready(), f"phase not reached in {timeout} s: {self.err[-500:]}"

    def interrupt(self) -> float:
        """SIGINT; the seconds to the exit."""
        t0 = time.time()
        self.p.send_signal(signal.SIGINT)
        try:
            self.p.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(self.p.pid, signal.SIGKILL)               # its workers too: nothing left running
            pytest.fail(f"not ended 60 s after Ctrl-C: {self.err[-500:]}")
        return time.time() - t0


def _finished(folder: Path) -> list[Path]:
    """Finished task files (not a temporary ``.KEY.*.part.json``)."""
    return list((folder / "tasks").glob("[!.]*.json"))


def _partial(folder: Path) -> list[Path]:
    return [p for p in folder.rglob("*") if ".part" in p.name] if folder.exists() else []


#: a single-case survey of 32 forcing periods (4 tasks of 8), a few seconds of simulation on 2 cores
SURVEY = ["survey", "--T", "10", "12", "--num", "32", "--periods", "3000", "--no-plot", "--no-paths"]


def test_a_survey_interrupted_after_a_task_keeps_it_and_resumes(tmp_path):
    """The default chunking keeps what finished (before: the default survey was 2 tasks; at 90 % a Ctrl-C kept
    nothing, though the command said 'finished study tasks are kept')."""
    out = tmp_path / "sv"
    c = Child([*SURVEY, "--out", str(out)])
    c.wait_for(lambda: _finished(out))
    dt = c.interrupt()
    assert c.p.returncode == 130 and dt <= LIMIT, (c.p.returncode, dt, c.err[-300:])
    assert "kept" in c.err and "rerun" in c.err
    kept = {p.name: p.stat().st_mtime_ns for p in _finished(out)}
    assert len(json.loads((out / "study.json").read_text())["tasks"]) == 8         # 4 forcing periods each
    assert 1 <= len(kept) < 8 and not _partial(out)
    r = subprocess.run([sys.executable, "-m", "plbar", *SURVEY, "--out", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert all((out / "tasks" / n).stat().st_mtime_ns == t for n, t in kept.items())     # resumed, not redone
    assert sum(1 for line in (out / "survey.csv").read_text().splitlines()[1:] if line) == 32


def test_a_survey_interrupted_while_simulating_before_any_task_says_nothing_was_kept(tmp_path):
    out = tmp_path / "sv"
    c = Child([*SURVEY[:-4], "--periods", "400000", "--no-plot", "--no-paths", "--out", str(out)])
    c.wait_for(lambda: "periods (" in c.err and (out / "tasks").is_dir())        # the progress bar: simulating
    dt = c.interrupt()
    assert c.p.returncode == 130 and dt <= LIMIT, (c.p.returncode, dt, c.err[-300:])
    assert "no results written" in c.err and "kept" not in c.err
    assert not out.exists()


REFINE = ["-N", "4", "14", "--no-plot"]   #: two meshes of the default chain family


def _levels(folder: Path) -> list[Path]:
    return list((folder / "levels").glob("*/N*.json")) if folder.exists() else []


def test_refine_interrupted_while_following_exits_at_once_and_resumes(tmp_path):
    """``plbar refine`` (the default chain family, 2 meshes): Ctrl-C after the first mesh is carried, while the
    next is followed; the finished meshes are kept and the rerun continues from them."""
    out = tmp_path / "rf"
    c = Child(["refine", *REFINE, "--out", str(out)])
    c.wait_for(lambda: len(_levels(out)) >= 1)
    dt = c.interrupt()
    assert c.p.returncode == 130 and dt <= LIMIT, (c.p.returncode, dt, c.err[-300:])
    assert "kept" in c.err and not _partial(out)
    kept = {p: p.stat().st_mtime_ns for p in _levels(out)}
    r = subprocess.run([sys.executable, "-m", "plbar", "refine", *REFINE, "--out", str(out)], capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    assert all(p.stat().st_mtime_ns == t for p, t in kept.items())                # resumed, not redone
    assert (out / "refine.csv").exists()


RUN = ["run", "--no-plot"]   #: the default case, every signature


@pytest.mark.parametrize("args", [SURVEY, RUN], ids=["survey", "run"])
def test_interrupted_while_compiling_exits_at_once(tmp_path, args):
    """An empty kernel cache (a first run after an install): Ctrl-C while the kernels compile (``plbar run``:
    beside the paper's solve); nothing written, no compile left running."""
    env = dict(os.environ, PLBAR_CACHE_DIR=str(tmp_path / "cache"))
    out = tmp_path / "out"
    c = Child([*args, "--out", str(out)], env=env)
    c.wait_for(lambda: "compiling" in c.err)
    time.sleep(0.5)                                                                # inside numba, not before it
    dt = c.interrupt()
    assert c.p.returncode == 130 and dt <= LIMIT, (c.p.returncode, dt, c.err[-300:])
    assert "no results written" in c.err
    assert not out.exists()


@pytest.mark.parametrize("args, name", [([*RUN, "--signatures", "paper"], "paths.csv"),
                                        pytest.param(["refine", *REFINE], "refine.csv", marks=pytest.mark.slow),
                                        (SURVEY, "survey.csv")], ids=["run", "refine", "survey"])
def test_interrupted_while_writing_leaves_no_partial_file(tmp_path, args, name):
    """Ctrl-C in the middle of writing the command's table: exit 130 within 2 s, the temporary removed, no table
    under its final name; the rerun writes the whole table."""
    out = tmp_path / "out"
    args = [*args, "--out", str(out)]
    stem, suffix = name.split(".")
    p = subprocess.Popen([sys.executable, "-c", RUNNER, *args], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, start_new_session=True,
                         env=dict(os.environ, PLBAR_TEST_SLOW=name),
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    t0 = time.time()
    while not (out.exists() and any(q.stat().st_size > 0 for q in out.glob(f".{stem}.*.part.{suffix}"))):
        assert p.poll() is None and time.time() - t0 < 300, p.communicate()[1][-500:]
        time.sleep(0.005)
    t1 = time.time()
    p.send_signal(signal.SIGINT)
    try:
        err = p.communicate(timeout=60)[1]
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        pytest.fail("not ended 60 s after Ctrl-C")
    dt = time.time() - t1
    assert p.returncode == 130 and dt <= LIMIT, (p.returncode, dt, err[-300:])
    assert not _partial(out) and not (out / name).exists()
    r = subprocess.run([sys.executable, "-m", "plbar", *args], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert len((out / name).read_text().splitlines()) > 2 and not _partial(out)
