"""Certified event search: step on while the margin provably stays positive (pure functions).

At the current point the margin ``g`` of the state has the Taylor expansion
``g(t + u) = sum_k g^(k) u^k / k! + R``, ``|R| <= B u^(K+1) / (K+1)!`` over
the step (:func:`plbar.motion.margin.taylor`).  Let ``k`` be the first order
whose derivative is not round-off.  If ``g^(k) < 0`` the state ends here (an
event).  Otherwise, dropping the lower orders (round-off) and the positive
higher ones,

``g(t + u) >= u^k [ g^(k)/k! - sum_{i>k} max(-g^(i), 0) u^(i-k)/i! - B u^(K+1-k)/(K+1)! ]``,

and the bracket decreases with ``u``: wherever it is positive, so is ``g``
on the whole step.  The largest such point of a geometric ladder is a
*certified* step: no crossing can hide in it, whatever happens between
evaluated points.  Near a simple crossing (``k = 0``, ``g' < 0``) a second
certificate, ``g(t + u) >= g + g' u - B2 u^2 / 2`` with ``B2`` bounding
``|g''|`` over the step from the same expansion, gives quadratic convergence
onto the crossing from the left.

``k`` tells a zero-dwell impact (the reaction pulls at once: ``k = 0``,
``g < 0``) from a normal opening (the gap grows like ``u^3``: ``k = 3``), and
a bar started at rest with its load far from the contact (the reaction
vanishes to order ``2 (N - 1)`` on the paper's chain) from a crossing.
"""

from __future__ import annotations

from math import lgamma

import numpy as np

__all__ = ["ZERO", "SIGNIFICANT", "LADDER", "first_order", "certified_step", "quadratic_step", "decide_step"]

ZERO = 1e-13          #: |g| below ZERO * (size of its terms) is round-off: the crossing is located to this
SIGNIFICANT = 1e-9    #: a derivative counts when |g^(k)| > SIGNIFICANT * (size of its terms)
LADDER = 0.5 ** np.arange(0, 48)   #: step candidates, as fractions of the longest step


def _inv_factorials(n: int) -> np.ndarray:
    """``1 / i!`` for ``i = 0 .. n - 1`` (through ``lgamma``: no integer overflow at high orders)."""
    return np.exp(-np.array([lgamma(i + 1.0) for i in range(n)]))


def first_order(d, scale):
    """The first order ``k`` whose derivative is not round-off (``K + 1`` where none is); shape (B,)."""
    thr = np.full(d.shape[0], SIGNIFICANT)[:, None]
    thr[0] = ZERO
    sig = np.abs(d) > thr * scale
    return np.where(sig.any(axis=0), np.argmax(sig, axis=0), d.shape[0])


def _bracket(lead, coef, R, e_rem, v):
    """``lead - sum_j coef_j v^j - R v^e_rem`` (Horner; ``coef`` (J, B), ``v`` (B, L) or (B,))."""
    vv = v if v.ndim == 2 else v[:, None]
    acc = np.zeros_like(vv)
    for j in range(coef.shape[0] - 1, -1, -1):
        acc = (acc + coef[j][:, None]) * vv
    out = lead[:, None] - acc - R[:, None] * vv ** e_rem[:, None]
    return out if v.ndim == 2 else out[:, 0]


def certified_step(d, rem, k, vmax):
    """The largest step (scaled time ``v = Om u``, up to ``vmax``, to a factor ``2^(1/4)``) over which ``g > 0`` is certain.

    Parameters
    ----------
    d : ndarray, shape (K + 1, B)
    rem : ndarray, shape (B,)
    k : ndarray of int, shape (B,)
        First significant order (its derivative positive).
    vmax : ndarray, shape (B,)

    Returns
    -------
    ndarray, shape (B,)
        Scaled step; 0 where not even the smallest candidate is certified.
    """
    K = d.shape[0] - 1
    B = d.shape[1]
    inv_fact = _inv_factorials(K + 2)
    rows = np.arange(B)
    kk = np.minimum(k, K)
    lead = d[kk, rows] * inv_fact[kk]                                   # g^(k)/k!
    j = np.arange(1, K + 1)[:, None]                                     # powers of v in the bracket
    src = kk[None, :] + j                                                # derivative order of each power
    valid = src <= K
    coef = np.where(valid, np.maximum(-d[np.minimum(src, K), rows], 0.0) * inv_fact[np.minimum(src, K + 1)], 0.0)
    R = rem * inv_fact[K + 1]
    e_rem = (K + 1 - kk).astype(float)
    v = vmax[:, None] * LADDER[None, :]
    ok = _bracket(lead, coef, R, e_rem, v) > 0
    first = np.argmax(ok, axis=1)
    good = ok.any(axis=1)
    lo = np.where(good, v[rows, first], 0.0)
    for f in (np.sqrt(2.0), 2.0 ** 0.25):                               # refine between ladder rungs
        hi = np.minimum(lo * f, vmax)
        take = good & (first > 0) & (_bracket(lead, coef, R, e_rem, hi) > 0)
        lo = np.where(take, hi, lo)
    return lo


def quadratic_step(d, rem, v):
    """``rho`` with ``g + g' u - B2 u^2 / 2 > 0`` on ``[0, rho)``, ``B2`` bounding ``|g''|`` over ``[0, v]`` (scaled).

    Valid where the returned value is at most ``v``; ``g >= 0`` is taken as given.
    """
    K = d.shape[0] - 1
    inv = _inv_factorials(K + 1)
    j = np.arange(K - 1)[:, None]
    B2 = np.sum(np.abs(d[2:]) * inv[:K - 1, None] * v ** j, axis=0) + rem * inv[K - 1] * v ** (K - 1)
    g, g1 = np.maximum(d[0], 0.0), d[1]
    root = np.sqrt(g1 * g1 + 2.0 * B2 * g)
    with np.errstate(divide="ignore", invalid="ignore"):
        up = np.divide(g1 + root, B2, out=np.full(g.shape, np.inf), where=B2 > 0)
        down = np.divide(2.0 * g, root - g1, out=np.full(g.shape, np.inf), where=root - g1 > 0)
    return np.where(g1 > 0, up, down)


def decide_step(d, rem, scale, vmax, floor=0.0):
    """The decision at a point from its Taylor model: ``(event, step, found)`` (scaled step ``v = Om u``).

    * ``event``: the first significant derivative is negative (the state ends here);
    * ``step``: certified by :func:`certified_step` from that order, by :func:`quadratic_step` near a simple
      crossing (``k = 0``, ``g' < 0``: quadratic convergence onto it from the left), and, where the margin is
      round-off small but not crossing (``k > 0``, or no derivative significant at all), also for the margin
      shifted by its round-off level ``ZERO * max(scale, floor)`` (no crossing below that level is missed):
      where the margin vanishes to a high order (a bar at rest, loaded far from its contact) this certifies
      long steps instead of tiny ones; ``floor`` is the problem's own size of the margin (a bar at rest has
      none of its own);
    * ``found``: some derivative up to the model's order is significant, or the shifted margin certified a step.
    """
    K = d.shape[0] - 1
    k = first_order(d, scale)
    rows = np.arange(d.shape[1])
    found = k <= K
    event = found & (d[np.minimum(k, K), rows] < 0)
    go = found & ~event
    v = np.where(go, certified_step(d, rem, k, vmax), 0.0)
    flat = (go & (k > 0)) | ~found
    if flat.any():
        ds = d[:, flat].copy()
        ds[0] = np.maximum(ds[0], 0.0) + ZERO * np.maximum(scale[0, flat], floor if np.ndim(floor) == 0 else
                                                            np.asarray(floor)[flat])
        v[flat] = np.maximum(v[flat], certified_step(ds, rem[flat], np.zeros(int(flat.sum()), int), vmax[flat]))
    near = go & (k == 0) & (d[1] < 0) & (v < vmax)
    if near.any():
        sig = np.minimum(2.0 * v[near], vmax[near])
        rho = quadratic_step(d[:, near], rem[near], sig)
        v[near] = np.maximum(v[near], np.minimum(rho, sig) * (1 - 1e-15))
    return event, v, found | (v > 0)
