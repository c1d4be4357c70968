"""Certified event search, compiled: step on while the margin provably stays positive.

**The margin and its Taylor model.**  In either state the margin is
``g(t) = c . eta(t) + cv . eta'(t) + rq cos(W t - phi)`` (``-R`` in state I, Eq. (4), with the
damper's share ``cv`` under Rayleigh damping; ``-x_c`` in state II, Eq. (5)); the state holds
while ``g >= 0``.  Its derivatives follow from the modal equation
``eta'' = f cos(W t - phi) - w^2 eta - 2 zeta w eta'``:
``eta^(k) = f W^(k-2) cos(W t - phi + (k-2) pi/2) - w^2 eta^(k-2) - 2 zeta w eta^(k-1)``.

**Remainder bound.**  For each mode the amplitude ``a = |(w eta, eta')|`` obeys
``|da/dt| <= |f|`` (damping only takes energy out), so over a step of length ``s`` it stays
below ``a + |f| s``; then ``|eta| <= a / w``, ``|eta'| <= a`` and, by the same recursion,
``|eta^(k)| <= |f| W^(k-2) + w^2 |eta^(k-2)| + 2 zeta w |eta^(k-1)|``.  Summed with the weights
this bounds ``|g^(K+1)|`` over the whole step.  Everything is scaled by ``Om = max(w_max, W)``
(``g^(k) / Om^k``), so that high orders stay finite.

**The certified step.**  Let ``k`` be the first order whose derivative is not round-off.  If
``g^(k) < 0`` the state ends here (an event).  Otherwise, dropping the lower orders
(round-off) and the positive higher ones,
``g(t + u) >= u^k [ g^(k)/k! - sum_{i>k} max(-g^(i), 0) u^(i-k)/i! - B u^(K+1-k)/(K+1)! ]``,
and the bracket decreases with ``u``: wherever it is positive, so is ``g`` on the whole step.
The largest such point of a geometric ladder (found by bisection, the bracket being monotone)
is a *certified* step: no crossing can hide in it, whatever happens between evaluated
points.  Near a simple crossing (``k = 0``, ``g' < 0``) a second certificate,
``g(t + u) >= g + g' u - B2 u^2 / 2`` with ``B2`` bounding ``|g''|`` over the step from the same
expansion, gives quadratic convergence onto the crossing from the left.  ``k`` tells a
zero-dwell impact (the reaction pulls at once: ``k = 0``, ``g < 0``) from a normal opening (the
gap grows like ``u^3``) and a bar at rest loaded far from its contact (the reaction vanishes to
order ``2 (N - 1)`` on the paper's chain) from a crossing.
"""

from __future__ import annotations

from math import cos, lgamma, sin, sqrt

import numpy as np

from .jit import jit

__all__ = ["ZERO", "SIGNIFICANT", "LADDER", "KMAX", "INV_FACT", "taylor", "decide_step"]

ZERO = 1e-13          #: |g| below ZERO * (size of its terms) is round-off: the crossing is located to this
SIGNIFICANT = 1e-9    #: a derivative counts when |g^(k)| > SIGNIFICANT * (size of its terms)
LADDER = 0.5 ** np.arange(0, 48)   #: step candidates, as fractions of the longest step
KMAX = 42             #: largest order of a Taylor model (+ 2)
INV_FACT = np.exp(-np.array([lgamma(i + 1.0) for i in range(KMAX + 2)]))   #: 1 / i!


@jit
def _cyc(c, s, i):
    """``cos(x + i pi / 2)`` from ``c, s = cos x, sin x``."""
    r = i & 3
    return c if r == 0 else (-s if r == 1 else (-c if r == 2 else s))


@jit
def taylor(c, rq, w, f, eta, vel, W, t, phi, s, K, d, scale, zeta, cv):
    """Scaled derivatives ``g^(k) / Om^k`` (``k = 0 .. K``) into ``d`` and their sizes into ``scale``.

    Returns ``(rem, Om)``: the bound of ``|g^(K+1)| / Om^(K+1)`` over a step of length ``s``, and ``Om``.
    ``scale[k]`` is the size of the terms that make ``g^(k)`` (through the recursion, so that a derivative
    that cancels to round-off is seen as such).  ``zeta, cv``: the damping ratios and the margin's weights on
    the velocities, or None (undamped; that code is then not compiled).
    """
    m = w.size
    Om = W
    for j in range(m):
        Om = max(Om, w[j])
    Wr, arg = W / Om, W * t - phi
    ca, sa = cos(arg), sin(arg)
    wk = 1.0
    for k in range(K + 1):
        d[k] = rq * wk * _cyc(ca, sa, k)
        scale[k] = abs(d[k])
        wk *= Wr
    rem = abs(rq) * wk
    for j in range(m):
        amp = sqrt((w[j] * eta[j]) ** 2 + vel[j] ** 2) + abs(f[j]) * s
        if zeta is None:
            rem += _mode(c[j], 0.0, w[j] / Om, f[j] / (Om * Om), 0.0, eta[j], vel[j] / Om, amp, w[j], Om, Wr, ca,
                         sa, K, False, d, scale)
        else:
            rem += _mode(c[j], cv[j] * Om, w[j] / Om, f[j] / (Om * Om), 2.0 * zeta[j] * w[j] / Om, eta[j],
                         vel[j] / Om, amp, w[j], Om, Wr, ca, sa, K, True, d, scale)
    return rem, Om


@jit
def _mode(cj, cvs, wr, load, damp, e0, e1, amp, wj, Om, Wr, ca, sa, K, damped, d, scale):
    """Add one mode's terms to ``d`` and ``scale``; return its share of the remainder bound."""
    top = K + 2 if damped else K + 1
    ep, e = e0, e1                         # e[k-2], e[k-1]
    mp, mg = abs(e0), abs(e1)
    bp, b = amp / wj, amp / Om
    wr2 = wr * wr
    d[0] += cj * e0
    scale[0] += abs(cj) * mp
    d[1] += cj * e1
    scale[1] += abs(cj) * mg
    if damped:
        d[0] += cvs * e1
        scale[0] += abs(cvs) * mg
    wk = 1.0                               # Wr^(k-2)
    for k in range(2, top + 1):
        if k < top:
            lk = load * wk * _cyc(ca, sa, k - 2)
            en = lk - wr2 * ep - damp * e
            mn = abs(lk) + wr2 * mp + damp * mg
            if k <= K:
                d[k] += cj * en
                scale[k] += abs(cj) * mn
            if damped:
                d[k - 1] += cvs * en
                scale[k - 1] += abs(cvs) * mn
            ep, e, mp, mg = e, en, mg, mn
        bn = abs(load) * wk + wr2 * bp + damp * b
        bp, b = b, bn
        wk *= Wr
    if damped:                              # b is b[K + 2], bp is b[K + 1]
        return abs(cj) * bp + abs(cvs) * b
    return abs(cj) * b


@jit
def _bracket(d, K, k, lead, R, v):
    """``lead - sum_{i>k} max(-g^(i), 0) v^(i-k)/i! - R v^(K+1-k)`` (Horner)."""
    acc = 0.0
    for j in range(K - k, 0, -1):
        acc = (acc + max(-d[k + j], 0.0) * INV_FACT[k + j]) * v
    return lead - acc - R * v ** (K + 1 - k)


@jit
def certified_step(d, K, k, lead, rem, vmax):
    """The largest step (scaled, up to ``vmax``, to a factor ``2^(1/4)``) over which ``g > 0`` is certain (0: none).

    ``lead`` is ``g^(k)/k!`` (or the shifted margin at ``k = 0``); ``rem`` bounds the scaled ``g^(K+1)``.
    """
    k = min(k, K)
    R = rem * INV_FACT[K + 1]
    n = LADDER.size
    if _bracket(d, K, k, lead, R, vmax) > 0:
        return vmax
    if not _bracket(d, K, k, lead, R, vmax * LADDER[n - 1]) > 0:
        return 0.0
    lo, hi = 0, n - 1                       # bracket fails at rung lo, holds at rung hi
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _bracket(d, K, k, lead, R, vmax * LADDER[mid]) > 0:
            hi = mid
        else:
            lo = mid
    v = vmax * LADDER[hi]
    for fac in (sqrt(2.0), 2.0 ** 0.25):    # refine between ladder rungs
        x = min(v * fac, vmax)
        if _bracket(d, K, k, lead, R, x) > 0:
            v = x
    return v


@jit
def quadratic_step(d, K, rem, v):
    """``rho`` with ``g + g' u - B2 u^2 / 2 > 0`` on ``[0, rho)``, ``B2`` bounding ``|g''|`` over ``[0, v]`` (scaled)."""
    B2, vj = 0.0, 1.0
    for j in range(K - 1):
        B2 += abs(d[2 + j]) * INV_FACT[j] * vj
        vj *= v
    B2 += rem * INV_FACT[K - 1] * vj
    g, g1 = max(d[0], 0.0), d[1]
    root = sqrt(g1 * g1 + 2.0 * B2 * g)
    if g1 > 0:
        return (g1 + root) / B2 if B2 > 0 else np.inf
    return 2.0 * g / (root - g1) if root - g1 > 0 else np.inf


@jit
def first_order(d, scale, K):
    """The first order whose derivative is not round-off (``K + 1`` where none is)."""
    for k in range(K + 1):
        if abs(d[k]) > (ZERO if k == 0 else SIGNIFICANT) * scale[k]:
            return k
    return K + 1


@jit
def decide_step(d, rem, scale, K, vmax, floor):
    """The decision at a point from its Taylor model: ``(event, step, found)`` (scaled step ``v = Om u``).

    * ``event``: the first significant derivative is negative (the state ends here);
    * ``step``: certified by :func:`certified_step` from that order, by :func:`quadratic_step` near a simple
      crossing (quadratic convergence onto it from the left), and, where the margin is round-off small but
      not crossing (``k > 0``, or no derivative significant at all), also for the margin shifted by its
      round-off level ``ZERO * max(scale, floor)`` (no crossing below that level is missed); ``floor`` is the
      problem's own size of the margin (a bar at rest has none of its own);
    * ``found``: some derivative up to the model's order is significant, or the shifted margin certified a step.
    """
    k = first_order(d, scale, K)
    found = k <= K
    event = found and d[k] < 0
    go = found and not event
    v = certified_step(d, K, k, d[k] * INV_FACT[k], rem, vmax) if go else 0.0
    if (go and k > 0) or not found:
        shifted = max(d[0], 0.0) + ZERO * max(scale[0], floor)
        v = max(v, certified_step(d, K, 0, shifted, rem, vmax))
    if go and k == 0 and d[1] < 0 and v < vmax:
        sig = min(2.0 * v, vmax)
        rho = quadratic_step(d, K, rem, sig)
        v = max(v, min(rho, sig) * (1 - 1e-15))
    return event, v, found or v > 0
