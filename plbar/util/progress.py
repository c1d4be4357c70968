"""The one progress and logging path of plbar: progress bars and messages on stderr, never glued together.

* On a terminal, :func:`progress_bar` is a tqdm bar (shown after ``delay`` s, cleared when done) and
  :func:`message` prints above the bars (``tqdm.write``), so a warning never lands on a bar's line.
* Anywhere else (a file, a pipe, a batch job) there are no carriage returns: a phase that lasts longer
  than ``delay`` s prints whole lines, ``plbar: scanning: 12000/40000 points (30 %), 10 s``, at most
  every :data:`EVERY` s, and one line when it ends (``done in 12.3 s``; ``interrupted after 10.0 s`` when the
  phase ends by an exception, a Ctrl-C: use the bar as a context manager).

Every message of the command line (warnings, notes, errors) goes through :func:`message`.
"""

from __future__ import annotations

import contextlib
import os
import sys
import time

__all__ = ["progress_bar", "message", "EVERY"]

EVERY = 10.0        #: seconds between two progress lines when stderr is not a terminal
DELAY_ENV = "PLBAR_PROGRESS_DELAY"   #: overrides every phase's delay (seconds; 0 shows every phase)
_BARS: list = []    #: the tqdm bars open on a terminal (messages go above them)


class _Null:
    """A progress bar that shows nothing (``enabled=False``)."""

    def update(self, *_):
        pass

    def close(self):
        pass

    def set_description(self, *_):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def _tty() -> bool:
    try:
        return bool(sys.stderr.isatty())
    except (AttributeError, ValueError):
        return False


def message(text: str) -> None:
    """Print ``text`` as whole lines on stderr (above any progress bar on a terminal)."""
    if _BARS:
        from tqdm.auto import tqdm

        tqdm.write(text, file=sys.stderr)
    else:
        print(text, file=sys.stderr, flush=True)


class _Lines(_Null):
    """Progress as whole lines: after ``delay`` s, then every :data:`EVERY` s, and a last line at the end."""

    def __init__(self, total, desc: str, unit: str, delay: float, initial: int = 0):
        self.total, self.desc, self.unit, self.delay = total, desc, unit, delay
        self.n, self.t0, self.last, self.shown = initial, time.perf_counter(), None, False

    def _line(self, end: bool = False, interrupted: bool = False) -> str:
        dt = time.perf_counter() - self.t0
        if interrupted:
            end = False
        units = self.unit if (self.total or self.n) == 1 else f"{self.unit}es" if self.unit.endswith(("ch", "sh")) \
            else f"{self.unit}s"
        if self.total == 1 and end:                  # a phase without parts: just its time
            return f"plbar: {self.desc}: done in {dt:.1f} s"
        if self.total:
            done = f"{self.n}/{self.total} {units} ({100 * self.n / self.total:.0f} %)"
        else:
            done = f"{self.n} {units}"
        last = f"interrupted after {dt:.1f} s" if interrupted else f"done in {dt:.1f} s" if end else f"{dt:.0f} s"
        return f"plbar: {self.desc}: {done}, {last}"

    def update(self, n=1):
        self.n += n
        now = time.perf_counter()
        if self.total and self.n >= self.total:
            return                                   # the last line is close()'s
        if now - self.t0 >= self.delay and (self.last is None or now - self.last >= EVERY):
            self.last, self.shown = now, True
            message(self._line())

    def set_description(self, desc, *_):
        self.desc = desc

    def close(self, interrupted: bool = False):
        """The phase's last line: ``done in``, or ``interrupted after`` when it ends by an exception (Ctrl-C)."""
        if self.shown or time.perf_counter() - self.t0 >= self.delay:
            message(self._line(end=True, interrupted=interrupted))
        self.shown = False
        self.delay = float("inf")

    def __exit__(self, kind, *exc):
        self.close(interrupted=kind is not None)
        return False


class _Bar:
    """A tqdm bar on a terminal, registered so that :func:`message` writes above it."""

    def __init__(self, total, desc: str, unit: str, delay: float, initial: int = 0):
        from tqdm.auto import tqdm

        self._bar = tqdm(total=total, desc=desc, unit=unit, leave=False, delay=delay, initial=initial,
                         file=sys.stderr)
        _BARS.append(self)

    def update(self, n=1):
        self._bar.update(n)

    def set_description(self, desc, *_):
        self._bar.set_description(desc)

    def close(self):
        if self in _BARS:
            _BARS.remove(self)
            self._bar.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def progress_bar(total, enabled: bool, desc: str, unit: str = "it", delay: float = 1.0, initial: int = 0):
    """Progress of a phase on stderr: a tqdm bar on a terminal, whole lines elsewhere, nothing if not ``enabled``.

    Parameters
    ----------
    total : int or None
        Units of work (None: unknown).
    enabled : bool
        False gives a no-op with the same methods (``update``, ``set_description``, ``close``; a context manager).
    desc, unit : str
        What is done, and the name of one unit.
    delay : float
        Show nothing for a phase shorter than this (s); the environment variable ``PLBAR_PROGRESS_DELAY``
        overrides it.
    initial : int
        Units already done (a resumed study).
    """
    if not enabled:
        return _Null()
    with contextlib.suppress(ValueError):
        delay = float(os.environ.get(DELAY_ENV, delay))
    if _tty():
        return _Bar(total, desc, unit, delay, initial)
    return _Lines(total, desc, unit, delay, initial)
