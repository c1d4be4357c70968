"""The records the continuum kernels read the delay line and the bar through (plain NamedTuples: no numba here).

:class:`Pieces` is the stored ``w_out`` (a piece ``i``: linear from ``a0[i]`` at ``t0[i]`` to ``a1[i]`` at
``t1[i]``, plus ``C[i] cos(omega t) + D[i] sin(omega t)``); :class:`Constants` the bar, the load and the rotations
that the point evaluation (:func:`.fields.point`) takes, computed once per line
(:func:`plbar.continuum.fields.constants`).  The march (:func:`.march.march`) is given the bar, the load and the
start (:class:`MarchBar`, :class:`MarchLoad`, :class:`MarchStart`); :class:`MarchConstants`, :class:`MarchScratch`
and :class:`MarchState` are what every grid step of it (:func:`.march.step`) takes, made by :func:`.march.march`;
:class:`Incoming` is the incoming invariant over a part of a step (:func:`.march.end_over`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Constants", "Incoming", "MarchBar", "MarchConstants", "MarchLoad", "MarchScratch", "MarchStart",
           "MarchState", "Pieces"]


class Pieces(NamedTuple):
    """The stored delay line: the pieces' ends ``t0, t1``, linear parts ``a0, a1``, harmonic parts ``C, D`` (all
    shape ``(pieces,)``) at the load's frequency ``omega`` (the merge's: rows of the march's record, the times local
    to their grid step)."""

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


class MarchBar(NamedTuple):
    """The bar of a march: length ``L``, wave speed ``c``, impedance ``Z``, the end mass ``m`` and the load's
    position ``s``."""

    L: float
    c: float
    Z: float
    m: float
    s: float


class MarchLoad(NamedTuple):
    """The load ``q cos(omega t - phi)`` of a march, zero before ``t = 0`` if ``from_rest``."""

    q: float
    omega: float
    phi: float
    from_rest: bool


class MarchStart(NamedTuple):
    """The start of a march: the end's ``u, v`` and contact ``stuck``, and the past ``w_out = C cos + D sin``."""

    u: float
    v: float
    stuck: bool
    C: float
    D: float


class MarchState(NamedTuple):
    """What the march carries from step to step, written in place: ``ix`` = pieces, events, strobes, amp entries,
    switches in this step; ``st`` = the end's ``u, v``, stuck and a pending jump; ``amp`` the largest ``-u`` per
    period; ``strobes`` (3, periods) the end at the period boundaries; ``first`` the record's first piece of every
    step."""

    ix: np.ndarray
    st: np.ndarray
    amp: np.ndarray
    strobes: np.ndarray
    first: np.ndarray


class Incoming(NamedTuple):
    """The incoming invariant over a part of a step, ``w_in = l0 + l1 tau + C cos(omega t) + D sin(omega t)``, and
    ``LC, LD`` of the load on the end (zero unless it acts there)."""

    l0: float
    l1: float
    C: float
    D: float
    LC: float
    LD: float
