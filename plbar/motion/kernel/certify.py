"""Certified event search, compiled: step on while the margin provably stays positive.

**The margin and its Taylor model.**  In either state the margin is
``g(t) = c . eta(t) + cv . eta'(t) + rq cos(W t - phi)`` (``-R`` in state I, Eq. (4), with the
damper's share ``cv`` under Rayleigh damping; ``-x_c`` in state II, Eq. (5)); the state holds
while ``g >= 0``.  Its derivatives follow from the modal equation
``eta'' = f cos(W t - phi) + g - w^2 eta - 2 zeta w eta'`` (``g`` a constant load's acceleration, on a rigid-body
mode only): ``eta^(k) = f W^(k-2) cos(W t - phi + (k-2) pi/2) - w^2 eta^(k-2) - 2 zeta w eta^(k-1)``, plus ``g`` at
``k = 2``.

**Remainder bound.**  For each mode the amplitude ``a = |(w eta, eta')|`` obeys
``|da/dt| <= |f| + |g|`` (damping only takes energy out), so over a step of length ``s`` it stays
below ``a + |f| s``; then ``|eta| <= a / w``, ``|eta'| <= a`` and, by the same recursion,
``|eta^(k)| <= |f| W^(k-2) + w^2 |eta^(k-2)| + 2 zeta w |eta^(k-1)|``.  Summed with the weights
this bounds ``|g^(K+1)|`` over the whole step.  Everything is scaled by ``Om = max(w_max, W)``
(``g^(k) / Om^k``), so that high orders stay finite.

**The certified step.**  Let ``k`` be the first order whose derivative is not round-off.  If
``g^(k) < 0`` the state ends here (an event).  Otherwise, dropping the lower orders (round-off),
``g(t + u) >= u^k q(u)`` with the polynomial
``q(u) = g^(k)/k! + sum_{k<i<=K} g^(i) u^(i-k)/i! - B u^(K+1-k)/(K+1)!``
(Taylor's theorem with the remainder bound).  The step goes to the first root of ``q``,
certified: re-expanded about the current point, ``q`` is bounded below by its constant term
minus its negative terms, a concave decreasing function whose root is found by Newton from the
right and checked; every move to such a root is certified, and near a simple root the moves
are Newton steps from the left, so a few of them reach the root of ``q`` (no function
evaluation: ``q`` is a polynomial).  Near a crossing the next round, from a point whose model
has a tiny remainder, lands on the crossing to round-off.  ``k`` tells a zero-dwell impact (the
reaction pulls at once: ``k = 0``, ``g < 0``) from a normal opening (the gap grows like ``u^3``)
and a bar at rest loaded far from its contact (the reaction vanishes to order ``2 (N - 1)`` on
the paper's chain) from a crossing.

**Small but real lower orders.**  "Significant" (``SIGNIFICANT`` of the size of a derivative's
terms) is far above round-off (``REAL``).  An order between the two below ``k`` is real: a P2
bar's contact before the load's front arrives moves at 1e-10 of the size of its terms (issue 29).
Such an order is not dropped: the step from ``k`` is cut where the dropped orders' negative parts
could pull the margin down by its round-off level, and ``g^(k) < 0`` is no event where the first
real order is positive (the margin grows first: after an opening the contact's free acceleration
``a_c = lambda / S`` has the sign of the reaction that opened it, whatever a higher order says).
Without either, a step crossed such an opening, and the free state then decided an impact at once
against its real positive acceleration: impacts and openings at one instant until the chatter
guard.  Where no order lies in that band the decision and the step are those of before, bit for bit.
"""

from __future__ import annotations

from math import exp, log, sqrt

from .data import Scaled
from .jit import jit
from .orders import INV_FACT, KMAX, REAL, real_order, within

__all__ = [
    "INV_FACT",
    "KMAX",
    "MAX_SHIFTS",
    "REAL",
    "SIGNIFICANT",
    "ZERO",
    "bracket",
    "decide_step",
    "first_order",
    "polynomial_step",
    "real_order",
    "step_from",
    "taylor",
]

ZERO = 1e-13          #: ``|g|`` below ZERO times the size of its terms is round-off: the crossing is located to this
SIGNIFICANT = 1e-9    #: a derivative counts when ``|g^(k)|`` exceeds SIGNIFICANT times the size of its terms
MAX_SHIFTS = 2        #: re-expansions of the lower bound per step (its first root is reached in a few near a crossing)


@jit
def _cyc(c, s, i):
    """``cos(x + i pi / 2)`` from ``c, s = cos x, sin x``."""
    r = i & 3
    return c if r == 0 else (-s if r == 1 else (-c if r == 2 else s))


@jit
def taylor(modes, damp, eta, vel, load, s, K, d, scale):
    """Scaled derivatives ``g^(k) / Om^k`` (``k = 0 .. K``) into ``d`` and their sizes into ``scale``.

    The margin is ``c . eta + cv . eta' + rq cos(W t - phi) + rs sin(W t - phi) + g0`` at the point whose modal state
    is ``eta, vel``: ``modes`` (:class:`.data.Modes`) its modes and weights ``c``, ``damp`` (:class:`.data.Damping`)
    their damping ratios and the weights ``cv`` on the velocities, or None (undamped; that code is then not
    compiled), ``load`` (:class:`.data.LoadTerm`) its load term (``rs = 0`` but for the low part of a split model,
    :mod:`.split`).  Returns ``(rem, Om)``: the bound of ``|g^(K+1)| / Om^(K+1)`` over a step of length ``s``, and
    ``Om``.  ``scale[k]`` is the size of the terms that make ``g^(k)`` (through the recursion, so that a derivative
    that cancels to round-off is seen as such; the load's terms by their amplitude: at a zero of ``cos(W t - phi)``
    its value is the round-off of the phase, not a size).
    """
    c, w, f, gr = modes.c, modes.w, modes.f, modes.g
    W, ca, sa, rq, rs, g0 = load
    m = w.size
    Om = W
    for j in range(m):
        Om = max(Om, w[j])
    Wr = W / Om
    wk = 1.0
    for k in range(K + 1):
        d[k] = wk * (rq * _cyc(ca, sa, k) + rs * _cyc(ca, sa, k - 1))
        scale[k] = wk * (abs(rq) + abs(rs))    # a sinusoid's round-off is its amplitude's, not its value's
        wk *= Wr
    d[0] += g0                                 # a gap's constant (0 without one: no double changes)
    scale[0] += abs(g0)
    rem = (abs(rq) + abs(rs)) * wk
    for j in range(m):
        amp = sqrt((w[j] * eta[j]) ** 2 + vel[j] ** 2) + (abs(f[j]) + abs(gr[j])) * s
        # |eta| over the step: amp / w, or for a rigid-body mode (w = 0) |eta| + amp s (it enters only times w^2)
        b0 = amp / w[j] if w[j] != 0.0 else abs(eta[j]) + amp * s
        if damp is None:
            sm = Scaled(c[j], 0.0, w[j] / Om, f[j] / (Om * Om), 0.0, eta[j], vel[j] / Om, b0, amp / Om,
                        gr[j] / (Om * Om))
            rem += _mode(sm, Wr, ca, sa, K, False, d, scale)
        else:
            sm = Scaled(c[j], damp.cv[j] * Om, w[j] / Om, f[j] / (Om * Om), 2.0 * damp.zeta[j] * w[j] / Om, eta[j],
                        vel[j] / Om, b0, amp / Om, gr[j] / (Om * Om))
            rem += _mode(sm, Wr, ca, sa, K, True, d, scale)
    return rem, Om


@jit
def _mode(sm, Wr, ca, sa, K, damped, d, scale):
    """Add the terms of one mode (:class:`.data.Scaled`) to ``d`` and ``scale``; return its share of the remainder
    bound (``Wr = W / Om``, ``ca, sa = cos, sin(W t - phi)``)."""
    cj, cvs, wr, load, damp, e0, e1, acc = sm.c, sm.cv, sm.w, sm.f, sm.damp, sm.eta, sm.v, sm.g
    top = K + 2 if damped else K + 1
    ep, e = e0, e1                         # e[k-2], e[k-1]
    mp, mg = abs(e0), abs(e1)
    bp, b = sm.b0, sm.b1
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
        ga = acc if k == 2 else 0.0          # a constant acceleration: in eta'' alone (0 but on a loaded rigid mode)
        if k < top:
            lk = load * wk * _cyc(ca, sa, k - 2)
            en = lk + ga - wr2 * ep - damp * e
            mn = abs(load) * wk + abs(ga) + wr2 * mp + damp * mg
            if k <= K:
                d[k] += cj * en
                scale[k] += abs(cj) * mn
            if damped:
                d[k - 1] += cvs * en
                scale[k - 1] += abs(cvs) * mn
            ep, e, mp, mg = e, en, mg, mn
        bn = abs(load) * wk + abs(ga) + wr2 * bp + damp * b
        bp, b = b, bn
        wk *= Wr
    if damped:                              # b is b[K + 2], bp is b[K + 1]
        return abs(cj) * bp + abs(cvs) * b
    return abs(cj) * b


@jit
def _below(t, n, h):
    """The monotone lower bound ``b(h) = s_0 - sum_{i>=1} max(-s_i, 0) h^i`` of ``sum s_i h^i``, and ``-b'(h)``, from
    ``t = (s_0, max(-s_1, 0), ..., max(-s_n, 0))``."""
    q, dq = 0.0, 0.0
    for i in range(n, 0, -1):
        dq = dq * h + q
        q = q * h + t[i]
    return t[0] - h * q, q + h * dq


@jit
def _monotone_step(s, n, H):
    """The largest ``h <= H`` with ``b(h) > 0`` (:func:`_below`; ``b`` is concave and decreasing), 0 if none
    (``s`` has room for ``2 (n + 1)`` entries: the negative parts go in the second half).

    With ``P = s_0 - b`` (a sum of monomials with non-negative coefficients), ``log P`` is a convex, increasing
    function of ``y = log h`` (a log-sum-exp), nearly linear where one monomial dominates: Newton on
    ``log P(e^y) = log s_0`` converges onto the root monotonically from the right in a few steps.  Near a
    simple root the linear term decides: plain Newton from its root, to full precision (the step onto a
    crossing); elsewhere from the remainder term's root, to 1e-6 (both start right of the root).  The step
    taken is just left of the root, where ``b > 0`` is checked.
    """
    t = s[n + 1:]                              # the negative parts, once
    t[0] = s[0]
    for i in range(1, n + 1):
        t[i] = max(-s[i], 0.0)
    b, db = _below(t, n, H)
    if b > 0:
        return H
    near = s[1] < 0 and s[0] < -s[1] * H
    if near:                                   # near a simple root the linear term decides: plain Newton
        h, tol = s[0] / -s[1], 1e-13
        b, db = _below(t, n, h)
        near = b > -s[0]
    else:
        h, tol = min(H, (s[0] / -s[n]) ** (1.0 / n)), 1e-3
        b, db = _below(t, n, h)
    for _ in range(60):
        if b > 0 or not db > 0:
            break
        if near:
            x = h + b / db                     # b < 0: x < h, and (concave) still right of the root
        else:                                  # Newton on log(s_0 - b) = log(s_0) in y = log h
            P = s[0] - b
            x = h * exp(-log(P / s[0]) * P / (h * db))
        done = not h - x > tol * h
        h = x
        b, db = _below(t, n, h)
        if done:
            break
    back = 2.0 * max(tol, 1e-15)              # the root is within tol of h
    for _ in range(20):
        x = h * (1.0 - back)
        if _below(t, n, x)[0] > 0:
            return x
        back *= 8.0
    return 0.0


@jit
def _shift(s, n, h):
    """Re-expand ``sum s_i x^i`` about ``x = h`` in place (Taylor shift)."""
    for i in range(n):
        for j in range(n - 1, i - 1, -1):
            s[j] += h * s[j + 1]


@jit
def polynomial_step(s, n, vmax):
    """The largest ``a <= vmax`` with ``sum_{i<=n} s_i v^i > 0`` on ``[0, a]`` certified (``s_0 > 0``); ``s`` is used
    as work space and has room for ``2 (n + 1)`` entries.

    Each round takes the monotone lower bound of the polynomial re-expanded about the current point
    (:func:`_monotone_step`; every step is certified by it) and moves there: near a simple root this is a
    Newton step from the left (quadratic convergence onto the root of the polynomial), far from one it steps
    over the polynomial's dips as far as its negative terms allow.
    """
    a = 0.0
    for _ in range(MAX_SHIFTS):
        H = vmax - a
        if not H > 0:
            return vmax
        h = _monotone_step(s, n, H)
        if h >= H:
            return vmax
        if not h > 4e-16 * a:
            return a
        _shift(s, n, h)
        if not s[0] > 0:                     # round-off at the root: stay where the last step was certified
            return a
        a += h
    return a


@jit
def first_order(d, scale, K, floor):
    """The first order whose derivative is not round-off (``K + 1`` where none is); the margin itself is round-off
    below ``ZERO`` times the size of its terms or the problem's own size ``floor``, whichever is larger."""
    if abs(d[0]) > ZERO * max(scale[0], floor):
        return 0
    for k in range(1, K + 1):
        if abs(d[k]) > SIGNIFICANT * scale[k]:
            return k
    return K + 1


@jit
def step_from(d, K, k, lead, rem, vmax, s):
    """:func:`polynomial_step` of ``v^-k`` times the Taylor model's lower bound (orders below ``k`` are round-off):
    ``lead + sum_{i>k} g^(i) v^(i-k) / i! - B v^(K+1-k) / (K+1)!``."""
    if not vmax > 0:
        return 0.0
    n = K + 1 - k
    s[0] = lead
    for i in range(1, n):
        s[i] = d[k + i] * INV_FACT[k + i]
    s[n] = -rem * INV_FACT[K + 1]
    return polynomial_step(s, n, vmax)


@jit
def decide_step(d, rem, scale, K, vmax, floor, s):
    """The decision at a point from its Taylor model: ``(event, step, found)`` (scaled step ``v = Om u``).

    * ``event``: the first significant derivative is negative (the state ends here), unless a lower order is
      real and positive (:func:`real_order`): the margin grows first, so the state holds here;
    * ``step``: the first root of the model's lower bound, certified (:func:`polynomial_step`), from the first
      significant order ``k`` (the lower orders dropped as round-off: the step is cut where their negative
      parts could have pulled the margin down by its round-off level); where the margin is round-off small but
      not crossing (``k > 0``, or no derivative significant at all), also for the margin shifted by its
      round-off level ``ZERO * max(scale, floor)`` (no crossing below that level is missed); ``floor`` is the
      problem's own size of the margin (a bar at rest has none of its own);
    * ``found``: some derivative up to the model's order is significant, or the shifted margin certified a step.

    ``s`` is work space of at least ``2 (K + 2)`` entries.
    """
    k = first_order(d, scale, K, floor)
    found = k <= K
    level = ZERO * max(scale[0], floor)
    j = real_order(d, scale, min(k, K + 1))
    event = found and d[k] < 0 and not (j < k and d[j] > 0)
    go = found and not event
    v = 0.0
    if go and d[k] > 0:
        v = step_from(d, K, k, d[k] * INV_FACT[k], rem, vmax, s)
        if j < k:                                   # real orders were dropped: no further than they allow
            v = within(d, k, v, level)
    if (go and k > 0) or not found:
        shifted = max(d[0], 0.0) + level
        v = max(v, step_from(d, K, 0, shifted, rem, vmax, s))
    return event, v, found or v > 0


@jit
def lands(d, K, rem, v, scale, floor):
    """Whether the model puts the point ``v`` (scaled) on a crossing: the margin there at most half its round-off
    level and its slope clearly negative, bounds included (``P(v) + B v^(K+1)/(K+1)!`` and
    ``P'(v) + B v^K/K!``, ``P`` the Taylor polynomial).  Such a point is an event: the round that would
    evaluate it would decide just that (:func:`decide_step`: order 0 round-off, order 1 negative).
    """
    P, dP = 0.0, 0.0
    for i in range(K, -1, -1):
        dP = dP * v + P
        P = P * v + d[i] * INV_FACT[i]
    vk = v ** K
    return (P + rem * INV_FACT[K + 1] * vk * v <= 0.5 * ZERO * max(scale[0], floor)
            and dP + rem * INV_FACT[K] * vk < -2.0 * SIGNIFICANT * scale[1])


@jit
def _horner(d, K, x):
    """``P(x), P'(x)`` of the Taylor polynomial ``P(x) = sum_{i<=K} d_i x^i / i!``."""
    P, dP = 0.0, 0.0
    for i in range(K, -1, -1):
        dP = dP * x + P
        P = P * x + d[i] * INV_FACT[i]
    return P, dP


@jit
def _root(d, K, v, vmax):
    """The Taylor polynomial's root right of ``v`` by Newton from ``v`` (0 where it is not decreasing on the way,
    or the root is beyond ``vmax``)."""
    x = v
    for _ in range(12):
        P, dP = _horner(d, K, x)
        if not dP < 0:
            return 0.0
        dx = -P / dP
        x += dx
        if not x <= vmax:
            return 0.0
        if abs(dx) <= 1e-12 * x:
            break
    return x if x > v else 0.0


@jit
def bracket(d, K, rem, v, vmax, scale, s):
    """``(w, x)``: a certified bracket ``[v, w]`` (scaled) of the margin's first crossing after the certified step
    ``v``, and the Taylor polynomial's root ``x`` in it; ``(0, 0)`` where the model certifies none within ``vmax``.

    With ``P`` the Taylor polynomial and ``B`` the remainder bound (``rem``), the margin ``g`` obeys
    ``g(w) <= P(w) + B w^(K+1)/(K+1)!`` and ``g'(u) <= P'(u) + B u^K/K!`` (``P'`` is the Taylor polynomial of
    ``g'``, whose remainder has the same bound).  If the first is negative at ``w`` and the second on all of
    ``[v, w]`` (``P'`` re-expanded about ``v`` and bounded by its constant term plus its positive terms), ``g``
    -- positive at ``v`` -- decreases through zero exactly once in ``[v, w]``: the crossing is the first event,
    and Newton on the closed form finds it (:func:`plbar.motion.kernel.locate.locate`).  ``s`` is work space of
    ``K`` entries.
    """
    if not _horner(d, K, vmax)[0] < 0:             # the polynomial does not even come down: no crossing in sight
        return 0.0, 0.0
    x = _root(d, K, v, vmax)
    if not x > 0:
        return 0.0, 0.0
    w, low = x, False
    for _ in range(6):
        if _horner(d, K, w)[0] + rem * INV_FACT[K + 1] * w ** (K + 1) < -ZERO * scale[0]:
            low = True
            break
        w = min(vmax, x + 2.0 * (w - v))
    if not low:
        return 0.0, 0.0
    for i in range(K):
        s[i] = d[i + 1] * INV_FACT[i]
    _shift(s, K - 1, v)
    delta = w - v
    top, hp = s[0], 1.0
    for i in range(1, K):
        hp *= delta
        top += max(s[i], 0.0) * hp
    top += rem * INV_FACT[K] * w ** K
    return (w, x) if top < -SIGNIFICANT * scale[1] else (0.0, 0.0)
