"""Branches and paths: the results of :func:`plbar.find_paths` (ordered curves of admissible responses)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..model import Problem
from ..response import Admissibility, Damping, Orbits, damping
from ..util.check import interval
from ..util.reprs import build, count, listing, rng

__all__ = ["Domain", "default_domain", "Branch", "Paths", "events", "build_branches", "EVENT_KINDS", "FOLD_T",
           "GRAZING", "NEIMARK_SACKER", "PERIOD_DOUBLING", "FOLD_MU"]

FOLD_T = "fold in T"                   #: event kind: the branch turns back in the forcing period
GRAZING = "grazing"                    #: event kind: a grazing stretch begins
NEIMARK_SACKER = "Neimark-Sacker"      #: event kind: stability change through a complex pair
PERIOD_DOUBLING = "period doubling"    #: event kind: stability change through mu = -1
FOLD_MU = "fold (mu = +1)"             #: event kind: stability change through mu = +1
EVENT_KINDS = (FOLD_T, GRAZING, NEIMARK_SACKER, PERIOD_DOUBLING, FOLD_MU)

@dataclass(frozen=True)
class Domain:
    """Search domain ``T1 in (T1_lo, T1_hi]``, ``T2 in (T2_lo, T2_hi]``."""

    T1: tuple[float, float]
    T2: tuple[float, float]

    def __post_init__(self):
        for nm in ("T1", "T2"):
            object.__setattr__(self, nm, interval(f"search domain {nm}", getattr(self, nm)))


def default_domain(prob: Problem) -> Domain:
    """The paper's domain ``T^alpha in (0, T0^alpha / 2]`` (Sec. 4.1); a single mass held at the stop (no
    period of its own, ``T0^I = 0``) is searched with stuck phases up to ``T0^II / 2``."""
    T0I, T0II = prob.system.T0
    return Domain((0.0, (T0I or T0II) / 2), (0.0, T0II / 2))


@dataclass(frozen=True)
class Branch:
    """One ordered curve of admissible periodic responses.

    Attributes
    ----------
    id : int
    orbits : Orbits
        The responses, ordered along the curve.
    damping : Damping
        ``Delta_PL`` and ``xi_eq`` at each point.
    adm : plbar.response.Admissibility
    e1, e2 : ndarray
        Switch residuals, relative to their scale.
    ends : (str, str)
        What ended the branch at its first and last point (``"domain edge"``,
        ``"closed loop"``, ``"premature switch (reaction)"``, ``"premature
        switch (gap)"``, ``"impact velocity <= 0"``, ``"not periodic"``, ...).
    events : tuple of dict
        Events detected along the branch (folds in ``T``, grazing), each with ``kind``, ``index`` and
        ``T1, T2, T``.  Stability and its changes are the periodic core's (:func:`plbar.periodic.from_paths`:
        ``plbar.solve(case).paper``), for this class as for every other signature.
    """

    id: int
    orbits: Orbits
    damping: Damping
    adm: Admissibility
    e1: np.ndarray
    e2: np.ndarray
    ends: tuple[str, str] = ("", "")
    events: tuple = ()

    @property
    def T1(self):
        return self.orbits.T1

    @property
    def T2(self):
        return self.orbits.T2

    @property
    def phi(self):
        return self.orbits.phi

    @property
    def T(self):
        return self.orbits.T

    @property
    def dPL(self):
        return self.damping.dPL

    @property
    def xi(self):
        return self.damping.xi

    @property
    def xi_w(self):
        """``xi_w``: the damping ratio with one frequency, the forcing's (see :class:`plbar.response.Damping`)."""
        return self.damping.xi_w

    @property
    def viscous(self):
        """Energy the Rayleigh dampers dissipate per period (0 without damping)."""
        return self.damping.viscous

    @property
    def xi_total(self):
        """Rayleigh ratio at the forcing frequency plus ``xi_eq``."""
        return self.damping.xi_total

    @property
    def grazing(self):
        return self.adm.grazing

    def __len__(self):
        return len(self.orbits)

    def describe(self) -> str:
        """One line: id, points, ``T`` and ``xi`` ranges, events by kind and the ends."""
        ev = _event_counts(self.events)
        return (f"branch {self.id}: {len(self)} points, T in {rng(self.T)}, xi in {rng(self.xi)}"
                + (f", events {ev}" if ev else "") + f", ends: {' / '.join(self.ends)}")

    def __repr__(self) -> str:
        return build("Branch", {"id": self.id, "points": len(self), "T": rng(self.T),
                                "T1": rng(self.T1), "T2": rng(self.T2), "xi": rng(self.xi),
                                "grazing": count(self.grazing),
                                "events": _event_counts(self.events) or "{}", "ends": self.ends})


@dataclass(frozen=True)
class Paths:
    """All branches found in a domain, with scan statistics."""

    prob: Problem
    domain: Domain
    grid: tuple[int, int]
    branches: tuple[Branch, ...]
    stats: dict = field(default_factory=dict)

    def __repr__(self) -> str:
        n = sum(len(b) for b in self.branches)
        xi = max((float(b.xi.max()) for b in self.branches if len(b)), default=0.0)
        T0I, T0II = self.prob.system.T0
        head = build("Paths", {"branches": len(self.branches), "points": n, "grid": self.grid,
                               "T1": f"({self.domain.T1[0]:.4g}, {self.domain.T1[1]:.4g}]",
                               "T2": f"({self.domain.T2[0]:.4g}, {self.domain.T2[1]:.4g}]",
                               "n": self.prob.system.n, "T0": f"({T0I:.4g}, {T0II:.4g})", "max_xi": f"{xi:.4g}"})
        return head + "".join("\n  " + ln for ln in listing((b.describe() for b in self.branches), 5))

    def points(self) -> Orbits | None:
        """All path points of all branches as one :class:`Orbits` (None if empty)."""
        return Orbits.concat([b.orbits for b in self.branches]) if self.branches else None


def _event_counts(evs) -> str:
    """``{kind: count, ...}`` of a sequence of events, in the order of :data:`EVENT_KINDS` ("" if none)."""
    kinds = [e["kind"] for e in evs]
    order = [k for k in EVENT_KINDS if k in kinds] + sorted(set(kinds) - set(EVENT_KINDS))
    return "{" + ", ".join(f"{k}: {kinds.count(k)}" for k in order) + "}" if kinds else ""


def events(T1, T2, T, adm: Admissibility) -> list[dict]:
    """Folds in ``T`` and grazing along an ordered branch."""
    ev = []
    dT = np.diff(T)
    for k in np.flatnonzero(dT[:-1] * dT[1:] < 0):
        ev.append(dict(kind=FOLD_T, index=int(k + 1)))
    g = adm.grazing
    for k in np.flatnonzero(g[1:] & ~g[:-1]):
        ev.append(dict(kind=GRAZING, index=int(k + 1)))
    for e in ev:
        i = e["index"]
        e.update(T1=float(T1[i]), T2=float(T2[i]), T=float(T[i]))
    return sorted(ev, key=lambda e: e["index"])


def build_branches(ev, runs) -> list[Branch]:
    """Branches from admissible runs of evaluated points (``ev``: :class:`~plbar.paths.evaluate.Evaluated`).

    ``runs`` is a list of ``(point indices, (start reason, end reason))``.  The
    damping of all points is computed in one batch; branches
    are numbered by their smallest period and ordered by increasing ``T`` of
    their ends.
    """
    sel = np.concatenate([r for r, _ in runs]) if runs else np.zeros(0, int)
    if not sel.size:
        return []
    orb = ev.orbits
    sorb = orb.take(sel)
    dmp = damping(sorb)
    lookup = {int(k): j for j, k in enumerate(sel)}
    out = []
    for bid, r in enumerate(sorted(range(len(runs)), key=lambda r: min(orb.T[runs[r][0]]))):
        run, ends = runs[r]
        if orb.T[run[0]] > orb.T[run[-1]]:
            run, ends = run[::-1], ends[::-1]
        jj = [lookup[k] for k in run]
        bo, ba = orb.take(run), ev.adm.take(run)
        out.append(Branch(bid, bo, dmp.take(jj), ba, ev.r1[run], ev.r2[run], ends,
                          tuple(events(bo.T1, bo.T2, bo.T, ba))))
    return out
