"""The orders of a Taylor model of the margin (:mod:`.certify`): ``1 / i!``, and the small but real orders.

A derivative of the margin is *significant* above ``SIGNIFICANT`` (1e-9) times the size of its terms and
round-off below ``REAL`` (1e-13).  An order between the two, below the first significant one, is small but real:
a P2 bar's contact before the load's front arrives moves at 1e-10 of the size of its terms (issue 29).
:func:`.certify.decide_step` does not drop such an order: :func:`real_order` finds it, :func:`within` cuts a step
where the dropped orders could pull the margin down by its round-off level (:func:`dropped`).
"""

from __future__ import annotations

from math import lgamma

import numpy as np

from .jit import jit

__all__ = ["INV_FACT", "KMAX", "REAL", "dropped", "real_order", "within"]

KMAX = 42             #: largest order of a Taylor model (+ 2)
INV_FACT = np.exp(-np.array([lgamma(i + 1.0) for i in range(KMAX + 2)]))   #: 1 / i!
REAL = 1e-13          #: a derivative is not round-off when ``|g^(k)|`` exceeds REAL times the size of its terms


@jit
def real_order(d, scale, k):
    """The first order in ``1 .. k - 1`` whose derivative is not round-off (above ``REAL`` times the size of its
    terms), ``k`` where none is: an order below the first significant one (:func:`.certify.first_order`) that is
    small but real (issue 29: an FE bar's contact before the load's front arrives moves at 1e-10 of the size of
    its terms)."""
    for i in range(1, k):
        if abs(d[i]) > REAL * scale[i]:
            return i
    return k


@jit
def dropped(d, k, v):
    """``sum_{1 <= i < k} max(-g^(i), 0) v^i / i!``: how far the orders dropped below ``k`` can pull the margin down
    over ``[0, v]`` (increasing and convex in ``v``)."""
    out = 0.0
    for i in range(k - 1, 0, -1):
        out = (out + max(-d[i], 0.0) * INV_FACT[i]) * v
    return out


@jit
def within(d, k, v, level):
    """The largest ``x <= v`` over which the orders dropped below ``k`` pull the margin down by at most ``level``
    (:func:`dropped`; Newton from the right on the increasing convex function, then checked)."""
    if dropped(d, k, v) <= level:
        return v
    x = v
    for _ in range(60):
        p, dp = 0.0, 0.0
        for i in range(k - 1, 0, -1):
            a = max(-d[i], 0.0) * INV_FACT[i]
            dp = dp * x + p
            p = p * x + a
        p, dp = p * x, p + x * dp                  # (sum a_i x^i and its derivative)
        if not dp > 0:
            return 0.0
        xn = x - (p - level) / dp
        if not xn < x:
            break
        x = xn
    for _ in range(20):
        if dropped(d, k, x) <= level:
            return x
        x *= 0.5
    return 0.0
