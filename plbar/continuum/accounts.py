"""The survey's accounts of a continuum run, from the delay line (pure functions over arrays).

Integrals over time and space are Gauss-Legendre on intervals cut at every jump and kink the delay line can
carry (the piece ends, mapped along the characteristics), so each is exact to round-off for the stored fields.
The work and the space integrals (bar energy, ``int rhoA v^2 dx``) are compiled (:mod:`.kernel.accounts`).
"""

from __future__ import annotations


import numpy as np

from .fields import Line, constants, invariants, pieces
from .kernel.accounts import space_into, work_into

__all__ = ["gauss", "work", "bar_energy", "velocity_square", "strobe"]

_X, _W = np.polynomial.legendre.leggauss(6)

def gauss(f, edges: np.ndarray, chunk: int = 1 << 16) -> np.ndarray:
    """Integrals of ``f`` over each interval of the sorted ``edges`` (6-point Gauss-Legendre), shape (len - 1,);
    ``chunk`` intervals at a time (memory)."""
    out = np.empty(max(edges.size - 1, 0))
    for lo in range(0, out.size, chunk):
        hi = min(lo + chunk, out.size)
        a, b = edges[lo:hi], edges[lo + 1:hi + 1]
        h = 0.5 * (b - a)
        pts = (0.5 * (a + b))[:, None] + h[:, None] * _X[None, :]
        out[lo:hi] = h * (f(pts) @ _W)
    return out


def _cuts(values, lo: float, hi: float, *extra) -> np.ndarray:
    v = np.concatenate([np.asarray(values, float).ravel()] + [np.atleast_1d(np.asarray(e, float)) for e in extra])
    v = np.unique(v[(v > lo) & (v < hi)])
    return np.concatenate([[lo], v, [hi]])


def work(ln: Line, T: float, periods: int) -> np.ndarray:
    """Work of the load per period, ``int F(t) v(s, t) dt``, shape (periods,)."""
    d, P = (ln.L - ln.s) / ln.c, 2 * ln.L / ln.c
    bounds = T * np.arange(periods + 1)
    edges = _cuts(np.concatenate([ln.t0 + d, ln.t0 + P - d]), 0.0, bounds[-1], bounds, 2 * ln.s / ln.c)
    out = np.zeros(periods)
    work_into(pieces(ln), constants(ln), edges, float(T), out)
    return out


def _integrals(ln: Line, ts, kind: int) -> np.ndarray:
    ts = np.ascontiguousarray(ts, float)
    out = np.empty(ts.size)
    space_into(pieces(ln), constants(ln), ts, kind, out)
    return out


def _x_cuts(ln: Line, t: float) -> np.ndarray:
    P = 2 * ln.L / ln.c
    lo = max(int(np.searchsorted(ln.t0, t - P)) - 1, 0)
    hi = int(np.searchsorted(ln.t0, t, side="right")) + 1
    t0, t1 = ln.t0[lo:hi], ln.t1[lo:hi]  # only the pieces of the last 2L/c are in the bar at time t
    xs = np.concatenate([ln.L - ln.c * (t - t0), ln.L - ln.c * (t0 + P - t), ln.L - ln.c * (t - t1),
                         ln.L - ln.c * (t1 + P - t)])
    more = [ln.s, ln.s - ln.c * t, 2 * ln.L - ln.c * t - ln.s, ln.c * t - ln.s]
    return _cuts(xs, 0.0, ln.L, *more)


def bar_energy(ln: Line, t):
    """Kinetic plus strain energy of the bar at time(s) ``t``: ``rhoA / 4 int (w+^2 + w-^2) dx`` (float for a
    float, else an array)."""
    out = _integrals(ln, np.atleast_1d(t), 0)
    return float(out[0]) if np.ndim(t) == 0 else out


def velocity_square(ln: Line, T: float, first: int, periods: int, n: int) -> np.ndarray:
    """``int int rhoA v^2 dx dt`` per period for periods ``first .. periods - 1`` (Gauss in ``x`` at each time,
    trapezoid in ``t`` on ``n`` samples per ``L / c``: second order, the space integral is continuous in ``t``)."""
    m = max(2, int(np.ceil(T * ln.c / ln.L * n)))
    out = []
    for p in range(first, periods):
        ts = np.linspace(p * T, (p + 1) * T, m + 1)
        out.append(np.trapezoid(_integrals(ln, ts, 1), ts))
    return np.asarray(out)


def strobe(ln: Line, t: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``u, v`` at the ``n + 1`` grid points ``x_j = j L / n`` at time ``t`` (``u`` integrates ``u_x`` exactly)."""
    x = np.linspace(0.0, ln.L, n + 1)
    wp, wm = invariants(ln, x, t)
    cuts = _x_cuts(ln, t)
    edges = np.unique(np.concatenate([cuts, x]))
    ux = lambda y: 0.5 * np.subtract(*invariants(ln, y, t)[::-1]) / ln.c  # noqa: E731 -- (w- - w+) / 2c
    cum = np.concatenate([[0.0], np.cumsum(gauss(ux, edges))])
    u = cum[np.searchsorted(edges, x)]
    return u, 0.5 * (wp + wm)
