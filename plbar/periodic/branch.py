"""One branch of periodic responses of any signature: a maximal run of admissible orbits along a curve in ``T``.

:class:`Branch` is the one record of a branch, the paper's class (``1P``) and every other signature alike
(:func:`.branches.find_branches` makes them, :func:`.branches.from_paths` those of the paper's scan).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..paths import GRAZING
from ..util.reprs import build, count, rng
from .signature import PAPER, Signature

__all__ = ["Branch", "DWELL_ZERO", "PREMATURE"]

DWELL_ZERO = "stuck phase -> 0"     #: event kind: a stuck phase shrinks to zero (the signature changes)
PREMATURE = "premature switch"      #: branch end: the next point on its curve switches prematurely


@dataclass(frozen=True)
class Branch:
    """Admissible periodic responses of one signature along a curve in ``T`` (ordered).

    Attributes
    ----------
    sig : Signature
        As followed (``label`` is its canonical string).
    orbits : tuple of Orbit
    stable : ndarray of bool
    max_abs_multiplier : ndarray
    events : list of dict
        ``kind`` (:data:`PD`, :data:`NS`, :data:`FOLD`, :data:`GRAZING` where the branch stops being admissible,
        :data:`DWELL_ZERO` where a stuck phase shrinks to zero), ``index``, ``T``.
    ends : (str, str)
        What ended the branch at its first and last point: :data:`PREMATURE` (the next point on the curve switches
        prematurely), or why the curve itself ended (:mod:`.follow`: ``"window"``, ``"dwell->0"``, ...; the
        paper's class: :attr:`plbar.paths.Branch.ends`).
    grazing_points : ndarray of bool, optional
        Per point, a grazing contact (the paper's class: its dense admissibility check).
    """

    id: int
    sig: Signature
    orbits: tuple = field(repr=False)
    stable: np.ndarray = field(repr=False)
    max_abs_multiplier: np.ndarray = field(repr=False)
    events: list = field(default_factory=list, repr=False)
    ends: tuple = ("", "")
    grazing_points: np.ndarray | None = field(default=None, repr=False)

    @property
    def label(self) -> str:
        return str(self.sig.canonical())

    def _a(self, name):
        return np.array([getattr(o, name) for o in self.orbits], float)

    @property
    def T1(self):
        """The total stuck time over each orbit (``m`` periods): the paper's ``T^I`` for ``1P``."""
        return np.array([o.durations[0::2].sum() for o in self.orbits])

    @property
    def T2(self):
        """The total free time over each orbit: the paper's ``T^II`` for ``1P``."""
        return np.array([o.durations[1::2].sum() for o in self.orbits])

    @property
    def grazing(self):
        """Per point: a grazing contact (:attr:`grazing_points`, where the paper's dense admissibility check gives
        them); else the branch ends there because the next point on its curve switches prematurely (a grazing
        contact or a premature opening: :data:`GRAZING` events)."""
        if self.grazing_points is not None:
            return self.grazing_points
        g = np.zeros(len(self), bool)
        for e in self.events:
            if e["kind"] == GRAZING:
                g[e["index"]] = True
        return g

    @property
    def paper(self) -> bool:
        """Of the paper's class (signature ``1P``)."""
        return self.sig.canonical() == PAPER

    def describe(self) -> str:
        """One line: id, signature, points, ``T`` and ``xi`` ranges, stable points, events by kind, the ends."""
        kinds = [e["kind"] for e in self.events]
        ev = ", ".join(f"{k}: {kinds.count(k)}" for k in dict.fromkeys(kinds))
        return (f"branch {self.id} ({self.label}): {len(self)} points, T in {rng(self.T)}, xi in {rng(self.xi)}, "
                f"stable {count(self.stable)}" + (f", events {{{ev}}}" if ev else "") +
                f", ends: {' / '.join(self.ends)}")

    def __len__(self) -> int:
        return len(self.orbits)

    def __repr__(self) -> str:
        return build("Branch", {"id": self.id, "signature": self.label, "points": len(self), "T": rng(self.T),
                                      "xi": rng(self.xi), "loss_per_T": rng(self.loss_per_T),
                                      "stable": count(self.stable), "events": len(self.events)})


def _per_orbit(name: str, doc: str | None = None) -> property:
    """The :class:`Branch` property of the orbits' ``name``, one value per point."""
    return property(lambda b: b._a(name), doc=doc or f"Each orbit's ``{name}`` (:class:`plbar.periodic.Orbit`).")


for _name in ("T", "phi", "dPL", "loss_per_T", "xi", "xi_w", "xi_total", "viscous"):
    setattr(Branch, _name, _per_orbit(_name))
Branch.amplitude = _per_orbit("amplitude", "``max |x_c|`` of each orbit (:attr:`Orbit.amplitude`).")
