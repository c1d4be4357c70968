"""The records the continuum kernels read the delay line and the bar through (plain NamedTuples: no numba here).

:class:`Pieces` is the stored ``w_out`` (a piece ``i``: linear from ``a0[i]`` at ``t0[i]`` to ``a1[i]`` at
``t1[i]``, plus ``C[i] cos(omega t) + D[i] sin(omega t)``); :class:`Constants` the bar, the load and the rotations
that the point evaluation (:func:`.fields.point`) takes, computed once per line
(:func:`plbar.continuum.fields.constants`).  :class:`MarchConstants` and :class:`MarchScratch` are what every grid
step of the march (:func:`.march.step`) takes, made by :func:`.march.march`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Constants", "MarchConstants", "MarchScratch", "Pieces"]


class Pieces(NamedTuple):
    """The stored delay line: the pieces' ends ``t0, t1``, linear parts ``a0, a1``, harmonic parts ``C, D`` (all
    shape ``(pieces,)``) at the load's frequency ``omega``."""

    t0: np.ndarray
    t1: np.ndarray
    a0: np.ndarray
    a1: np.ndarray
    C: np.ndarray
    D: np.ndarray
    omega: float


class Constants(NamedTuple):
    """The bar (length ``L``, wave speed ``c``, impedance ``Z``), the load (at ``s``, amplitude ``q``, phase
    ``phi``, ``from_rest``: zero before ``t = 0``) and the rotations of the point evaluation: ``P = 2 L / c`` and
    ``cP, sP`` of ``omega P``, ``c1, s1`` and ``c2, s2`` of ``omega (L -+ s) / c``, ``cphi, sphi`` of ``phi``."""

    L: float
    c: float
    Z: float
    s: float
    P: float
    cP: float
    sP: float
    c1: float
    s1: float
    c2: float
    s2: float
    phi: float
    cphi: float
    sphi: float
    q: float
    from_rest: bool


class MarchConstants(NamedTuple):
    """The march's constants: the bar (``L, c, Z``, the end mass ``m``), the load (at ``s``, ``q``, ``omega``,
    ``phi``), the grid step ``dt``, ``cr, sr`` of ``omega 2 L / c`` (the delay's rotation), the load's delays
    ``d1, d2 = (L -+ s) / c``, the held state ``hold`` (0 none, 1 closed, 2 open), ``from_rest`` and ``at_end``
    (the load acts on the end: ``s = L``)."""

    L: float
    c: float
    Z: float
    m: float
    s: float
    q: float
    omega: float
    phi: float
    dt: float
    cr: float
    sr: float
    d1: float
    d2: float
    hold: int
    from_rest: bool
    at_end: bool


class MarchScratch(NamedTuple):
    """A step's work space: the period cuts in it ``cutv``, its sorted breakpoints ``pts`` (``pjump``, ``pcut``:
    whether each is a jump, a cut) and the event searches' samples ``taus, vals``."""

    cutv: np.ndarray
    pts: np.ndarray
    pjump: np.ndarray
    pcut: np.ndarray
    taus: np.ndarray
    vals: np.ndarray
