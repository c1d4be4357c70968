"""The one progress and logging path of plbar: progress bars and messages on stderr, never glued together.

* On a terminal, :func:`progress_bar` is a tqdm bar (shown after ``delay`` s, cleared when done) and
  :func:`message` prints above the bars (``tqdm.write``), so a warning never lands on a bar's line.
* Anywhere else (a file, a pipe, a batch job) there are no carriage returns: a phase that lasts longer
  than ``delay`` s prints whole lines, ``plbar: scanning: 12000/40000 points (30 %), 10 s``, every
  :data:`EVERY` s, and one line when it ends (``done in 12.3 s``; ``interrupted after 10.0 s`` when the
  phase ends by an exception, a Ctrl-C: use the bar as a context manager).
* A phase says it is alive even while its count stands still (one long curve, one compile): a daemon thread
  (:class:`_Beat`) prints the line of every open phase that has been silent for :data:`EVERY` s, and redraws
  the bars on a terminal (their elapsed time goes on), so a long job never looks like a stuck one.

Every message of the command line (warnings, notes, errors) goes through :func:`message`.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time

from .threads import signals_to_main

__all__ = ["progress_bar", "message", "EVERY"]

EVERY = 5.0         #: seconds between two progress lines when stderr is not a terminal
BEAT = 0.5          #: seconds between two looks of the heartbeat (:class:`_Beat`) at the open phases
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

    def tick(self):
        """The heartbeat's look (:class:`_Beat`): show that the phase goes on."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


class _Beat:
    """The heartbeat: one daemon thread that calls ``tick()`` on every open phase every :data:`BEAT` s."""

    def __init__(self):
        self.open: list = []
        self.lock = threading.Lock()
        self.thread = None

    def add(self, bar) -> None:
        with self.lock:
            self.open.append(bar)
            if self.thread is None or not self.thread.is_alive():      # (none after a fork)
                self.thread = threading.Thread(target=self._loop, name="plbar-progress", daemon=True)
                self.thread.start()

    def remove(self, bar) -> None:
        with self.lock:
            if bar in self.open:
                self.open.remove(bar)

    def _loop(self) -> None:
        signals_to_main()
        while True:
            time.sleep(BEAT)
            with self.lock:
                bars = list(self.open)
            for bar in bars:
                with contextlib.suppress(Exception):     # a bar closed meanwhile: nothing to show
                    bar.tick()


_BEAT = _Beat()


def _after_fork_in_child():
    """A forked child (the studies' process pools) has none of the parent's threads, nor its open phases."""
    global _BEAT
    _BEAT = _Beat()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


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
        self.lock = threading.Lock()             # the heartbeat's line and update's never both
        _BEAT.add(self)

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
        if self.total and self.n >= self.total:
            return                                   # the last line is close()'s
        self.tick()

    def tick(self):
        """A line, if the phase has lasted ``delay`` s and the last one is :data:`EVERY` s old."""
        with self.lock:
            now = time.perf_counter()
            if now - self.t0 >= self.delay and (self.last is None or now - self.last >= EVERY):
                self.last, self.shown = now, True
                message(self._line())

    def set_description(self, desc, *_):
        self.desc = desc

    def close(self, interrupted: bool = False):
        """The phase's last line: ``done in``, or ``interrupted after`` when it ends by an exception (Ctrl-C)."""
        _BEAT.remove(self)
        with self.lock:
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
        self.t0, self.delay = time.perf_counter(), delay
        _BARS.append(self)
        _BEAT.add(self)

    def update(self, n=1):
        self._bar.update(n)

    def tick(self):
        """Redraw the bar once it shows (its elapsed time goes on while its count stands still)."""
        if time.perf_counter() - self.t0 >= self.delay:
            self._bar.refresh()

    def set_description(self, desc, *_):
        self._bar.set_description(desc)

    def close(self):
        _BEAT.remove(self)
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
