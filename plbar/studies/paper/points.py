"""Exact path points of the paper's chain: the red and green sample points and the point at a given period.

The paper's sample points (Fig. 2b) are printed to four digits off its scan grid, so they lie near, not on,
the ``D = 0`` curves (FORMULATION section 6).  :func:`exact_point` puts them on the path at the paper's
``T^I`` (``T^II`` from ``D = 0`` on a short bracket, ``phi`` exact, the admissible one of ``phi`` and
``phi + pi``); :func:`point_at_period` does the same at a given total period ``T = T^I + T^II``.  Figures
2-6 and ``examples/paper_sec41.py`` mark and print these points.
"""

from __future__ import annotations

import numpy as np

__all__ = ["PAPER_POINTS", "exact_point", "point_at_period"]

#: the paper's sample points ``(T1, T2, phi)``: red on path 1, green on path 2 (Fig. 2b)
PAPER_POINTS = {"red": (1.7748, 8.1525, 3.5495), "green": (2.3876, 9.8894, 4.8050)}


def _admissible(prob, T1: float, T2: float):
    """The admissible orbit of ``phi`` and ``phi + pi`` at an exact ``(T1, T2)`` of ``D = 0``."""
    from ...response import check, coefficients, orbits, phase

    phi0 = float(phase(coefficients(prob, [T1], [T2]))[0])
    orb = orbits(prob, [T1, T1], [T2, T2], [phi0, phi0 + np.pi])
    ok = np.flatnonzero(check(orb).ok)
    if not ok.size:
        raise ValueError(f"no admissible orbit at T1 = {T1:.6g}, T2 = {T2:.6g}")
    return orb.take([int(ok[0])])


def exact_point(prob, T1: float, T2_guess: float, width: float = 0.02):
    """The path point at ``T1`` whose ``T2`` (``D = 0``) lies within ``width`` of ``T2_guess``.

    Parameters
    ----------
    prob : plbar.Problem
        The system and load (e.g. ``plbar.solve().paths.prob``).
    T1, T2_guess : float
        ``T^I`` of the point and a guess of its ``T^II`` (the paper's rounding).
    width : float
        Half-width of the bracket of ``T^II``.

    Returns
    -------
    plbar.Orbits
        The single admissible orbit (``T1``, ``T2``, ``phi``, ``T`` exact to round-off).
    """
    from scipy.optimize import brentq  # on use: importing scipy.optimize takes 0.13 s

    from ...paths.continuation import G

    T2 = brentq(lambda x: G(prob, np.array([T1]), np.array([x]))[0], T2_guess - width, T2_guess + width,
                xtol=1e-15, rtol=1e-15)
    return _admissible(prob, float(T1), float(T2))


def point_at_period(prob, T: float, T1_guess: float, width: float = 0.02):
    """The path point of total period ``T`` (``T^I + T^II = T``) whose ``T^I`` lies within ``width`` of ``T1_guess``.

    Parameters
    ----------
    prob : plbar.Problem
        The system and load.
    T : float
        The forcing period.
    T1_guess, width : float
        The bracket ``T1_guess -+ width`` of ``T^I`` (take ``T1_guess`` from the nearest computed path point).

    Returns
    -------
    plbar.Orbits
        The single admissible orbit.
    """
    from scipy.optimize import brentq  # on use: importing scipy.optimize takes 0.13 s

    from ...paths.continuation import G

    T1 = brentq(lambda x: G(prob, np.array([x]), np.array([T - x]))[0], T1_guess - width, T1_guess + width,
                xtol=1e-15, rtol=1e-15)
    return _admissible(prob, float(T1), float(T - T1))
