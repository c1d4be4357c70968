"""Following a periodic response of any signature in the forcing period: pseudo-arclength continuation.

The unknowns ``Y = (X, T)`` satisfy ``F(X, T) = 0`` (:mod:`.chain`): one more
unknown than equations, so the responses form curves.  Each step predicts
along the unit tangent (in scaled coordinates: the state by its size, the
durations and ``T`` by ``T``, the phase as it is), then corrects by Newton on
``F = 0`` and the arclength condition; the Jacobian in ``X`` is exact, the
column in ``T`` a forward difference (the load's frequency enters every
flow).  The curve passes folds in ``T``.  It stops at the ends of the period
window, where a duration reaches zero (a stuck phase shrinking to zero is a
change of signature: :func:`plbar.periodic.branches` continues into the new
one), or where Newton fails at the smallest step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Problem
from .chain import compiled, layout, model, pairs_of
from .packed import Control
from .signature import Signature
from .solve import ACCEPT, ROUNDOFF, Orbit, NotConverged, orbit_at, polish

__all__ = ["FollowSettings", "follow", "END_WINDOW", "END_DWELL", "END_FREE", "END_FAILED", "END_POINTS",
           "END_INADMISSIBLE", "END_REPEATED", "END_LOOP", "plausible", "correct", "scale_of"]

END_WINDOW = "window"          #: left the period window
END_DWELL = "dwell->0"         #: a stuck phase shrank to zero (the signature changes)
END_FREE = "free->0"           #: a free phase shrank to zero
END_FAILED = "no convergence"  #: Newton failed at the smallest step
END_POINTS = "max points"
END_INADMISSIBLE = "inadmissible"   #: :attr:`FollowSettings.patience` points in a row fail the necessary conditions
END_REPEATED = "repeats a shorter orbit"   #: the curve reaches an orbit that is a shorter one repeated
END_LOOP = "closed loop"       #: the curve came back to one of its points (it has gone round a loop once)


#: a curve ends where a duration reaches zero only when a step this short (scaled arclength) predicts it: a long
#: step's tangent overshoots where the curve bends, and ended curves short of their end
END_STEP = 1e-3


@dataclass(frozen=True)
class FollowSettings:
    """Step control of :func:`follow` (scaled arclength; ``h`` relative to the period)."""

    h0: float = 0.02
    h_min: float = 1e-6
    h_max: float = 0.15
    max_points: int = 600
    newton: int = 8
    patience: int = 8        #: stop after this many points in a row that fail the necessary conditions


def scale_of(prob: Problem, sig: Signature, X: np.ndarray, T: float) -> np.ndarray:
    """The scales of ``Y = (X, T)``: the state by its largest component, the durations and ``T`` by ``T``, the phase
    by 1."""
    nz, q, _ = layout(prob, sig)
    S = np.empty(nz + q + 2)
    S[:nz] = max(float(np.abs(X[:nz]).max(initial=0.0)), 1e-12)
    S[nz:] = T
    S[-2] = 1.0
    return S


def _kernel(prob, sig):
    """The compiled step (:func:`plbar.periodic.kernel.newton.step`) bound to a problem and a signature: ``run(Y, S,
    c, Ja, ctl, t, Ynew)``, ``ctl`` a :class:`plbar.periodic.packed.Control`."""
    step = compiled().step
    md, pairs = model(prob), pairs_of(sig)

    def run(Y, S, c, Ja, ctl, t, Ynew):
        f64 = lambda a: np.ascontiguousarray(a, dtype=float)  # noqa: E731
        ctl = Control(float(ctl.h), float(ctl.h_min), int(ctl.newton), int(ctl.mode))
        return step(md, pairs, f64(Y), f64(S), f64(c), f64(Ja), ctl, t, Ynew)

    return run


def correct(prob, sig, Yp, t, S, newton: int = 8, Ja: np.ndarray | None = None):
    """Newton on ``F = 0`` and ``t . (Y - Yp) = 0`` (scaled); the orbit or None (compiled:
    :func:`plbar.periodic.kernel.newton.correct`).

    With ``Ja`` (the augmented Jacobian at the last point) the corrector is a chord method: that
    matrix is factorised once and every iteration evaluates only the residuals.
    """
    K = compiled()
    Y = np.empty(Yp.size)
    ctl = Control(0.0, 0.0, newton, K.NEWTON if Ja is None else K.CHORD)
    out, _ = _kernel(prob, sig)(Yp, S, t, np.zeros((1, 1)) if Ja is None else Ja, ctl, np.empty(Yp.size), Y)
    return None if out == K.FAILED else _final(prob, sig, orbit_at(prob, sig, Y[-1], Y[:-1]))


def _final(prob, sig, orb: Orbit):
    """``orb`` if its residual is at round-off (after a Newton polish at its T if need be), else None."""
    if orb.residual <= ROUNDOFF:
        return orb
    if orb.residual > ACCEPT:
        return None
    try:
        return polish(prob, sig, orb.T, orb.X)
    except NotConverged:
        return None


def plausible(orb: Orbit) -> bool:
    """The necessary conditions of admissibility that cost nothing: every impact comes in (``v_c > 0``) and the
    reaction pulls after every impact followed by a zero dwell."""
    return bool((orb.v_impact > 0).all() and (orb.zero_margins < 0).all())


def follow(prob: Problem, sig: Signature, start: Orbit, window: tuple[float, float], direction: float = 1.0,
           settings: FollowSettings | None = None, before=()) -> tuple[list[Orbit], str]:
    """The curve of responses of signature ``sig`` through ``start``, in one direction of ``T``, inside ``window``.

    ``before`` (optional): the curve's points already followed, in the order that arrives at ``start`` (the other
    half, reversed, without ``start``).  The curve then leaves ``start`` away from the last of them, whatever
    ``direction`` says (at a fold the sign of the tangent's ``T`` component does not tell the two ways apart), and
    ends where it closes a loop through them as through its own points (:data:`END_LOOP`).
    Returns the orbits in order (``start`` first) and why the curve ended.
    """
    K = compiled()
    st = settings or FollowSettings()
    Y = np.concatenate([start.X, [start.T]])
    out = [start]
    nz, q, _ = layout(prob, sig)
    h = st.h0
    run = _kernel(prob, sig)
    c = np.zeros(Y.size)                 # the last tangent; at the first point the direction in T
    c[-1] = direction
    before = list(before)
    if before:
        away = before[-1]
        c = (Y - np.concatenate([away.X, [away.T]])) / scale_of(prob, sig, Y[:-1], Y[-1])
        c[-2] = -np.angle(np.exp(1j * (away.phi - start.phi)))
    t, Yn, none = np.empty(Y.size), np.empty(Y.size), np.zeros((1, 1))
    bad = 0
    while len(out) < st.max_points:
        S = scale_of(prob, sig, Y[:-1], Y[-1])
        orb = None
        while h >= st.h_min:
            res, h = run(Y, S, c, none, Control(h, st.h_min, st.newton, K.FOLLOW), t, Yn)
            if res == K.FAILED:
                break
            Yp = Y + h * t * S
            if res != K.ENDED:
                orb = _final(prob, sig, orbit_at(prob, sig, Yn[-1], Yn[:-1].copy()))
                if orb is not None and abs(orb.T - Y[-1]) <= 0.2 * Y[-1]:
                    break
                orb = None
            if np.any(Yp[nz:nz + q] <= 0) and h <= END_STEP:     # a duration reaches 0 within a short step
                return out, _duration_end(sig, int(np.argmin(Yp[nz:nz + q])))
            h *= 0.5
        if orb is None:
            return out, END_FAILED
        if not window[0] <= orb.T <= window[1]:
            edge = _at_edge(prob, sig, out[-1], orb, window)
            return out + ([edge] if edge is not None else []), END_WINDOW
        if sig.m > 1 and orb.period < sig.m:         # on the shorter orbit seen m / period times: its own curve
            return out, END_REPEATED
        Y = np.concatenate([orb.X, [orb.T]])
        out.append(orb)
        if len(before) + len(out) > 4 and _back_at(before + out, S, h):
            return out, END_LOOP
        bad = 0 if plausible(orb) else bad + 1
        if bad >= st.patience:
            return out, END_INADMISSIBLE
        c = t.copy()
        h = min(1.5 * h, st.h_max)
    return out, END_POINTS


def _back_at(out, S: np.ndarray, h: float) -> bool:
    """Has the curve's last step closed a loop: its last point within that step ``h`` of a point three or more
    steps back, passing it the same way (tangents within 60 degrees; scaled by ``S``, the phase mod ``2 pi``)?
    A hairpin (the curve turning back along itself) passes the other way and goes on."""
    Y = np.array([np.concatenate([o.X, [o.T]]) for o in out])
    d = Y[-1] - Y[:-4]
    d[:, -2] = np.angle(np.exp(1j * d[:, -2]))
    near = np.linalg.norm(d / S, axis=1) <= h
    if not near.any():
        return False
    step = np.diff(Y, axis=0)
    step[:, -2] = np.angle(np.exp(1j * step[:, -2]))
    step /= S
    u, v = step[-1], step[:-3]                      # the last step; the step leaving each earlier point
    cos = v @ u / np.maximum(np.linalg.norm(v, axis=1) * np.linalg.norm(u), 1e-300)
    return bool(np.any(near & (cos > 0.5)))


def _at_edge(prob: Problem, sig: Signature, inside: Orbit, outside: Orbit, window) -> Orbit | None:
    """The curve's point on the window's edge, between its last point inside and the first outside: Newton at the
    edge's ``T`` from the linear interpolation (so that a curve covers the window to its ends); None where Newton
    fails or the point is not plausible."""
    edge = window[1] if outside.T > window[1] else window[0]
    w = (edge - inside.T) / (outside.T - inside.T)
    X = inside.X + w * (outside.X - inside.X)
    try:
        orb = polish(prob, sig, edge, X)
    except NotConverged:
        return None
    return orb if plausible(orb) else None


def _duration_end(sig: Signature, col: int) -> str:
    """Which kind of duration is the unknown column ``col``."""
    k = 0
    for positive in sig.dwell:
        if positive:
            if k == col:
                return END_DWELL
            k += 1
        if k == col:
            return END_FREE
        k += 1
    return END_FREE
