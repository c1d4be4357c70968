"""The compiled kernel's first compile: whether it is due, doing it ahead, doing it in another process.

numba compiles the kernel (:mod:`.kernel`) on the first simulation after an install (or an
upgrade of plbar or numba), one *specialisation* per kind of run -- accounts or a replay of the
switches only, damped or not, the split model or not -- and caches each on disk; later sessions
load it in a fraction of a second.

* :func:`compiled` tells beforehand whether a simulation will compile (:data:`COMPILE_NOTE` is what a
  command says then);
* :func:`plbar.motion.run.prepare` compiles or loads it in this process (a study does it before its workers
  fork, so that they inherit it);
* :func:`compile_elsewhere` starts the compile in another process and returns at once: a caller with
  other work first (``plbar run`` solves the paper's class and compiles the chain of
  :mod:`plbar.periodic` meanwhile) waits for it (:meth:`Elsewhere.wait`) before its first simulation, which
  then loads the kernel from the cache.  Two cores compile the two kernels side by side.
"""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
import tempfile
from pathlib import Path

from ..model import Problem
from .model import Padded, padded

__all__ = ["COMPILE_NOTE", "Elsewhere", "compile_elsewhere", "compiled", "kind"]

#: what a caller with a terminal says before the first simulation after an install (:func:`compiled`)
#: (15-30 s measured idle on 2 cores; 68 s on 2 busy ones: issue 44, finding 7)
COMPILE_NOTE = ("compiling the kernels (once after an install or an upgrade, 15-30 s idle, up to 70 s on a busy "
                "machine; cached on disk: later runs load them in under a second)")


def kind(pad: Padded, accounts: bool) -> str:
    """The kernel's specialisation for ``pad``: accounts or a replay, damped or not, split model or not."""
    from .kernel import data as D

    return "-".join(("accounts" if accounts else "replay", "damped" if pad.zeta is not None else "undamped",
                     "small" if D.large(pad) is None else "large"))


def _pad(prob: Problem | Padded) -> Padded:
    return prob if isinstance(prob, Padded) else padded(prob)


def compiled(prob: Problem | Padded, accounts: bool = True) -> bool:
    """Whether simulations of ``prob`` find their compiled kernel in the on-disk cache (else the first one
    compiles it: :data:`COMPILE_NOTE`)."""
    from .kernel import advance, jit

    return jit.is_compiled(advance, kind(_pad(prob), accounts))


class Elsewhere:
    """A compile running in another process (:func:`compile_elsewhere`); :meth:`wait` before simulating."""

    def __init__(self, proc: subprocess.Popen | None, path: Path | None, ready: bool = False):
        self.proc, self.path, self.ready = proc, path, ready

    def wait(self) -> bool:
        """Wait for it; True when the kernel is in the cache (compiled there, or before), False when the compile
        failed or could not start (a simulation here then compiles it itself)."""
        if self.proc is None:
            return self.ready
        try:
            return self.proc.wait() == 0
        finally:
            self._clean()

    def cancel(self) -> None:
        """Stop it (an interrupted caller leaves no process behind)."""
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        self._clean()

    def _clean(self) -> None:
        if self.path is not None:
            self.path.unlink(missing_ok=True)
            self.path = None

    def __enter__(self):
        return self

    def __exit__(self, exc_type, *exc):
        if exc_type is not None:
            self.cancel()
        return False


_CHILD = "import pickle, sys; from plbar.motion.run import prepare; prepare(*pickle.load(open(sys.argv[1], 'rb')))"


def compile_elsewhere(prob: Problem | Padded, accounts: bool = True) -> Elsewhere:
    """Start compiling the kernel for simulations of ``prob`` in another Python process, unless it is compiled
    already (then nothing runs).  The process gets this process's ``sys.path`` (the same plbar) and environment
    (the same numba cache)."""
    pad = _pad(prob)
    if compiled(pad, accounts):
        return Elsewhere(None, None, ready=True)
    fd, name = tempfile.mkstemp(prefix="plbar-compile-", suffix=".pkl")
    with os.fdopen(fd, "wb") as fh:
        pickle.dump((pad, accounts), fh)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    # started where this plbar lives: ``-c`` puts its working directory first on sys.path, and a checkout's plbar
    # there would shadow an installed one (another file: another cache entry, compiled for nothing)
    home = Path(__file__).resolve().parents[2]
    try:
        proc = subprocess.Popen([sys.executable, "-c", _CHILD, name], env=env, cwd=home, stdin=subprocess.DEVNULL,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except OSError:
        Path(name).unlink(missing_ok=True)
        return Elsewhere(None, None)
    return Elsewhere(proc, Path(name))
