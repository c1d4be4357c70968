"""The seeds of every signature but the paper's class in a run: the search window and the seeding simulation.

:class:`Search` is what :func:`plbar.solve` begins beside the paper's class (:func:`plbar.find_paths`), for
``Case.signatures`` ``"default"`` or ``"all"``: the periodic motions of a simulation from rest across the window
(``"default"``: 81 forcing periods, 600 periods each, the last 60 recorded; ``"all"``: 161, 1,000 and 100, as
``plbar survey``, and orbits up to ``m = 8``) are polished
(:func:`plbar.periodic.from_motion`) and followed with the seeds of the structure and of the paper's branches
(:func:`plbar.periodic.find_branches`).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor, wait
from contextlib import ExitStack

import numpy as np

from ..periodic import NotConverged, from_motion
from ..periodic import compiled as chain_compiled
from ..motion import COMPILE_NOTE, compile_elsewhere, compiled, halt_flag, padded, run, steady
from ..model import Problem
from ..paths import Domain
from ..util.progress import message, progress_bar
from ..util.threads import signals_to_main

__all__ = ["Search", "search_window", "SEED_PERIODS", "M_MAX"]

#: forcing periods, periods simulated, periods recorded of the seeding simulation, per kind
SEED_PERIODS = {"default": (81, 600, 60), "all": (161, 1000, 100)}
#: the longest orbit (forcing periods) followed, per kind
M_MAX = {"paper": 1, "default": 4, "all": 8}


def search_window(prob: Problem, domain: Domain) -> tuple[float, float]:
    """Forcing periods searched: from ``T0^I / 2`` (``T0^II / 4`` for a single mass held at the stop, whose
    ``T0^I = 0``) to the top of the paper's search domain ``max T1 + max T2``."""
    T0I, T0II = prob.system.T0
    return (0.5 * T0I if T0I else 0.25 * T0II), float(domain.T1[1] + domain.T2[1])


def _seeding(prob: Problem, window, kinds: str, progress=None, pad=None, halt=None):
    """The seeding simulation: ``SEED_PERIODS[kinds]`` forcing periods across ``window`` from rest, the switches
    only (``progress(n)`` after each block of periods; ``halt``: its kernel's halt flag, :func:`plbar.motion.run`)."""
    num, periods, record = SEED_PERIODS[kinds]
    T = np.linspace(window[0], window[1], num)
    return run(padded(prob) if pad is None else pad, T, 0.0, periods, record, progress=progress, accounts=False,
               halt=halt)


def _seeds(prob: Problem, r, progress: bool = False) -> list:
    """Orbits polished (:func:`plbar.periodic.from_motion`) from the periodic motions of the seeding simulation
    ``r``."""
    s = steady(r, tol=1e-4)
    periodic = np.flatnonzero(s.kind == 0)
    out = []
    with progress_bar(periodic.size, progress, "signatures: polishing the periodic motions", "motion") as bar:
        for b in periodic:
            out += _seed(prob, r, int(b), int(s.m[b]))
            bar.update(1)
    return out


def _seed(prob: Problem, r, b: int, m: int) -> list:
    """The orbit of ``m`` periods polished from motion ``b`` of ``r``, its recorded periods (none where Newton
    fails)."""
    try:
        return [from_motion(prob, r, b, m)]
    except (NotConverged, ValueError, np.linalg.LinAlgError):
        return []



class Search:
    """The seeds of the other signatures of a run, begun before the paper's class is scanned (:func:`plbar.solve`).

    What needs the case only starts at once, beside the scan: after an install the compile of the
    simulator in another process (:func:`plbar.motion.compile_elsewhere`), else the seeding simulation in a
    thread (the compiled kernel releases the GIL).  :meth:`seeds` waits for the simulation once the paper's
    class is solved, and polishes its periodic motions.
    :meth:`cancel` (or leaving the ``with`` block, a Ctrl-C) stops what still runs: the simulation's kernel at its
    next round (its halt flag, :func:`plbar.motion.halt_flag`), the compile elsewhere at once.
    """

    def __init__(self, prob: Problem, domain: Domain, kinds: str, progress: bool = False):
        self.prob, self.kinds, self.progress = prob, kinds, progress
        self.window = search_window(prob, domain)
        self.pad = padded(prob)
        self.done, self._halt = 0, halt_flag()
        self._stack, self._bar = ExitStack(), None
        self._other = self._pool = self._future = None
        if compiled(self.pad, accounts=False):
            self._pool = ThreadPoolExecutor(1, thread_name_prefix="plbar-seeding", initializer=signals_to_main)
            self._future = self._pool.submit(_seeding, prob, self.window, kinds, self._count, self.pad, self._halt)
        else:
            self._other = compile_elsewhere(self.pad, accounts=False)
        if progress and not (self._other is None and chain_compiled(prob)):
            message(f"plbar: {COMPILE_NOTE}")

    def _count(self, n: int) -> None:
        self.done += n

    def _simulation(self):
        num, periods, _ = SEED_PERIODS[self.kinds]
        desc = f"signatures: simulating {num} forcing periods from rest"
        if self._future is None:                       # compiled elsewhere meanwhile: simulate here
            self._other.wait()
            with progress_bar(periods, self.progress, desc, "period") as bar:
                return _seeding(self.prob, self.window, self.kinds, bar.update, self.pad, self._halt)
        with progress_bar(periods, self.progress, desc, "period", initial=self.done) as bar:
            shown = self.done
            while not self._future.done():
                wait([self._future], timeout=0.2)
                bar.update(self.done - shown)
                shown = self.done
            return self._future.result()

    def seeds(self) -> list:
        """The orbits polished from the periodic motions of the seeding simulation (:func:`_seeds`)."""
        try:
            return _seeds(self.prob, self._simulation(), self.progress)
        finally:
            self.cancel()

    def curve(self) -> None:
        """Called once per curve followed: the progress bar of the curves (shown with ``progress``)."""
        if self._bar is None:
            self._bar = self._stack.enter_context(progress_bar(None, self.progress, "following curves", "curve"))
        self._bar.update(1)

    def cancel(self) -> None:
        """Stop the simulation (its kernel at its next round) or the compile elsewhere; wait for them."""
        self._halt[0] = 1
        if self._other is not None:
            self._other.cancel()
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.cancel()
        self._stack.close()
        return False
