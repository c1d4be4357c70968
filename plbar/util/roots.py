"""The one bracketed root finder of plbar: batched Anderson-Björck (modified regula falsi).

Every sign-change refinement in the package goes through :func:`bracketed`:
the scan's grid edges (:mod:`plbar.paths.scan`), the grid-line crossings of
the continuation walkers (:mod:`plbar.paths.continuation`) and the fallback
of :func:`plbar.find_response`.  It is a *generator* so that the caller
decides how the function is evaluated (one batched call for all brackets, a
walker that hands its points to a lockstep driver, or a scalar loop that may
stop early on its own acceptance test); :func:`solve` drives it with a plain
batched function.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Roots", "bracketed", "solve"]


@dataclass(frozen=True)
class Roots:
    """Result of :func:`bracketed`: the roots, iterations used and which brackets converged."""

    x: np.ndarray
    iterations: int
    converged: np.ndarray


def _update(a, b, fa, fb, side, x, f):
    """One Anderson-Björck bracket update (in place on the active slices); returns the new arrays."""
    left = np.sign(f) == np.sign(fa)
    prev = np.where(left, fa, fb)
    with np.errstate(divide="ignore", invalid="ignore"):
        m = 1.0 - f / prev
    m = np.where((m > 0) & np.isfinite(m), m, 0.5)       # Illinois halving where the AB factor fails
    na = np.where(left, x, a)
    nfa = np.where(left, f, np.where(side == -1, m * fa, fa))
    nb = np.where(left, b, x)
    nfb = np.where(left, np.where(side == 1, m * fb, fb), f)
    return na, nb, nfa, nfb, np.where(left, 1, -1)


def bracketed(a, b, fa, fb, tol, x0=None, maxit: int = 100):
    """Refine a root in each bracket ``[a, b]`` with ``f(a) f(b) < 0`` (a generator).

    Parameters
    ----------
    a, b, fa, fb : array_like, shape (E,)
        Bracket ends and the function values there.
    tol : float or array_like
        Absolute tolerance in ``x``: a bracket stops when its width, or the
        step between two iterates, is at most ``tol`` (or ``f(x) == 0``).
    x0 : array_like, optional
        First iterate of each bracket (clipped into it); default regula falsi.
    maxit : int
        Largest number of rounds.

    Yields
    ------
    idx, x : ndarray
        Indices of the still-active brackets and their next points; send back
        ``f(x)`` (same shape as ``x``).

    Returns
    -------
    Roots
        Through ``StopIteration.value``: the last iterate of each bracket (the
        better end where none was evaluated).
    """
    a, b, fa, fb = (np.array(v, float) for v in np.broadcast_arrays(*np.atleast_1d(a, b, fa, fb)))
    tol = np.broadcast_to(np.asarray(tol, float), a.shape)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    last = np.full(a.shape, np.nan)
    side = np.zeros(a.shape, int)
    active = np.ones(a.shape, bool)
    it = 0
    for it in range(maxit):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        A, B, FA, FB = a[idx], b[idx], fa[idx], fb[idx]
        if it == 0 and x0 is not None:
            x = np.clip(np.broadcast_to(np.asarray(x0, float), a.shape)[idx], lo[idx], hi[idx])
        else:
            x = (A * FB - B * FA) / (FB - FA)
            inside = (x > np.minimum(A, B)) & (x < np.maximum(A, B))
            x = np.where(inside, x, 0.5 * (A + B))
        f = np.asarray((yield idx, x), float)
        a[idx], b[idx], fa[idx], fb[idx], side[idx] = _update(A, B, FA, FB, side[idx], x, f)
        done = (f == 0) | (np.abs(b[idx] - a[idx]) <= tol[idx]) | (np.abs(x - last[idx]) <= tol[idx])
        last[idx] = x
        active[idx[done]] = False
    x = np.where(np.isnan(last), np.where(np.abs(fa) <= np.abs(fb), a, b), last)
    return Roots(x, it, ~active)


def solve(f, a, b, fa, fb, tol, x0=None, maxit: int = 100) -> Roots:
    """:func:`bracketed` driven by a batched function ``f(idx, x) -> values``."""
    gen = bracketed(a, b, fa, fb, tol, x0, maxit)
    try:
        idx, x = next(gen)
        while True:
            idx, x = gen.send(f(idx, x))
    except StopIteration as stop:
        return stop.value
