"""Harmonic loads: point forces anywhere on the bar, nodal forces, a shaking support, and sums.

The load amplitude vector ``q0`` enters Eq. (1) as ``q0 cos(w t - phi)``.  A
point force at ``s`` is distributed through the element shape functions
(``Basis.point_source``); for P1 this is the paper's linear split between the
two neighbouring DOFs (Sec. 4.2).

A base excitation (FORMULATION §9) is the support's acceleration ``a_g cos(w t - phi)`` along the bar: in
coordinates relative to the support the structure obeys ``M x'' + C x' + K x = -M t a_g cos(w t - phi)``, with
``t`` the free DOFs' displacement under a unit rigid motion of the support (ones for the bar: ``M t`` is
:attr:`plbar.model.Assembled.body`, the clamp's columns included).  The stop moves with the support, so the
contact coordinate, the gap and every reported response are relative to it; damping acts on the relative
velocities (Rayleigh damping of the structure's deformation).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..util.check import finite, integer, pairs, show
from .bar import Assembled, Bar
from ..errors import InputError

__all__ = ["Load", "point", "node", "base_excitation"]

#: smallest allowed load position, relative to the bar length (closer is "at the clamp")
MIN_POSITION = 1e-9
#: allowed range of non-zero load amplitudes (the response is linear in the amplitude;
#: outside this range its squares under- or overflow)
MIN_AMPLITUDE, MAX_AMPLITUDE = 1e-24, 1e24


def _amplitude(a) -> float:
    must = f"0 or a finite number of magnitude in [{MIN_AMPLITUDE:g}, {MAX_AMPLITUDE:g}]"
    a = finite("load amplitude", a, must)
    if a != 0.0 and not MIN_AMPLITUDE <= abs(a) <= MAX_AMPLITUDE:
        raise InputError(f"load amplitude = {show(a)} is not allowed; it must be {must}")
    return a


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
    base : float
        The support's acceleration amplitude ``a_g`` (a base excitation, module docstring), positive along the bar
        towards the stop; 0: none.
    """

    points: tuple[tuple[float, float], ...] = ()
    nodes: tuple[tuple[int, float], ...] = ()
    base: float = 0.0

    def __post_init__(self):
        pts = []
        for s, a in pairs("load points", self.points, "(s, amplitude)"):
            s = finite("load position s", s, "a position in (0, L]")
            if s <= 0.0:
                raise InputError(f"load position s = {show(s)} is outside the bar; it must lie in (0, L] "
                                 "(x = 0 is the clamped end, where a force does no work)")
            pts.append((s, _amplitude(a)))
        nds = []
        for k, a in pairs("load nodes", self.nodes, "(k, amplitude)"):
            nds.append((integer("load node", k, 1), _amplitude(a)))
        base = _amplitude(self.base) if self.base is not None else 0.0
        if not pts and not nds and not base:
            raise InputError("the load is empty; give at least one point force, nodal force or base acceleration")
        object.__setattr__(self, "points", tuple(pts))
        object.__setattr__(self, "nodes", tuple(nds))
        object.__setattr__(self, "base", base)

    def __add__(self, other: "Load") -> "Load":
        if not isinstance(other, Load):
            return NotImplemented
        return Load(self.points + other.points, self.nodes + other.nodes, self.base + other.base)

    def scaled(self, factor: float) -> "Load":
        """The same load times ``factor``."""
        factor = finite("load factor", factor)
        return Load(tuple((s, a * factor) for s, a in self.points),
                    tuple((k, a * factor) for k, a in self.nodes), self.base * factor)

    def check(self, bar: Bar) -> None:
        """Raise unless every force acts on ``bar``: positions in ``(0, L]`` away from the clamp, DOFs in range."""
        L = bar.length
        free = bar.supports == "free-free"                       # no clamp at x = 0: a force may act there
        for s, _ in self.points:
            if not ((0.0 <= s if free else 0.0 < s) and s <= L * (1 + 1e-14)):
                raise InputError(f"load position s = {show(s)} is outside the bar; it must lie in "
                                 f"{'[' if free else '('}0, {L:g}]")
            if s < MIN_POSITION * L and not free:
                raise InputError(f"load position s = {show(s)} is at the clamped end x = 0; it must lie in "
                                 f"[{MIN_POSITION:g} L, L] = [{MIN_POSITION * L:g}, {L:g}]")
            if bar.supports == "clamped-clamped" and s > L * (1 - MIN_POSITION):
                raise InputError(f"load position s = {show(s)} is at the clamped end x = L of a bar clamped at both "
                                 f"ends; it must lie in [{MIN_POSITION:g} L, (1 - {MIN_POSITION:g}) L]")
            if bar.crack_at is not None and s == bar.crack_at:
                raise InputError(f"load position s = {show(s)} is at the crack, on both faces; put the force on one "
                                 "side of it")
        if self.base and bar.supports == "free-free":
            raise InputError("a base excitation shakes the bar's support, and a bar with supports = 'free-free' "
                             "has none; load it by forces (or clamp it)")
        for k, _ in self.nodes:
            if not 1 <= k <= bar.n_dofs:
                raise InputError(f"load node = {k} is out of range; free DOFs are numbered 1..{bar.n_dofs}")

    def vector(self, bar: Bar, asm: Assembled) -> np.ndarray:
        """Load amplitude vector ``q0`` over the sorted free DOFs, shape ``(n,)`` (Eq. (1))."""
        self.check(bar)
        q = np.zeros(asm.n)
        for s, a in self.points:
            q += a * asm.load_vector(min(s, bar.length))
        for k, a in self.nodes:
            q[k - 1] += a
        if self.base:
            q -= self.base * asm.body
        scale = sum(abs(a) for _, a in self.points + self.nodes) + abs(self.base) * float(np.abs(asm.body).max())
        if not np.all(np.isfinite(q)):
            raise InputError(f"the load vector is not finite ({self.describe()}); amplitudes must be "
                             f"at most {MAX_AMPLITUDE:g} in magnitude")
        if scale and not np.max(np.abs(q)) > 1e-12 * scale:      # (no force at all: a free motion, taken)
            raise InputError(f"the load vector is zero: the forces {self.describe()} cancel; "
                             "give a load with a non-zero resultant on the free DOFs")
        return q

    def describe(self) -> str:
        parts = [f"{a:g} at s={s:g}" for s, a in self.points] + [f"{a:g} on DOF {k}" for k, a in self.nodes]
        return " + ".join(parts + ([f"a base acceleration {self.base:g}"] if self.base else []))


def point(s: float, amplitude: float = 1.0) -> Load:
    """A point force of ``amplitude`` at position ``s``."""
    return Load(points=((s, amplitude),))


def node(k: int, amplitude: float = 1.0) -> Load:
    """A force of ``amplitude`` on free DOF ``k`` (1-based from the clamp)."""
    return Load(nodes=((k, amplitude),))


def base_excitation(acceleration: float = 1.0) -> Load:
    """The support shaken along the bar with the acceleration amplitude ``acceleration`` (module docstring)."""
    return Load(base=acceleration)
