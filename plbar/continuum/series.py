"""The last periods of a continuum run as a time series (:class:`ContinuumSeries`), for export and render.

It has the interface of :class:`plbar.motion.Series` that :func:`plbar.io.motion_data` samples: the fields
``u, v`` on the grid ``x_j = j L / n`` (``u`` exact: it integrates ``u_x`` from the clamp), the contact's state and
reaction, the energies, the switches.  Everything is evaluated from the stored delay line (:mod:`.fields`), so a
sample is the run's own solution, not an interpolation of its strobes.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .accounts import _x_cuts as x_cuts
from .accounts import gauss, strobe
from .fields import invariants, load, w_in
from .stepper import IMPACT

__all__ = ["ContinuumSeries"]


class ContinuumSeries:
    """The last ``periods`` forcing periods of ``run`` (a :class:`~plbar.continuum.ContinuumRun` with its line).

    ``prob`` is the FE problem whose mesh carries the samples (P1 on the run's grid, as
    :func:`plbar.io.motion_data` needs one for its cells and nodal shares).
    """

    def __init__(self, run, periods: int, prob):
        if not 1 <= int(periods) <= run.periods:
            raise InputError(f"periods = {periods!r} must be in [1, {run.periods}]")
        self.run, self.prob, self.periods = run, prob, int(periods)
        self.T, self.phi = float(run.T), float(run.phi)
        self.t0 = (run.periods - self.periods) * self.T
        self.span = self.periods * self.T
        ev = run.events
        sel = (ev["time"] >= self.t0) & (ev["time"] <= self.t0 + self.span)
        self.events = {k: np.asarray(ev[k][sel]) for k in ("time", "kind", "loss")}
        self._stuck0 = bool(run.end[run.periods - self.periods, 2])

    def _states(self, times) -> np.ndarray:
        """1 in contact, 2 gap open, just after any switch at that time."""
        t = np.asarray(times, float)
        te, ke = self.events["time"], self.events["kind"]
        i = np.searchsorted(te, t, side="right") - 1          # the last switch at or before t
        stuck = np.where(i >= 0, ke[np.maximum(i, 0)] == IMPACT, self._stuck0)
        return np.where(stuck, 1, 2)

    def response(self, times):
        """Grid ``u, v`` at the free points (K, n) and the state (K,) (1 in contact, 2 gap open)."""
        ln, n = self.run.line, self.run.n
        uv = [strobe(ln, float(t), n) for t in np.asarray(times, float)]
        return (np.array([u[1:] for u, _ in uv]), np.array([v[1:] for _, v in uv]), self._states(times))

    def reaction(self, times):
        """The compression the wall holds, ``Z w_in + F_L`` (>= 0), in contact; 0 while the gap is open."""
        ln, bar = self.run.line, self.run.bar
        t = np.asarray(times, float)
        g = bar.Z * w_in(ln, t) + (load(ln, t) if bar.at_end else 0.0)
        return np.where(self._states(t) == 1, g, 0.0)

    def energies(self, times):
        """Kinetic (bar and end mass) and strain energy at ``times``; each (K,)."""
        ln, bar = self.run.line, self.run.bar
        ek, ep = [], []
        for t in np.asarray(times, float):
            edges = x_cuts(ln, t)
            kin = gauss(lambda x, t=t: 0.5 * bar.rhoA * (0.5 * np.add(*invariants(ln, x, t))) ** 2, edges).sum()
            pot = gauss(lambda x, t=t: 0.5 * bar.rhoA * (0.5 * np.subtract(*invariants(ln, x, t)[::-1])) ** 2,
                        edges).sum()
            vL = 0.5 * np.add(*invariants(ln, np.array([bar.L]), t))[0]
            ek.append(kin + 0.5 * bar.end_mass * vL ** 2)
            ep.append(pot)
        return np.array(ek), np.array(ep)

    @property
    def stuck_time(self) -> float:
        """Time in contact over the window."""
        total, t, stuck = 0.0, self.t0, self._stuck0
        for te, ke in zip(self.events["time"], self.events["kind"]):
            if stuck:
                total += te - t
            t, stuck = te, ke == IMPACT
        return total + (self.t0 + self.span - t if stuck else 0.0)
