"""The uniform continuum bar: clamped at ``x = 0``, end mass and unilateral contact at ``x = L``."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError

__all__ = ["ContinuumBar", "from_case", "natural_periods"]


def _positive(name: str, v, zero: bool = False) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {v!r} must be a number") from None
    if not math.isfinite(x) or x < 0 or (x == 0 and not zero):
        raise InputError(f"{name} = {v!r} is not allowed; it must be finite and {'>= 0' if zero else '> 0'}")
    return x


@dataclass(frozen=True)
class ContinuumBar:
    """A uniform bar ``0 <= x <= L`` with wave speed ``c = sqrt(EA / rhoA)`` (FORMULATION §1).

    Parameters
    ----------
    L, EA, rhoA : float
        Length, axial stiffness and mass per length (> 0).
    end_mass : float
        Rigid mass at the contact end ``x = L`` (absolute, >= 0).
    s : float
        Position of the point load ``q cos(omega t - phi)``, in ``(0, L]``.
    q : float
        Load amplitude.
    """

    L: float = 1.0
    EA: float = 1.0
    rhoA: float = 1.0
    end_mass: float = 0.5
    s: float = 0.37
    q: float = 1.0

    def __post_init__(self):
        for nm in ("L", "EA", "rhoA"):
            object.__setattr__(self, nm, _positive(nm, getattr(self, nm)))
        object.__setattr__(self, "end_mass", _positive("end_mass", self.end_mass, zero=True))
        s = _positive("load position s", self.s)
        if s > self.L:
            raise InputError(f"load position s = {s:g} is outside the bar (0, {self.L:g}]")
        object.__setattr__(self, "s", s)
        q = float(self.q)
        if not math.isfinite(q):
            raise InputError(f"load amplitude q = {self.q!r} must be finite")
        object.__setattr__(self, "q", q)

    @property
    def c(self) -> float:
        """Wave speed ``sqrt(EA / rhoA)``."""
        return math.sqrt(self.EA / self.rhoA)

    @property
    def Z(self) -> float:
        """Impedance ``rhoA c = EA / c``."""
        return math.sqrt(self.EA * self.rhoA)

    @property
    def at_end(self) -> bool:
        """The load acts on the end mass (``s = L``)."""
        return self.s == self.L


def from_case(case) -> ContinuumBar:
    """The continuum bar of a :class:`plbar.Case` with ``model = "fe"`` (uniform section, one point load).

    The end mass is :attr:`Case.end_mass_value`; other point masses and multi-point loads are refused.
    """
    if case.model != "fe":
        raise InputError(f"a continuum bar needs model = 'fe', got {case.model!r}")
    bar = case.bar()
    if getattr(bar.EA, "ndim", 0) or getattr(bar.rhoA, "ndim", 0):
        raise InputError("a continuum bar needs a uniform section (scalar EA and rhoA)")
    extra = [pm for pm in bar.point_masses if pm[0] != bar.length]
    if extra:
        raise InputError(f"point masses {extra} away from the end have no continuum counterpart here")
    pts, nodes = case.load().points, case.load().nodes
    if nodes or len(pts) != 1:
        raise InputError("a continuum bar takes a single point load (load_positions with one (x, amplitude))")
    (x, a), = pts
    me = sum(m for xp, m in bar.point_masses if xp == bar.length)
    return ContinuumBar(bar.length, float(bar.EA), float(bar.rhoA), me, x, a)


def natural_periods(bar: ContinuumBar) -> tuple[float, float]:
    """The fundamental periods ``(T0^I, T0^II)`` of the bar held closed (clamped-clamped: ``2 L / c``) and held open
    (clamped, end mass ``m_e``: ``kL tan kL = rhoA L / m_e``, ``T = 2 pi / (c k)``; ``4 L / c`` without a mass)."""
    from scipy.optimize import brentq

    TI = 2 * bar.L / bar.c
    if bar.end_mass == 0:
        return TI, 2 * TI
    mu = bar.rhoA * bar.L / bar.end_mass
    z = brentq(lambda z: z * math.sin(z) - mu * math.cos(z), 0.0, 0.5 * math.pi, xtol=1e-15, rtol=1e-15)
    return TI, 2 * math.pi * bar.L / (bar.c * z)
