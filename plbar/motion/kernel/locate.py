"""The crossing inside a certified bracket, by safeguarded Newton on the closed-form margin.

Where the Taylor model certifies that the margin decreases through zero exactly once in
``[lo, hi]`` (:func:`plbar.motion.kernel.certify.bracket`), the event is that crossing: Newton on
the margin evaluated from the closed-form flow (:func:`margin_at`), kept inside the bracket
(bisection where a Newton step would leave it), finds it to the round-off of the margin in two
or three evaluations.  This replaces the rounds that would otherwise step towards the crossing
one certified step at a time.  The segment is a :class:`.data.Segment` ``seg`` (its forcing
``seg.ld``, its start ``seg.ts = tp`` within the forcing period), its start state ``z0[0 | 1]``.
"""

from __future__ import annotations

from math import cos, sin

from ..model import FREE
from . import data as D
from .certify import ZERO
from .closed import half, mode_flow
from .jit import jit

__all__ = ["MAX_NEWTON", "land", "locate", "margin_at"]

MAX_NEWTON = 60   #: evaluations at most (bisection halves the bracket where Newton would leave it)
POLISH_MAX = 1e-7  #: longest polishing step, times the fastest frequency (its neglected term is ~1e-14 of it)


@jit
def margin_at(md, st, seg, u, z0, e, v, damping):
    """``(g, g', size)``: the margin, its rate and the size of its terms at ``u`` into the segment ``seg`` of state
    ``st`` that starts with the modal state ``z0``; the modal state at ``u`` is left in ``e, v``."""
    modal, margin, ld, W = md.modal, md.margin, seg.ld, seg.ld.W
    hf = half(W, u)
    arg = W * (seg.ts + u) - seg.phi
    ca, sa = cos(arg), sin(arg)
    rq, g0 = margin[D.RQ, st], margin[D.G0, st]
    g, g1, size = rq * ca + g0, -rq * W * sa, abs(rq) + abs(g0)
    for j in range(e.size):
        w, f, c = modal[D.W, st, j], modal[D.F, st, j], modal[D.C, st, j]
        z = 0.0 if damping is None else damping[st, D.ZETA, j]
        e[j], v[j] = mode_flow(D.Mode(w, f, z, modal[D.G, st, j]), ld, u, D.ModeState(z0[0, j], z0[1, j]), hf, damping)
        g += c * e[j]
        g1 += c * v[j]
        size += abs(c * e[j])
        if damping is not None:
            cv = damping[st, D.CV, j]
            g += cv * v[j]
            g1 += cv * (f * ca + modal[D.G, st, j] - w * w * e[j] - 2.0 * z * w * v[j])
            size += abs(cv * v[j])
    return g, g1, size


@jit
def _polish(md, seg, x, dx, hi, e, v, damping):
    """An impact located to ``ZERO``: one more Newton step ``x - dx`` taken on the state by its Taylor expansion
    (``dx`` is round-off, its square far below it), so that ``x_c`` is zero to its last bits -- the impact's reset
    (``x_c = 0``) then moves no potential energy: a settled motion repeats that error every period, and the energy
    budget of 1,000 periods grew by it (issue 28: 5e-12 of the work where the load does little work)."""
    xn = x - dx
    if not 0.0 <= xn <= hi:
        return x
    modal = md.modal
    load = cos(seg.ld.W * (seg.ts + x) - seg.phi)
    for j in range(e.size):
        w, f = modal[D.W, FREE, j], modal[D.F, FREE, j]
        a = f * load + modal[D.G, FREE, j] - w * w * e[j]
        if damping is not None:
            a -= 2.0 * damping[FREE, D.ZETA, j] * w * v[j]
        e[j] -= v[j] * dx
        v[j] -= a * dx
    return xn


@jit
def land(md, seg, x, hi, e, v, damping):
    """The point ``x`` of an impact (segment time in ``[0, hi]``, the modal state there in ``e, v``) polished by
    :func:`_polish` from the margin ``g = c . eta = -x_c`` and its rate on that state.  However the impact was
    found (a round that decides it, a step that lands on it, :func:`locate`), the margin there is within its
    round-off level ``ZERO``, up to ~1e-13 of its size; the reset ``x_c = 0`` would move ``x_c`` times the contact
    force of potential energy, 1e-13 of the energy at some impacts, and the budget of 1,000 periods drifted by
    1e-12 of the work (issue 28)."""
    modal, g0 = md.modal, md.margin[D.G0, FREE]
    g, g1, size, wmax = g0, 0.0, abs(g0), 0.0
    for j in range(e.size):
        c = modal[D.C, FREE, j]
        g += c * e[j]
        g1 += c * v[j]
        size += abs(c * e[j])
        wmax = max(wmax, modal[D.W, FREE, j])
    if not (g1 < 0.0 and abs(g) <= ZERO * max(size, md.margin[D.SIZE, FREE])):
        return x
    dx = g / g1
    if not abs(dx) * wmax <= POLISH_MAX:    # a grazing impact (slow rate): the Taylor step would not be round-off
        return x
    return _polish(md, seg, x, dx, hi, e, v, damping)


@jit
def locate(md, st, seg, lo, hi, x, z0, wk, damping):
    """The crossing in ``[lo, hi]`` (segment time; the margin positive at ``lo``, negative at ``hi`` and decreasing
    in between), from the guess ``x``: the point where the margin is within half its round-off level, or ``hi``
    where the bracket closes to an ulp first.  The modal state there is left in ``wk.e, wk.v``
    (:class:`.data.Work`)."""
    floor = md.margin[D.SIZE, st]
    e, v = wk.e, wk.v
    x = min(max(x, lo), hi)
    for _ in range(MAX_NEWTON):
        g, g1, size = margin_at(md, st, seg, x, z0, e, v, damping)
        if abs(g) <= 0.5 * ZERO * max(size, floor):
            return x
        if g > 0:
            lo = x
        else:
            hi = x
        xn = x - g / g1 if g1 < 0 else 0.5 * (lo + hi)
        if not lo < xn < hi:
            xn = 0.5 * (lo + hi)
        if not lo < xn < hi:                       # the bracket is down to an ulp: the crossing is at hi
            break
        x = xn
    margin_at(md, st, seg, hi, z0, e, v, damping)
    return hi
