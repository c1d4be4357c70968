"""The event-driven loop, compiled: one trajectory at a time, exactly (FORMULATION §§2-3, §8).

Each trajectory has its own forcing period ``T`` and phase ``phi`` (the load is
``q cos(W t - phi)``, ``W = 2 pi / T``).  A *round* evaluates the closed-form segment
(:mod:`.closed`) at the current point and either steps on by a certified distance over
which the margin cannot cross zero (:mod:`.certify`), or switches: the gap opens
(``x^II = E x^I``) or the bar comes back to the wall in a plastic impact that keeps the
momenta of the DOFs other than the contact and loses ``S v_c^2 / 2`` (Eq. (14)).  Every
forcing-period boundary restarts the segment there (a stroboscopic sample), so no segment
spans a period and the forcing phase stays within one period (no loss of digits over
1,000 periods).  Segments are always evaluated from their start, never stepped: the state
at any point is the closed form, not an accumulation of steps.

Nothing here is shared with :func:`plbar.simulate` but the model: the two are
independent checks of each other.
"""

from __future__ import annotations

from math import cos, sin

import numpy as np

from ..model import CHATTER, FREE, OK, STALLED, STUCK
from . import data as D
from .certify import ZERO, bracket, decide_step, lands, taylor
from .closed import add, half, matvec, mode_flow
from .jit import alloc, cached, inline, jit
from .locate import land, locate
from .pieces import amplitude, piece_accounts
from .split import particular, split_step

__all__ = [
    "CAP",
    "CHATTER",
    "CHATTER_H",
    "DEEP_MAX",
    "MAX_STALL",
    "PROGRESS",
    "MAX_ZERO",
    "MAX_SHORT",
    "OK",
    "ORDER",
    "STALLED",
    "TINY",
    "advance",
    "rebound",
    "flow_all",
    "switch",
    "work_space",
]

TINY = 1e-12        #: step (in periods) where no derivative decides, and the snap of a step onto a period boundary
MAX_ZERO = 50       #: consecutive zero-length segments before a trajectory is stopped as chattering
MAX_SHORT = 1000    #: consecutive events, each ending a segment shorter than PROGRESS, before it is stopped as
                    #: chattering: impacts and openings a few ulps apart (a contact node of a tiny mass) are never
                    #: zero-length and each resets the stall count, so without this they go on for ever (issue 44)
CHATTER_T = 1e-3    #: a flight shorter than this (in periods) between zero-length stuck phases counts as one of them
MAX_STALL = 5000    #: rounds without progress (below PROGRESS) since an event or a period boundary: stalled
#: a round that steps on by this fraction of a period or more is progress, however many it takes
#: (stiff Rayleigh modes make the Taylor model's steps short: P2, N = 256, 2 % needs ~6,000 a period)
PROGRESS = 1e-6
#: longest step, in forcing periods (the remainder bound is taken over it; it may cross a period end)
CAP = 0.25
ORDER = 8           #: order of the Taylor model of the margin
LARGE_ORDER = 16    #: order of the Taylor model of a system of SPLIT_MIN modes or more (longer steps, for the cost)
DEEP_MAX = 40       #: highest order of the deep model (where no derivative up to ORDER is significant)
CHATTER_H = 1e-11   #: rebounds accumulate (:func:`rebound`) once the next flight is this low, of the margin's size


@jit
def flow_all(md, st, ld, u, z0, out_e, out_v, damping):
    """Modal ``eta, eta'`` of every mode into ``out_e, out_v`` at ``u`` into a segment of state ``st`` and forcing
    ``ld`` (:class:`.data.Forcing`) from the modal state ``z0[0 | 1]``."""
    flow_at(md, st, ld, u, half(ld.W, u), z0, out_e, out_v, damping)


@jit
def flow_at(md, st, ld, u, hf, z0, out_e, out_v, damping):
    """:func:`flow_all` from ``hf = half(W, u)`` (kept by the caller)."""
    modal = md.modal
    for j in range(modal.shape[2]):
        z = 0.0 if damping is None else damping[st, D.ZETA, j]
        out_e[j], out_v[j] = mode_flow(D.Mode(modal[D.W, st, j], modal[D.F, st, j], z, modal[D.G, st, j]), ld, u,
                                       D.ModeState(z0[0, j], z0[1, j]), hf, damping)


@inline
def _model(md, st, W, T, ca, sa, K, wk, damping):
    """``(event, step, lands, hi, guess)`` at the current point ``wk.e, wk.v`` (``ca, sa = cos, sin(W t - phi)``
    there) from a Taylor model of order ``K`` (step -1: undecided; ``lands``: the step ends on a crossing,
    :func:`.certify.lands`; ``hi > 0``: the margin crosses zero once in ``[step, hi]``, near ``guess``,
    :func:`.certify.bracket`)."""
    modal, margin, d, scale, work = md.modal, md.margin, wk.d, wk.scale, wk.taylor
    cap = CAP * T
    modes = D.Modes(modal[D.W, st], modal[D.F, st], modal[D.C, st], modal[D.G, st])
    load = D.LoadTerm(W, ca, sa, margin[D.RQ, st], 0.0, margin[D.G0, st])
    if damping is None:
        rem, Om = taylor(modes, None, wk.e, wk.v, load, cap, K, d, scale)
    else:
        rem, Om = taylor(modes, D.Damping(damping[st, D.ZETA], damping[st, D.CV]), wk.e, wk.v, load, cap, K, d, scale)
    event, v, found = decide_step(d, rem, scale, K, Om * cap, margin[D.SIZE, st], work)
    landing = not event and 0 < v < Om * cap and d[1] < 0 and lands(d, K, rem, v, scale, margin[D.SIZE, st])
    hi, guess = 0.0, 0.0
    if found and not (event or landing) and 0 < v < Om * cap and d[0] > ZERO * max(scale[0], margin[D.SIZE, st]):
        hi, guess = bracket(d, K, rem, v, Om * cap, scale, work)
    return event, (v / Om if found else -1.0), landing, hi / Om, guess / Om


@jit
def _certify(md, st, W, T, ca, sa, wk, large, damping):
    """``(event, step, lands, hi, guess)`` (:func:`_model`): for a ``large`` system (not None: :data:`SPLIT_MIN`
    modes or more) from the split model (:mod:`.split`) where it certifies a step, else from the model of order
    :data:`LARGE_ORDER`; for a small one from the model of order :data:`ORDER` (constants here: their loops
    unroll; a small system compiles neither the split model nor the large order); where that decides nothing (a
    bar at rest loaded far from its contact), from the deep model of order ``2 m + 4`` (at most
    :data:`DEEP_MAX`)."""
    if large is not None:
        step = split_step(md, st, W, ca, sa, CAP * T, wk, damping)
        if step > 0:
            return False, step, False, 0.0, 0.0
        event, step, landing, hi, guess = _model(md, st, W, T, ca, sa, LARGE_ORDER, wk, damping)
    else:
        event, step, landing, hi, guess = _model(md, st, W, T, ca, sa, ORDER, wk, damping)
    if step < 0:
        deep = min(2 * md.modal.shape[2] + 4, DEEP_MAX)
        event, step, landing, hi, guess = _model(md, st, W, T, ca, sa, deep, wk, damping)
    return event, step, landing, hi, guess


@jit
def switch(md, st, eta, vel, out_e, out_v, load, damping):
    """The event at the current point: ``(kind, loss, dt)``; the new modal state into ``out_e, out_v``.

    kind 1: the gap opens (I -> II, ``x^II = E x^I``); kind 2: plastic impact (II -> I, Eq. (10)),
    loss ``S v_c^2 / 2`` (Eq. (14)); for a truncated system the modal kinetic energy difference.  With a
    coefficient of restitution ``e > 0`` (``md.restitution``) an impact is a rebound (:func:`rebound`, kind 3, the state
    stays II) unless the rebounds accumulate (kind 4: the plastic impact, ``dt`` the time to the accumulation
    point).  ``load`` is ``cos(W t - phi)`` here.
    """
    maps, vc_row, S, truncated, rest = md.maps, md.vc_row, md.S, md.truncated, md.restitution
    if st == STUCK:
        matvec(maps[D.OPEN], eta, out_e)
        add(out_e, md.offsets[D.OPEN_OFF])
        matvec(maps[D.OPEN_VEL], vel, out_v)
        return D.OPENS, 0.0, 0.0
    kind, loss, dt = D.IMPACT, 0.0, 0.0
    if rest > 0.0:
        kind, loss, dt = rebound(md, eta, vel, out_e, out_v, load, damping)
        if kind == D.REBOUND:
            return kind, loss, dt
    matvec(maps[D.IMPACT_POS], eta, out_e)
    add(out_e, md.offsets[D.IMPACT_OFF])
    matvec(maps[D.IMPACT_VEL], vel, out_v)
    ke, vc = 0.0, 0.0
    for j in range(vel.size):
        ke += vel[j] * vel[j] - out_v[j] * out_v[j]
        vc += vel[j] * vc_row[j]
    return kind, (0.5 * ke if truncated else 0.5 * S * vc * vc), dt


@jit
def rebound(md, eta, vel, out_e, out_v, load, damping):
    """Newton's impact law with restitution ``e = md.restitution`` at an impact of state II: ``(kind, loss, dt)``.

    The impulse acts along the contact DOF, so in the modal coordinates (mass-orthonormal) along the contact row
    ``r`` (``x_c = r . eta``): ``v+ = v - (1 + e) (r . v) r / |r|^2``, which gives ``r . v+ = -e r . v`` and loses
    ``(1 - e^2) (r . v)^2 / (2 |r|^2)`` of kinetic energy (``|r|^2 = (M^-1)_cc``: the loss of Eq. (14) times
    ``1 - e^2``); the positions are kept.  Kind 3 (:data:`.data.REBOUND`), the state into ``out_e, out_v``.

    Where the contact is pressed to the wall (its free acceleration ``a > 0`` there) the rebounds come back ever
    faster: with ``a`` held, the flights last ``2 e^k v / a`` and add up to ``dt = 2 e v / (a (1 - e))``, after
    which the contact stays at the wall with ``v_c = 0`` (chattering).  Once the next flight's height
    ``(e v)^2 / (2 a)`` is below :data:`CHATTER_H` of the margin's size, the rest of the sequence is that limit:
    kind 4 (:data:`.data.STICK`, the caller's plastic impact, which loses the contact's whole kinetic energy,
    what the rest of the sequence loses, ``sum (1 - e^2) e^(2k) = 1``), with ``dt``.  The bar beside it moves
    as in state I meanwhile: the contact is within that height of the wall (docs/restitution.md).
    """
    modal, vc_row, e = md.modal, md.vc_row, md.restitution
    rr, vc, a, size = 0.0, 0.0, 0.0, md.margin[D.SIZE, FREE]
    for j in range(vel.size):
        rr += vc_row[j] * vc_row[j]
        vc += vc_row[j] * vel[j]
    k = (1.0 + e) * vc / rr
    for j in range(vel.size):
        w = modal[D.W, FREE, j]
        out_e[j] = eta[j]
        out_v[j] = vel[j] - k * vc_row[j]
        acc = modal[D.F, FREE, j] * load + modal[D.G, FREE, j] - w * w * eta[j]
        if damping is not None:
            acc -= 2.0 * damping[FREE, D.ZETA, j] * w * out_v[j]
        a += vc_row[j] * acc
        size = max(size, abs(vc_row[j] * eta[j]))
    if e < 1.0 and a > 0.0 and (e * vc) ** 2 <= 2.0 * a * CHATTER_H * size:
        return D.STICK, 0.0, 2.0 * e * vc / (a * (1.0 - e))
    return D.REBOUND, 0.5 * (1.0 - e * e) * vc * vc / rr, 0.0


@jit
def _account(md, cur, seg, acc, tau, rows, damping):
    """Account the piece ``[tp, tp + tau]`` of the current segment ``seg`` (:class:`.data.Segment`; its start state
    ``cur.z0``) of the current trajectory (``rows``: four rows of work space for :func:`.pieces.amplitude`)."""
    if acc is None:
        return
    s, z0, tot, first, b = cur.s, cur.z0, cur.tot, cur.first, cur.b
    st, period = s[D.STATE], s[D.PERIOD]
    full = period >= first
    wk, d_eq, d_w, visc = piece_accounts(md, st, seg.ld, tau, z0, full, damping)
    tot[D.WORK] += wk
    tot[D.VISC] += visc
    if full:
        r = period - first
        acc[b, r, D.D_EQ] += d_eq
        acc[b, r, D.D_W] += d_w
        acc[b, r, D.WORK_REC] += wk
        acc[b, r, D.VISC_REC] += visc
        if st == STUCK:
            acc[b, r, D.STUCK_T] += tau
        elif tau > 0:
            acc[b, r, D.AMP] = max(acc[b, r, D.AMP], amplitude(md, seg, tau, z0, rows, damping))


@jit
def _set(row, x):
    for j in range(x.size):
        row[j] = x[j]


@jit
def _event(md, cur, seg, rc, acc, wk, damping):
    """Account the segment ``seg`` that ends here (at ``wk.e, wk.v``), switch, record the event, count zero-length
    segments."""
    per, ev, f, s, z0, tot, first, b = rc.per, rc.ev, cur.f, cur.s, cur.z0, cur.tot, cur.first, cur.b
    e, v, e2, v2 = wk.e, wk.v, wk.e2, wk.v2
    st, tp, period = s[D.STATE], f[D.TP], s[D.PERIOD]
    if st == FREE:                     # an impact: landed on x_c = 0 to its last bits, however it was found
        f[D.P] = land(md, seg, f[D.P], f[D.T] - tp, e, v, damping)
    p = f[D.P]
    _account(md, cur, seg, acc, p, wk.rows, damping)
    # (tp + p) first: the next segment starts at tp + p, so a zero-length phase's second event gets the same time
    # (summed as period T + tp + p it came out ulps before the first: event times must never decrease)
    time = period * f[D.T] + (tp + p)
    kind, loss, dt = switch(md, st, e, v, e2, v2, cos(f[D.OMEGA] * (tp + p) - f[D.PHI]), damping)
    f[D.TP] = tp + p
    f[D.P] = 0.0
    _set(z0[0], e2)
    _set(z0[1], v2)
    if kind != D.REBOUND:
        s[D.STATE] = 1 - st
    tot[D.LOSSES] += loss
    if period >= first:
        r, n = period - first, s[D.EVENTS]
        per[b, r, D.OPENINGS if kind == D.OPENS else D.IMPACTS] += 1.0
        per[b, r, D.LOSS] += loss
        ev[b, n, D.TIME], ev[b, n, D.KIND], ev[b, n, D.LOSS] = time + dt, kind, loss
        s[D.EVENTS] = n + 1
    # A chatter: zero-length segments in a row.  A truncated system (fewer state II modes) also chatters with
    # short flights between them: its opening gives the contact a velocity into the wall (the kept modes cannot
    # hold it at rest), so an impact whose reaction pulls at once opens and hits again within ~1e-5 T, over and
    # over (276,000 events in one period, ``--modes 5``, N = 20): such a flight, after a zero-length phase,
    # counts as one of them too.
    short = p == 0.0 or (s[D.ZEROS] > 0 and p < CHATTER_T * f[D.T])
    s[D.ZEROS] = s[D.ZEROS] + 1 if short else 0
    s[D.SHORT] = s[D.SHORT] + 1 if p <= PROGRESS * f[D.T] else 0
    s[D.STALL] = 0
    if s[D.ZEROS] > MAX_ZERO or s[D.SHORT] > MAX_SHORT:
        s[D.STATUS] = CHATTER


@jit
def _boundary(md, cur, seg, rc, acc, wk, damping):
    """Account the last piece of the forcing period (of the segment ``seg``), restart the segment at its end, record
    the boundary state (the state at the end is left in ``wk.e, wk.v``)."""
    f, s, z0, first, b, e, v = cur.f, cur.s, cur.z0, cur.first, cur.b, wk.e, wk.v
    st, tp, period = s[D.STATE], f[D.TP], s[D.PERIOD]
    _account(md, cur, seg, acc, f[D.P], wk.rows, damping)
    flow_all(md, st, seg.ld, f[D.T] - tp, z0, e, v, damping)
    _set(z0[0], e)
    _set(z0[1], v)
    s[D.PERIOD] = period + 1
    f[D.TP] = 0.0
    f[D.P] = 0.0
    s[D.STALL] = 0
    r = period + 1 - first
    if r >= 0:
        _set(rc.sx[b, r], e)
        _set(rc.sv[b, r], v)
        rc.ss[b, r] = st


@jit
def _run(md, cur, rc, acc, stop, wk, large, damping, halt):
    """Advance one trajectory (:class:`.data.Current`) to the start of forcing period ``stop`` (``wk``: the work
    space from :func:`advance`), or until another thread sets ``halt[0]`` (checked every round: a Ctrl-C stops a
    chattering trajectory too)."""
    f, s, z0, first, e, v = cur.f, cur.s, cur.z0, cur.first, wk.e, wk.v
    T, W, phi = f[D.T], f[D.OMEGA], f[D.PHI]
    cphi, sphi = cos(phi), sin(phi)
    room = rc.ev.shape[1]
    if large is not None:
        particular(md, damping, W, wk.P, wk.fast)
    start, c0, s0 = -1.0, 1.0, 0.0
    while s[D.PERIOD] < stop and s[D.STATUS] == OK and halt[0] == 0:
        st, tp, p = s[D.STATE], f[D.TP], f[D.P]
        if tp != start:                        # the load's phase at the segment's start, once per segment
            start, c0, s0 = tp, cos(W * tp), sin(W * tp)
        ld = D.Forcing(W, c0, s0, cphi, sphi)
        seg = D.Segment(ld, tp, phi)
        hf = half(W, p)
        flow_at(md, st, ld, p, hf, z0, e, v, damping)
        cth, sth = c0 * cphi + s0 * sphi, s0 * cphi - c0 * sphi      # cos, sin(W tp - phi); then at tp + p:
        cWp = 1.0 - 2.0 * hf.sW * hf.sW
        event, step, landing, hi, guess = _certify(md, st, W, T, cth * cWp - sth * hf.sWu, sth * cWp + cth * hf.sWu,
                                                   wk, large, damping)
        if event and s[D.PERIOD] >= first and s[D.EVENTS] >= room:
            s[D.NEED] = 1                      # no room to record it: the caller grows the record and goes on
            return
        if not step > PROGRESS * T:
            s[D.STALL] += 1
        s[D.ROUNDS] += 1
        if event:
            _event(md, cur, seg, rc, acc, wk, damping)
        else:
            end = T - tp
            new_p = p + (step if step > 0 else TINY * T)
            if not new_p > p:                  # a step below the resolution of t: one ulp (the crossing is there)
                new_p = np.nextafter(p, np.inf)
            f[D.P] = end if new_p >= end - TINY * T else new_p
            if f[D.P] >= end:
                _boundary(md, cur, seg, rc, acc, wk, damping)
                if step > 0 and new_p > end:    # certified past the boundary: the next round starts there
                    f[D.P] = new_p - end
            elif s[D.PERIOD] >= first and s[D.EVENTS] >= room:
                pass                           # no room to record an event here: the next round meets it
            elif landing:
                flow_all(md, st, ld, f[D.P], z0, e, v, damping)
                _event(md, cur, seg, rc, acc, wk, damping)             # the step ends on a crossing
            elif 0 < hi and p + hi < end:      # the one crossing of a certified bracket, on the closed form
                f[D.P] = locate(md, st, seg, f[D.P], p + hi, p + guess, z0, wk, damping)
                _event(md, cur, seg, rc, acc, wk, damping)
        if s[D.STALL] > MAX_STALL:
            s[D.STATUS] = STALLED


@alloc
def work_space(m):
    """A :class:`.data.Work` for a system of ``m`` modes (the one allocation of the kernel's work space)."""
    return D.Work(np.empty(m), np.empty(m), np.empty(m), np.empty(m), np.empty(m), np.empty((4, m)),
                  np.empty(DEEP_MAX + 2), np.empty(DEEP_MAX + 2), np.empty(2 * (DEEP_MAX + 3)), np.empty((2, 2, m)),
                  np.empty(2, np.int64))


def _advance(stamp):
    def advance(md, tr, rc, acc, idx, stop, large, damping, halt):
        """Advance the trajectories ``idx`` to the start of forcing period ``stop`` (or until each stops, or has no
        room left to record an event: ``NEED``, or until ``halt[0]`` is set, an int64 array of one element that
        another thread may set: the state reached is kept, a later call goes on from it), recording from period
        ``rc.first`` on.

        Each trajectory runs on copies of its state (no two threads write near each other) written back at the
        end.  All work space is allocated here: the functions below are compiled without reference counting
        (:data:`.jit.jit`).  ``acc`` None: no accounts (a replay of the switches); ``damping`` None: undamped;
        ``large`` None: a system of fewer than :data:`SPLIT_MIN` modes.  The code that is not used is then not compiled.
        """
        if stamp < 0:                      # never: the stamp keys the on-disk cache (:func:`.jit.cached`)
            return
        tf, ti, z, tot = tr
        m = md.modal.shape[2]
        wk = work_space(m)
        f, s, t3, z0 = np.empty(tf.shape[1]), np.empty(ti.shape[1], np.int64), np.empty(3), np.empty((2, m))
        for b in idx:
            _set(f, tf[b])
            _set(s, ti[b])
            _set(t3, tot[b])
            _set(z0[0], z[b, 0])
            _set(z0[1], z[b, 1])
            _run(md, D.Current(b, rc.first, f, s, z0, t3), rc, acc, stop, wk, large, damping, halt)
            _set(tf[b], f)
            _set(ti[b], s)
            _set(tot[b], t3)
            _set(z[b, 0], z0[0])
            _set(z[b, 1], z0[1])

    return advance


advance = cached(_advance)
