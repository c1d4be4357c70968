"""Newton on the chain's residuals in compiled code: the continuation's step and corrector, and the polish.

The loops of :func:`plbar.periodic.follow.follow` (one step: the tangent, then the corrector from the predicted
point, halving the step where it fails), :func:`plbar.periodic.follow.correct` and :func:`plbar.periodic.polish`
(their docstrings say what they do), with the chain walked by :func:`.walk.chain` and the linear systems
solved by LU with partial pivoting (:func:`lu_factor`, :func:`lu_solve`: a few dozen unknowns at most).  The
tangent is the null vector of the augmented Jacobian, from the bordered system ``[Ja S; c] x = e`` (``c`` the
last tangent, or the direction in ``T`` at the first point: the orientation is kept, ``c . t > 0``).  The
problem is a :class:`plbar.periodic.packed.ChainModel` ``md``, the signature a :class:`plbar.periodic.packed.Pairs`
``sig``.
"""

from __future__ import annotations

from math import inf, isfinite, sqrt

import numpy as np

from ..packed import CHORD, CONVERGED, DONE, ENDED, FAILED, FOLLOW, NEWTON, SINGULAR, Walk
from .stamp import cached, jit
from .walk import chain, copy, relative, start_size, walk_space

__all__ = ["lu_factor", "lu_solve", "augmented", "tangent", "correct", "step", "polish", "FAILED",
           "CONVERGED", "DONE", "SINGULAR", "ENDED", "FOLLOW", "CHORD", "NEWTON"]

STEP_TOL = 1e-13                      #: the corrector's last step (scaled)
FLOOR_TOL = 1e-10                     #: a step that stalls below this is round-off: the residual decides


@jit
def lu_factor(A, piv):
    """LU of ``A`` in place (row pivots in ``piv``); False if a pivot is zero (singular) or not finite."""
    n = A.shape[0]
    for k in range(n):
        p, big = k, abs(A[k, k])
        for i in range(k + 1, n):
            if abs(A[i, k]) > big:
                p, big = i, abs(A[i, k])
        piv[k] = p
        if not big > 0.0 or not isfinite(big):
            return False
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
        for i in range(k + 1, n):
            a = A[i, k] / A[k, k]
            A[i, k] = a
            if a != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= a * A[k, j]
    return True


@jit
def lu_solve(A, piv, b):
    """Solve ``A x = b`` in place in ``b`` from :func:`lu_factor`."""
    n = A.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
    for i in range(n):
        s = b[i]
        for j in range(i):
            s -= A[i, j] * b[j]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= A[i, j] * b[j]
        b[i] = s / A[i, i]


@jit
def augmented(md, sig, Y, F, A):
    """``F`` at ``Y = (X, T)`` and the Jacobian in ``Y`` into the first rows of ``A``: exact in ``X``, the column in
    ``T`` a forward difference (step ``1e-7 T``); returns the switch scales."""
    nX = Y.size - 1
    X, T = Y[:nX], Y[nX]
    J, F2 = np.empty((nX, nX)), np.empty(nX)
    w = walk_space(md, sig.dwell, F, J)
    chain(md, sig, T, X, w)
    h = 1e-7 * T
    chain(md, sig, T + h, X, Walk(F2, np.empty((0, 0)), w.times, w.zs, w.zero, np.empty(w.scale.size), w.vimp))
    for i in range(nX):
        copy(J[i], A[i])
        A[i, nX] = (F2[i] - F[i]) / h
    return w.scale


@jit
def tangent(Ja, S, c, t):
    """Unit tangent ``t`` of the curve in scaled coordinates: ``[Ja S; c] x = e_n``, normalised (``c . t > 0``);
    False where that system is singular."""
    n = S.size
    A, piv = np.empty((n, n)), np.empty(n, np.int64)
    for j in range(n):
        for i in range(n - 1):
            A[i, j] = Ja[i, j] * S[j]
        A[n - 1, j] = c[j]
        t[j] = 0.0
    t[n - 1] = 1.0
    if not lu_factor(A, piv):
        return False
    lu_solve(A, piv, t)
    norm = 0.0
    for j in range(n):
        norm += t[j] * t[j]
    norm = sqrt(norm)
    for j in range(n):
        t[j] /= norm
    return isfinite(norm)


@jit
def _positive(Y, nz, q):
    """Every duration positive."""
    for i in range(nz, nz + q):
        if not Y[i] > 0:
            return False
    return True


@jit
def _newton_step(A, piv, F, Y, Yp, t, S, dY):
    """The Newton step of the bordered system into ``dY``; its scaled size (inf if not finite)."""
    n = Y.size
    s = 0.0
    for i in range(n):
        s += t[i] * (Y[i] - Yp[i]) / S[i]
        if i < n - 1:
            dY[i] = -F[i]
    dY[n - 1] = -s
    lu_solve(A, piv, dY)
    size = 0.0
    for i in range(n):
        if not isfinite(dY[i]):
            return inf
        size = max(size, abs(dY[i]) / S[i])
    return size


@jit
def correct(md, sig, Yp, t, S, newton, Ja, chord, Y):
    """Newton on ``F = 0`` and ``t . (Y - Yp) / S = 0`` from ``Yp`` into ``Y``: :data:`FAILED`, :data:`CONVERGED` (at
    ``Y``: the step from it, with residuals only, is below :data:`STEP_TOL`) or :data:`DONE` (the last step, below
    :data:`STEP_TOL`, taken; or the steps stalled below :data:`FLOOR_TOL`, at the round-off of the residuals:
    whether ``Y`` is a response is then its residual's to say, :func:`plbar.periodic.follow.correct`).

    With ``chord`` the augmented Jacobian ``Ja`` at the last point is factorised once and every iteration
    evaluates only the residuals (a chord method); a fresh Jacobian where the chord stalls.
    """
    n, nz = Yp.size, start_size(md, sig.dwell)
    q = n - nz - 2
    A, piv = np.empty((n, n)), np.empty(n, np.int64)
    F, dY = np.empty(n - 1), np.empty(n)
    w = walk_space(md, sig.dwell, F, np.empty((0, 0)))
    copy(Yp, Y)
    have, last = False, inf
    for it in range(2 * newton if chord else newton):
        if not (_positive(Y, nz, q) and Y[n - 1] > 0):
            return FAILED
        fresh = not chord or (not have and it > 0)
        if fresh:
            augmented(md, sig, Y, F, A)
        else:
            chain(md, sig, Y[n - 1], Y[:n - 1], w)
        if fresh or not have:
            for i in range(n):
                if not fresh and i < n - 1:
                    copy(Ja[i], A[i])
                A[n - 1, i] = t[i] / S[i]
            if not lu_factor(A, piv):
                return FAILED
            have = True
        size = _newton_step(A, piv, F, Y, Yp, t, S, dY)
        if size == inf:
            return FAILED
        if chord and size > 0.5 * last:               # the chord stalls
            if size < FLOOR_TOL:                      # at the round-off floor: the residual decides (the caller)
                Y += dY
                break
            have = False                              # else a fresh Jacobian
            if it > newton:
                return FAILED
        last = size
        if size < STEP_TOL and not fresh:             # converged at Y, whose residuals are in hand
            return CONVERGED
        Y += dY
        if size < STEP_TOL:
            break
    return DONE if _positive(Y, nz, q) and Y[n - 1] > 0 else FAILED


def _step(stamp):
    def step(md, sig, Y, S, c, Ja, ctl, t, Ynew):
        """``(outcome, h)``: with ``ctl.mode`` :data:`FOLLOW` a continuation step from ``Y`` (the tangent ``t`` from
        ``c``; the corrector from ``Y + h t S`` into ``Ynew``, ``h = ctl.h`` halved where it fails, down to
        ``ctl.h_min``; :data:`ENDED` where the predicted point has a duration that is not positive); with
        :data:`CHORD` (on ``Ja``) or :data:`NEWTON` one correction from ``Y`` along ``t = c``
        (:class:`plbar.periodic.packed.Control`).  The outcomes of :func:`correct`."""
        n, h, h_min, newton, mode = Y.size, ctl.h, ctl.h_min, ctl.newton, ctl.mode
        if mode == FOLLOW:
            Ja = np.empty((n - 1, n))
            augmented(md, sig, Y, np.empty(n - 1), Ja)
            if not tangent(Ja, S, c, t) or stamp < 0:      # (the stamp keys the on-disk cache)
                return FAILED, h
        else:
            copy(c, t)
        nz = start_size(md, sig.dwell)
        Yp = np.empty(n)
        while h >= h_min:
            for i in range(n):
                Yp[i] = Y[i] + h * t[i] * S[i]
            out = correct(md, sig, Yp, t, S, newton, Ja, mode != NEWTON, Ynew)
            if out != FAILED or mode != FOLLOW:
                return out, h
            if not _positive(Yp, nz, n - nz - 2):
                return ENDED, h
            h *= 0.5
        return FAILED, h

    return step


def _polish(stamp):
    def polish(md, sig, T, X, maxit, roundoff):
        """Newton on the chain's residuals from ``X`` (in place; damped by halving): :data:`DONE` or
        :data:`SINGULAR`."""
        nX, nz = X.size, start_size(md, sig.dwell)
        q = nX - nz - 1
        F, J, Fn = np.empty(nX), np.empty((nX, nX)), np.empty(nX)
        piv, dX, Xn = np.empty(nX, np.int64), np.empty(nX), X.copy()
        w = walk_space(md, sig.dwell, F, J)
        wn = Walk(Fn, np.empty((0, 0)), w.times, w.zs, w.zero, np.empty(w.scale.size), w.vimp)   # residuals only
        for _ in range(maxit if stamp >= 0 else 0):     # (the stamp keys the on-disk cache)
            r = chain(md, sig, T, X, w)
            if r <= roundoff:
                break
            if not lu_factor(J, piv):
                return SINGULAR
            for i in range(nX):
                dX[i] = -F[i]
            lu_solve(J, piv, dX)
            lam = 1.0
            for _ in range(20):
                for i in range(nX):
                    Xn[i] = X[i] + lam * dX[i]
                if _positive(Xn, nz, q):
                    chain(md, sig, T, Xn, wn)
                    if relative(Fn, w.scale, X, nz, T) < r or lam < 1e-3:     # at the scales of X
                        break
                lam *= 0.5
            copy(Xn, X)
        return DONE

    return polish


step = cached(_step)       #: entry point (:func:`_step`)
polish = cached(_polish)   #: entry point (:func:`_polish`)
