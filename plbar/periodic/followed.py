"""The curves followed so far: is a new orbit on one of them (then it is not followed again)?

A seed (a closed form, a period doubling, a split, a dwell transition) often lands on a curve that another seed
has already followed.  Two tests, the cheap one first:

* **on a chord** -- the orbit's loss is on the linear interpolation of a piece (two neighbouring followed points) at
  its ``T``, or its ``T`` on the interpolation at its loss, within a hundredth of the piece's change.  This misses
  the same orbit where the curve bends between the two points (a fold in ``T``, a steep loss): the interpolation
  is then off by the sagitta, far more than a hundredth;
* **the same orbit** -- Newton at the orbit's ``T`` (:func:`.solve.polish`) from the interpolation of a piece's
  unknowns (a piece whose ``T`` range, widened on each side by half and by ``1e-3 T``, holds the orbit's: seeds
  often sit at a curve's end, where a duration reaches zero, or past a fold's tip between two followed points)
  converges to an orbit whose rotation-invariant description (the sorted durations, the loss per period) equals
  the orbit's to ``1e-7``.  An exact test, where it converges; where it does not (a guess too far off), the orbit
  counts as new, so no curve is lost, at worst one is followed twice.
"""

from __future__ import annotations

import numpy as np

from ..model import Problem
from .solve import NotConverged, Orbit, polish

__all__ = ["Followed", "on_chord"]

#: two orbits at one ``T`` are the same when their sorted durations and loss agree to this (relative)
SAME = 1e-7


def on_chord(a, b, ya, yb, s: float, y: float, floor: float) -> np.ndarray:
    """The chords ``(a, ya)``-``(b, yb)`` whose ``s`` range holds ``s`` with ``y`` within ``1e-2 |yb - ya| + floor``
    of the chord's value at ``s`` (a boolean per chord)."""
    a, b, ya, yb = (np.asarray(v, float) for v in (a, b, ya, yb))
    w = np.divide(s - a, b - a, out=np.zeros(a.size), where=b != a)
    held = (np.minimum(a, b) <= s) & (s <= np.maximum(a, b))
    return held & (np.abs(ya + w * (yb - ya) - y) <= 1e-2 * np.abs(yb - ya) + floor)


def _invariants(orb: Orbit) -> np.ndarray:
    """What does not depend on where the orbit's period starts: its sorted durations and its loss per period."""
    return np.concatenate([np.sort(orb.durations), [orb.loss_per_T]])


class Followed:
    """The curves followed so far, per canonical signature (each a sequence of exact orbits)."""

    def __init__(self, prob: Problem):
        self.prob = prob
        self.curves: dict[str, list[tuple[Orbit, ...]]] = {}

    def add(self, orbs) -> None:
        """Record a followed curve (its orbits in order, all of one signature)."""
        orbs = tuple(orbs)
        if orbs:
            self.curves.setdefault(str(orbs[0].sig.canonical()), []).append(orbs)

    def known(self, orb: Orbit) -> bool:
        """Is ``orb`` on a followed curve (module docstring: on a chord, else the same orbit by Newton)?"""
        curves = self.curves.get(str(orb.sig.canonical()), [])
        T, loss = orb.T, orb.loss_per_T
        candidates = []
        for c in curves:
            Tc = np.array([o.T for o in c])
            Lc = np.array([o.loss_per_T for o in c])
            a, b, La, Lb = Tc[:-1], Tc[1:], Lc[:-1], Lc[1:]
            if np.any(on_chord(a, b, La, Lb, T, loss, 1e-6 * max(abs(loss), 1e-12))):
                return True
            half = 0.5 * np.abs(b - a) + 1e-3 * T             # and a little beyond: a curve's end, a fold's tip
            held = np.flatnonzero((np.minimum(a, b) - half <= T) & (T <= np.maximum(a, b) + half))
            candidates.extend((c[i], c[i + 1]) for i in held)
            if len(c) == 1:                                   # a curve of one point: Newton from it
                candidates.append((c[0], c[0]))
        return any(self._same(orb, p, q) for p, q in candidates)

    def _same(self, orb: Orbit, p: Orbit, q: Orbit) -> bool:
        """Newton at ``orb.T`` from the interpolation of ``p`` and ``q`` reaches ``orb`` (rotation-invariantly)."""
        w = 0.0 if q.T == p.T else (orb.T - p.T) / (q.T - p.T)
        X = p.X + w * (q.X - p.X)
        X[-1] = p.X[-1] + w * np.angle(np.exp(1j * (q.X[-1] - p.X[-1])))   # the phase the short way round
        try:
            o = polish(self.prob, p.sig, orb.T, X)
        except NotConverged:
            return False
        u, v = _invariants(o), _invariants(orb)
        if u.shape != v.shape:
            return False
        scale = np.r_[np.full(v.size - 1, orb.T), max(abs(orb.loss_per_T), 1e-9 * orb.T)]
        return bool(np.all(np.abs(u - v) <= SAME * scale))
