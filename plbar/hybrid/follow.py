"""Following a periodic response of any signature in the forcing period: pseudo-arclength continuation.

The unknowns ``Y = (X, T)`` satisfy ``F(X, T) = 0`` (:mod:`.chain`): one more
unknown than equations, so the responses form curves.  Each step predicts
along the unit tangent (in scaled coordinates: the state by its size, the
durations and ``T`` by ``T``, the phase as it is), then corrects by Newton on
``F = 0`` and the arclength condition; the Jacobian in ``X`` is exact, the
column in ``T`` a central difference (the load's frequency enters every
flow).  The curve passes folds in ``T``.  It stops at the ends of the period
window, where a duration reaches zero (a stuck phase shrinking to zero is a
change of signature: :func:`plbar.hybrid.branches` continues into the new
one), or where Newton fails at the smallest step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Problem
from .chain import evaluate, layout
from .signature import Signature
from .solve import ACCEPT, ROUNDOFF, HybridOrbit, NotConverged, orbit_at, polish

__all__ = ["FollowSettings", "follow", "END_WINDOW", "END_DWELL", "END_FREE", "END_FAILED", "END_POINTS", "END_INADMISSIBLE",
           "plausible", "correct", "scale_of"]

END_WINDOW = "window"          #: left the period window
END_DWELL = "dwell->0"         #: a stuck phase shrank to zero (the signature changes)
END_FREE = "free->0"           #: a free phase shrank to zero
END_FAILED = "no convergence"  #: Newton failed at the smallest step
END_POINTS = "max points"
END_INADMISSIBLE = "inadmissible"   #: :attr:`FollowSettings.patience` points in a row fail the necessary conditions


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
    nz, q, _ = layout(prob, sig)
    zs = max(float(np.abs(X[:nz]).max(initial=0.0)), 1e-12)
    return np.concatenate([np.full(nz, zs), np.full(q, T), [1.0], [T]])


def _jac(prob, sig, Y):
    X, T = Y[:-1], Y[-1]
    ch = evaluate(prob, sig, T, X)
    h = 1e-7 * T
    dT = (evaluate(prob, sig, T + h, X, jac=False).F - ch.F) / h
    return ch, np.hstack([ch.J, dT[:, None]])


def _tangent(Ja: np.ndarray, S: np.ndarray, prev: np.ndarray | None, direction: float) -> np.ndarray:
    """Unit tangent of the curve in scaled coordinates (orientation kept from ``prev``, else ``direction`` in T)."""
    A = Ja * S[None, :]
    _, _, vt = np.linalg.svd(A)
    t = vt[-1]
    ref = (prev @ t) if prev is not None else direction * t[-1]
    return t if ref >= 0 else -t


def correct(prob, sig, Yp, t, S, newton: int = 8, Ja: np.ndarray | None = None):
    """Newton on ``F = 0`` and ``t . (Y - Yp) = 0`` (scaled); the orbit or None.

    With ``Ja`` (the augmented Jacobian at the last point) the corrector is a chord method: that
    matrix is factorised once and every iteration evaluates only the residuals.
    """
    from scipy.linalg import lu_factor, lu_solve

    Y = Yp.copy()
    nz, q, _ = layout(prob, sig)
    lu = None
    ch = None
    last = np.inf
    for it in range(2 * newton if Ja is not None else newton):
        if np.any(Y[nz:nz + q] <= 0) or Y[-1] <= 0:
            return None
        if Ja is None or lu is None and it > 0:
            ch, J = _jac(prob, sig, Y)
            A = np.vstack([J, (t / S)[None, :]])
            lu = lu_factor(A, check_finite=False)
        elif lu is None:
            lu = lu_factor(np.vstack([Ja, (t / S)[None, :]]), check_finite=False)
            ch = evaluate(prob, sig, Y[-1], Y[:-1], jac=False)
        else:
            ch = evaluate(prob, sig, Y[-1], Y[:-1], jac=False)
        G = np.concatenate([ch.F, [t @ ((Y - Yp) / S)]])
        dY = lu_solve(lu, -G, check_finite=False)
        if not np.all(np.isfinite(dY)):
            return None
        size = np.max(np.abs(dY) / S)
        if Ja is not None and size > 0.5 * last:                  # the chord stalls: a fresh Jacobian
            lu = None
            if it > newton:
                return None
        last = size
        if size < 1e-13 and ch.J is None:              # converged at Y, whose residuals are in hand
            return _final(prob, sig, orbit_at(prob, sig, Y[-1], Y[:-1], ch))
        Y = Y + dY
        if size < 1e-13:
            break
    if np.any(Y[nz:nz + q] <= 0) or Y[-1] <= 0:
        return None
    return _final(prob, sig, orbit_at(prob, sig, Y[-1], Y[:-1]))


def _final(prob, sig, orb: HybridOrbit):
    """``orb`` if its residual is at round-off (after a Newton polish at its T if need be), else None."""
    if orb.residual <= ROUNDOFF:
        return orb
    if orb.residual > ACCEPT:
        return None
    try:
        return polish(prob, sig, orb.T, orb.X)
    except NotConverged:
        return None


def plausible(orb: HybridOrbit) -> bool:
    """The necessary conditions of admissibility that cost nothing: every impact comes in (``v_c > 0``) and the
    reaction pulls after every impact followed by a zero dwell."""
    return bool(np.all(orb.v_impact > 0) and np.all(orb.zero_margins < 0))


def follow(prob: Problem, sig: Signature, start: HybridOrbit, window: tuple[float, float], direction: float = 1.0,
           settings: FollowSettings | None = None) -> tuple[list[HybridOrbit], str]:
    """The curve of responses of signature ``sig`` through ``start``, in one direction of ``T``, inside ``window``.

    Returns the orbits in order (``start`` first) and why the curve ended.
    """
    st = settings or FollowSettings()
    Y = np.concatenate([start.X, [start.T]])
    out = [start]
    nz, q, _ = layout(prob, sig)
    h = st.h0
    prev = None
    bad = 0
    while len(out) < st.max_points:
        S = scale_of(prob, sig, Y[:-1], Y[-1])
        _, Ja = _jac(prob, sig, Y)
        t = _tangent(Ja, S, prev, direction)
        orb = None
        while h >= st.h_min:
            Yp = Y + h * t * S
            orb = correct(prob, sig, Yp, t, S, st.newton, Ja)
            if orb is not None and abs(orb.T - Y[-1]) <= 0.2 * Y[-1]:
                break
            orb = None
            if np.any(Yp[nz:nz + q] <= 0):
                d = Yp[nz:nz + q]
                return out, _duration_end(sig, int(np.argmin(d)))
            h *= 0.5
        if orb is None:
            return out, END_FAILED
        if not window[0] <= orb.T <= window[1]:
            return out, END_WINDOW
        Y = np.concatenate([orb.X, [orb.T]])
        out.append(orb)
        bad = 0 if plausible(orb) else bad + 1
        if bad >= st.patience:
            return out, END_INADMISSIBLE
        prev = t
        h = min(1.5 * h, st.h_max)
    return out, END_POINTS


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
