"""Closed-form steady harmonic responses of the linear bars: contact held closed, or held open (pure functions).

``u(x, t) = U(x) cos(omega t - phi)``, ``k = omega / c``.  Held closed (clamped-clamped): ``U = alpha sin kx`` left of
the load and ``beta sin k(L - x)`` right of it.  Held open (clamped, end mass ``m``): right of the load
``U = b1 cos k(L - x) + b2 sin k(L - x)`` and at the end ``-m omega^2 U(L) = -EA U'(L) (+ q if s = L)``, i.e.
``EA k b2 = -m omega^2 b1`` for ``s < L``.  At the load ``U`` is continuous and ``EA [U'] = -q``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .bar import ContinuumBar
from .stepper import Start

__all__ = ["Harmonic", "held_closed", "held_open"]


@dataclass(frozen=True)
class Harmonic:
    """``U(x) = alpha sin kx`` (``x < s``), ``b1 cos k(L - x) + b2 sin k(L - x)`` (``x >= s``)."""

    bar: ContinuumBar
    omega: float
    phi: float
    alpha: float
    b1: float
    b2: float

    @property
    def k(self) -> float:
        return self.omega / self.bar.c

    def U(self, x):
        x = np.asarray(x, float)
        y = self.bar.L - x
        right = self.b1 * np.cos(self.k * y) + self.b2 * np.sin(self.k * y)
        return np.where(self._left(x), self.alpha * np.sin(self.k * x), right)

    def dU(self, x):
        x = np.asarray(x, float)
        y, k = self.bar.L - x, self.k
        right = k * (self.b1 * np.sin(k * y) - self.b2 * np.cos(k * y))
        return np.where(self._left(x), self.alpha * k * np.cos(k * x), right)

    def _left(self, x):
        return x <= self.bar.s if self.bar.at_end else x < self.bar.s

    def u(self, x, t):
        return self.U(x) * np.cos(self.omega * t - self.phi)

    def v(self, x, t):
        return -self.omega * self.U(x) * np.sin(self.omega * t - self.phi)

    def start(self, stuck: bool) -> Start:
        """The state at ``t = 0`` with its past ``w_out = v(L) + c u_x(L) = C cos omega t + D sin omega t``."""
        UL, dUL, c, w, p = float(self.U(self.bar.L)), float(self.dU(self.bar.L)), self.bar.c, self.omega, self.phi
        C, D = c * dUL * math.cos(p) + w * UL * math.sin(p), c * dUL * math.sin(p) - w * UL * math.cos(p)
        return Start(UL * math.cos(p), w * UL * math.sin(p), stuck, C, D)


def _solve(A, rhs, what: str) -> np.ndarray:
    A = np.asarray(A, float)
    if abs(np.linalg.det(A)) < 1e-12 * np.abs(A).max() ** len(A):
        raise InputError(f"the forcing frequency is (numerically) a resonance of the {what} bar; choose another T")
    return np.linalg.solve(A, rhs)


def held_closed(bar: ContinuumBar, T: float, phi: float = 0.0) -> Harmonic:
    """The clamped-clamped steady response (the contact never opens)."""
    w = 2 * math.pi / T
    k, s, L, EA, q = w / bar.c, bar.s, bar.L, bar.EA, bar.q
    if bar.at_end:
        return Harmonic(bar, w, phi, 0.0, 0.0, 0.0)
    A = [[math.sin(k * s), -math.sin(k * (L - s))], [k * math.cos(k * s), k * math.cos(k * (L - s))]]
    a, b = _solve(A, [0.0, q / EA], "clamped-clamped")
    return Harmonic(bar, w, phi, a, 0.0, b)


def held_open(bar: ContinuumBar, T: float, phi: float = 0.0) -> Harmonic:
    """The clamped bar with a free end mass (the contact never closes; ``u(L)`` may cross the wall)."""
    w = 2 * math.pi / T
    k, s, L, EA, q, m = w / bar.c, bar.s, bar.L, bar.EA, bar.q, bar.end_mass
    if bar.at_end:
        a, = _solve([[EA * k * math.cos(k * L) - m * w * w * math.sin(k * L)]], [q], "clamped-mass")
        return Harmonic(bar, w, phi, a, a * math.sin(k * L), 0.0)
    y = L - s
    A = [[math.sin(k * s), -math.cos(k * y), -math.sin(k * y)],
         [k * math.cos(k * s), -k * math.sin(k * y), k * math.cos(k * y)],
         [0.0, m * w * w, EA * k]]
    a, b1, b2 = _solve(A, [0.0, q / EA, 0.0], "clamped-mass")
    return Harmonic(bar, w, phi, a, b1, b2)
