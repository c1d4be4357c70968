"""Issue 45: ``plbar run`` of a truncated FE model with every signature ends, says what it does, and stops on Ctrl-C.

The truncated model's chatter (``tests/motion/test_motion.py``, ``test_a_truncated_chatter_of_short_flights_...``)
made the seeding simulation run for hours without a line on stderr, and a Ctrl-C waited for the compiled kernel.
"""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import plbar

#: the smallest case of the issue's kind: FE, truncated, every signature (the default)
CASE = ["--model", "fe", "-N", "20", "--modes", "5"]


@pytest.mark.filterwarnings("ignore::plbar.errors.TruncationWarning")
@pytest.mark.slow                    # long: with the slow tests (the default suite under 10 minutes)
def test_a_truncated_fe_case_with_every_signature_is_solved():
    """As cheap as the full model's search, and its paper's class the same as without the search."""
    case = plbar.Case(model="fe", n=20, modes=5)
    t0 = time.perf_counter()
    res = plbar.solve(case)
    assert time.perf_counter() - t0 < 120                       # it ran for hours
    assert res.signatures_time < 60
    paper = plbar.solve(plbar.Case(model="fe", n=20, modes=5, signatures="paper"))
    # the scan's branches first, unchanged; then any of the paper's class that the search finds off them (the
    # curves through the scan's branches are followed: points of class 1P past the scan's ends or its domain)
    assert len(res.paper) >= len(paper.branches)
    for a, b in zip(res.paper, paper.branches):
        np.testing.assert_array_equal(a.T, b.T)
    for extra in res.paper[len(paper.branches):]:
        assert not any(b.T.min() <= t <= b.T.max() for t in extra.T for b in paper.branches)


def _lines(path):
    return path.read_text().splitlines() if path.exists() else []


def test_ctrl_c_during_the_signature_search_exits_130_within_2_s(tmp_path):
    """SIGINT once stderr (a file) shows the signature search under way, past its compiles (SIGINT's default
    disposition in the child, as a terminal gives it): exit 130 within 2 s, nothing left in the folder."""
    out, err = tmp_path / "out", tmp_path / "stderr.txt"
    before = sorted(p.name for p in tmp_path.iterdir())
    with open(err, "w") as f:
        proc = subprocess.Popen([sys.executable, "-m", "plbar", "run", *CASE, "--no-plot", "--out", str(out)],
                                stdout=subprocess.DEVNULL, stderr=f,
                                env=dict(os.environ, MPLBACKEND="agg", PLBAR_PROGRESS_DELAY="0"),
                                preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    t0 = time.monotonic()
    searching = ("plbar: signatures: simulating", "plbar: signatures: polishing", "plbar: signatures: seeding",
                 "plbar: signatures: following")
    while proc.poll() is None and time.monotonic() - t0 < 300:
        if any(line.startswith(searching) for line in _lines(err)):
            break
        time.sleep(0.02)
    assert proc.poll() is None, _lines(err)
    t1 = time.monotonic()
    proc.send_signal(signal.SIGINT)
    proc.wait(timeout=60)
    took = time.monotonic() - t1
    lines = _lines(err)
    assert proc.returncode == 130, lines
    assert took < 2.0, (took, lines)
    assert lines[-1] == "plbar: interrupted (no results written)"
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(before + ["stderr.txt"])
