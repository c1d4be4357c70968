"""The fields of the bar rebuilt from the delay line (d'Alembert), as pure array functions.

With ``d = (L - x) / c`` and ``P = 2L/c``: ``w-(x, t) = w_out(t - d) + [x < s] F(t - (s - x)/c) / Z`` and
``w+(x, t) = w_in(t + d) - [x < s] F(t + (s - x)/c) / Z``, ``w_in(t) = -w_out(t - P) + Fterm(t) / Z``;
``v = (w+ + w-) / 2``, ``c u_x = (w- - w+) / 2``, energy density ``rhoA (w+^2 + w-^2) / 4``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .kernel.fields import invariants_into, w_out_into
from .kernel.records import Constants, Pieces

__all__ = ["Line", "w_out", "load", "w_in", "invariants", "pieces", "constants"]


@dataclass(frozen=True)
class Line:
    """The stored delay line and what evaluating it needs (arrays from :meth:`History.arrays`)."""

    t0: np.ndarray
    t1: np.ndarray
    a0: np.ndarray
    a1: np.ndarray
    C: np.ndarray
    D: np.ndarray
    omega: float
    phi: float
    q: float
    L: float
    c: float
    Z: float
    s: float
    from_rest: bool


def pieces(ln: Line) -> Pieces:
    """The line's pieces as the kernels take them."""
    return Pieces(ln.t0, ln.t1, ln.a0, ln.a1, ln.C, ln.D, ln.omega)


def constants(ln: Line) -> Constants:
    """The constants of the line's point evaluation (:func:`plbar.continuum.kernel.fields.point`)."""
    w, P = ln.omega, 2 * ln.L / ln.c
    d1, d2 = (ln.L - ln.s) / ln.c, (ln.L + ln.s) / ln.c
    return Constants(ln.L, ln.c, ln.Z, ln.s, P, math.cos(w * P), math.sin(w * P), math.cos(w * d1),
                     math.sin(w * d1), math.cos(w * d2), math.sin(w * d2), ln.phi, math.cos(ln.phi),
                     math.sin(ln.phi), ln.q, bool(ln.from_rest))


def w_out(ln: Line, t):
    """``w_out(t)``, right-continuous at the jumps; shape of ``t``."""
    t = np.asarray(t, float)
    flat = np.ascontiguousarray(t).ravel()
    out = np.empty_like(flat)
    w_out_into(pieces(ln), flat, out)
    return out.reshape(t.shape)


def load(ln: Line, t):
    """The load ``F(t) = q cos(omega t - phi)`` (0 before ``t = 0`` from rest)."""
    t = np.asarray(t, float)
    F = ln.q * np.cos(ln.omega * t - ln.phi)
    return np.where(t >= 0, F, 0.0) if ln.from_rest else F


def w_in(ln: Line, t):
    """``w_in(t)`` at the end: the reflected ``-w_out(t - 2L/c)`` plus the load crossed twice."""
    t = np.asarray(t, float)
    out = -w_out(ln, t - 2 * ln.L / ln.c)
    if ln.s < ln.L:
        out = out + (load(ln, t - (ln.L - ln.s) / ln.c) - load(ln, t - (ln.L + ln.s) / ln.c)) / ln.Z
    return out


def invariants(ln: Line, x, t):
    """``(w+, w-)`` at points ``x`` and times ``t`` (broadcast), taking right limits at ``x = s``."""
    x, t = np.broadcast_arrays(np.asarray(x, float), np.asarray(t, float))
    xf, tf = np.ascontiguousarray(x).ravel(), np.ascontiguousarray(t).ravel()
    wp, wm = np.empty_like(xf), np.empty_like(xf)
    invariants_into(pieces(ln), constants(ln), xf, tf, wp, wm)
    return wp.reshape(x.shape), wm.reshape(x.shape)
