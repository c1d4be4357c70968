"""What the command-line tests share: ``main(argv)`` with its output, a refused command, a child ``python -m plbar``,
the paper's signatures and a fast search (importable: the tests' folder is on sys.path, as for tests/shared_points.py).
"""

import signal
import subprocess
import sys
from pathlib import Path

from plbar.cli import main

PAPER = ["--signatures", "paper"]      # the paper's class only: these runs are not about the other signatures

ROOT = Path(__file__).resolve().parents[2]
MESH = ROOT / "meshes" / "bar_uniform_8.msh"
CASES = ROOT / "examples" / "cases"
FAST = ["--grid", "30", "30", "-q", "--no-plot"]


def _run(capsys, argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _refused(capsys, argv, *words):
    """Exit 2 with one line on stderr naming ``words``; returns the line."""
    code, _, err = _run(capsys, argv)
    assert code == 2 and err.count("\n") == 1 and err.startswith("plbar: error:"), err
    for w in words:
        assert w in err, (w, err)
    return err


def _plbar(args, **kw):
    """``python -m plbar ARGS`` with Ctrl-C's default (a test runner started in the background ignores SIGINT, and a
    child would inherit that: Python then installs no KeyboardInterrupt)."""
    return subprocess.Popen([sys.executable, "-m", "plbar", *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL), **kw)
