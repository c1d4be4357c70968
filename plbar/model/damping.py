"""Inherent (Rayleigh) damping of the bar: ``C = alpha M + beta K`` (FORMULATION §8).

Both states take the same ``C`` (state I its ``C_rr``), so each stays diagonal in
its own undamped modes with the modal damping ratio

``zeta_j = alpha / (2 w_j) + beta w_j / 2``,

and the contact reaction ``R = (M x'' + C x' + K x - q)_c`` is defined without
ambiguity.  Structural engineers specify Rayleigh damping by one ratio at two
frequencies: :func:`rayleigh_from_ratio`.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..util.check import show

__all__ = ["rayleigh_from_ratio", "rayleigh_ratio", "check_rayleigh", "outside_fit", "FIT_FACTOR"]

#: forcing periods farther than this factor outside the fit's interval ``[T_A, T_B]`` get a warning
FIT_FACTOR = 2.0


def rayleigh_ratio(alpha: float, beta: float, w):
    """The damping ratio of Rayleigh damping at circular frequency ``w``: ``alpha / (2 w) + beta w / 2``."""
    w = np.asarray(w, float)
    return alpha / (2.0 * w) + beta * w / 2.0


def rayleigh_from_ratio(xi, T_a, T_b) -> tuple[float, float]:
    """``(alpha, beta)`` of the Rayleigh damping with ratio ``xi`` at the periods ``T_a`` and ``T_b``.

    With ``w = 2 pi / T``: ``alpha = 2 xi w_a w_b / (w_a + w_b)``, ``beta = 2 xi / (w_a + w_b)``;
    between the two periods the ratio is a little below ``xi``, outside above it.

    Parameters
    ----------
    xi : float
        Damping ratio, ``0 <= xi < 1`` (e.g. 0.02 for 2 %).
    T_a, T_b : float
        Two different periods (> 0), typically bracketing the forcing periods of interest.

    Examples
    --------
    >>> a, b = rayleigh_from_ratio(0.02, 8.0, 12.0)
    >>> round(float(rayleigh_ratio(a, b, 2 * math.pi / 8.0)), 12)
    0.02
    """
    vals = []
    for name, v in (("damping ratio xi", xi), ("period T_a", T_a), ("period T_b", T_b)):
        try:
            v = float(v)
        except (TypeError, ValueError):
            raise InputError(f"{name} = {show(v)} must be a number") from None
        vals.append(v)
    xi, T_a, T_b = vals
    if not (math.isfinite(xi) and 0.0 <= xi < 1.0):
        raise InputError(f"damping ratio xi = {show(xi)} is not allowed; give a ratio in [0, 1) (0.02 for 2 %)")
    for name, T in (("T_a", T_a), ("T_b", T_b)):
        if not (math.isfinite(T) and T > 0):
            raise InputError(f"period {name} = {show(T)} is not allowed; it must be finite and > 0")
    if T_a == T_b:
        raise InputError(f"the two periods are equal ({show(T_a)}); give two different periods (Rayleigh damping "
                         "has two parameters), or give (alpha, beta) directly with rayleigh=(alpha, beta)")
    wa, wb = 2 * math.pi / T_a, 2 * math.pi / T_b
    return 2 * xi * wa * wb / (wa + wb), 2 * xi / (wa + wb)


def check_rayleigh(rayleigh) -> tuple[float, float] | None:
    """A validated ``(alpha, beta)`` (floats ``>= 0``), or None for no damping (None or ``(0, 0)``)."""
    if rayleigh is None:
        return None
    bad = (f"rayleigh = {show(rayleigh)} must be a pair (alpha, beta) of finite numbers >= 0 "
           "(C = alpha M + beta K; see plbar.rayleigh_from_ratio)")
    if isinstance(rayleigh, (str, bytes, dict)):
        raise InputError(bad)
    try:
        a, b = (float(v) for v in rayleigh)
    except (TypeError, ValueError):
        raise InputError(bad) from None
    if not (math.isfinite(a) and math.isfinite(b) and a >= 0 and b >= 0):
        raise InputError(bad)
    return None if a == 0 and b == 0 else (a, b)


def outside_fit(xi, at, T, factor: float = FIT_FACTOR) -> str | None:
    """Why the Rayleigh damping of ratio ``xi`` fitted at the periods ``at`` is not that ratio at the forcing
    periods ``T``, or None where every ``T`` is within ``factor`` of ``[T_A, T_B]``.

    Below ``T_A / factor`` the stiffness term ``beta w / 2`` grows, above ``factor T_B`` the mass term
    ``alpha / (2 w)``: the text names the forcing period farthest out and the ratio there.
    """
    lo, hi = sorted(float(t) for t in at)
    T = np.asarray(T, float).ravel()
    out = T[(T < lo / factor) | (T > factor * hi)]
    if not out.size:
        return None
    far = out[np.argmax(np.maximum(lo / out, out / hi))]
    a, b = rayleigh_from_ratio(xi, lo, hi)
    z = float(rayleigh_ratio(a, b, 2 * math.pi / far))
    term = "mass term alpha / (2 w)" if far > hi else "stiffness term beta w / 2"
    return (f"the Rayleigh damping fitted to {xi:g} at T = {lo:.4g} and {hi:.4g} is evaluated at forcing periods "
            f"up to a factor {max(lo / far, far / hi):.3g} outside them: its ratio at T = {far:.4g} is {z:.3g}, "
            f"dominated by the {term} (zeta = alpha / (2 w) + beta w / 2); fit --at around the forcing periods")
