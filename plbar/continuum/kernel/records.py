"""The records the continuum kernels read the delay line and the bar through (plain NamedTuples: no numba here).

:class:`Pieces` is the stored ``w_out`` (a piece ``i``: linear from ``a0[i]`` at ``t0[i]`` to ``a1[i]`` at
``t1[i]``, plus ``C[i] cos(omega t) + D[i] sin(omega t)``); :class:`Constants` the bar, the load and the rotations
that the point evaluation (:func:`.fields.point`) takes, computed once per line
(:func:`plbar.continuum.fields.constants`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Constants", "Pieces"]


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
