"""Harmonic loads: point forces anywhere on the bar, nodal forces, and sums.

The load amplitude vector ``q0`` enters Eq. (1) as ``q0 cos(w t - phi)``.  A
point force at ``s`` is distributed through the element shape functions
(``Basis.point_source``); for P1 this is the paper's linear split between the
two neighbouring DOFs (Sec. 4.2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._check import finite
from .bar import Assembled, Bar
from .errors import InputError

__all__ = ["Load", "point", "node"]


@dataclass(frozen=True)
class Load:
    """A sum of point forces and nodal forces.

    Attributes
    ----------
    points : tuple of (s, amplitude)
        Point forces at positions ``s`` in ``(0, L]``.
    nodes : tuple of (k, amplitude)
        Forces on free DOF ``k`` (1-based, sorted from the clamp, as in the
        paper; the contact DOF is the last one).
    """

    points: tuple[tuple[float, float], ...] = ()
    nodes: tuple[tuple[int, float], ...] = ()

    def __post_init__(self):
        pts = tuple((finite("load position", s), finite("load amplitude", a)) for s, a in self.points)
        nds = []
        for k, a in self.nodes:
            if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
                raise InputError(f"load node = {k!r} must be an integer DOF number >= 1")
            nds.append((int(k), finite("load amplitude", a)))
        if not pts and not nds:
            raise InputError("the load is empty; give at least one point force or nodal force")
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "nodes", tuple(nds))

    def __add__(self, other: "Load") -> "Load":
        return Load(self.points + other.points, self.nodes + other.nodes)

    def scaled(self, factor: float) -> "Load":
        """The same load times ``factor``."""
        return Load(tuple((s, a * factor) for s, a in self.points),
                    tuple((k, a * factor) for k, a in self.nodes))

    def vector(self, bar: Bar, asm: Assembled) -> np.ndarray:
        """Load amplitude vector ``q0`` over the sorted free DOFs, shape ``(n,)``."""
        q = np.zeros(asm.n)
        L = bar.length
        for s, a in self.points:
            if not (0.0 < s <= L * (1 + 1e-14)):
                raise InputError(f"load position s = {s!r} is outside the bar; it must lie in (0, {L:g}]")
            q += a * asm.load_vector(min(s, L))
        for k, a in self.nodes:
            if not 1 <= k <= asm.n:
                raise InputError(f"load node = {k} is out of range; free DOFs are numbered 1..{asm.n}")
            q[k - 1] += a
        if not np.any(q != 0.0) or not np.all(np.isfinite(q)):
            raise InputError("the load vector is all zero; give a non-zero amplitude")
        return q

    def describe(self) -> str:
        parts = [f"{a:g} at s={s:g}" for s, a in self.points] + [f"{a:g} on DOF {k}" for k, a in self.nodes]
        return " + ".join(parts)


def point(s: float, amplitude: float = 1.0) -> Load:
    """A point force of ``amplitude`` at position ``s``."""
    return Load(points=((s, amplitude),))


def node(k: int, amplitude: float = 1.0) -> Load:
    """A force of ``amplitude`` on free DOF ``k`` (1-based from the clamp)."""
    return Load(nodes=((k, amplitude),))
