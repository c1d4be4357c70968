"""Following zero curves of ``G`` without a scan, inside a period window (for mesh refinement).

The scan-free use of the walker of :mod:`.continuation` (tangent predictor,
corrector along the normal, step control on the corrector effort and the
turning angle).  Coordinates are those of a :class:`Band`: ``T^I`` and the
forcing period ``T = T^I + T^II``, normalised to the window, so the window's
edges are the walker's domain edges and every crossing of them is located
exactly.  Points move onto a curve with :func:`correct_onto` (a sign change
of ``G`` along a direction, refined by the one root finder) and curves are
followed from them with :func:`follow`, which stops a walker at the window
edge, when its curve closes, or when it has left the neighbourhood of a set
of *carried* points (the family it is meant to follow) for a while.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model import Problem
from ..response import scan_G as G
from ..util.blas import single_thread_blas
from ..util.roots import solve
from ..util.threads import map_chunks
from .branches import Domain
from .continuation import Trace, _Tracer
from .evaluate import evaluate

__all__ = ["Band", "correct_onto", "follow", "follow_one", "WINDOW_EDGE", "CLOSED_LOOP", "LEFT_FAMILY"]

WINDOW_EDGE = "window edge"                   #: a walker reached the window's edge
CLOSED_LOOP = "closed loop"                   #: a walker came back to its seed
LEFT_FAMILY = "left the carried family"       #: a walker stayed away from the carried points


@dataclass(frozen=True)
class Band:
    """A period window: ``T^I`` in ``T1`` and ``T = T^I + T^II`` in ``T``.

    Normalised coordinates ``u = ((T^I - T1_lo) / span1, (T - T_lo) / span2)`` map
    the window onto the unit square.
    """

    T1: tuple[float, float]
    T: tuple[float, float]

    def __post_init__(self):
        (a, b), (c, d) = self.T1, self.T
        if not (0 <= a < b and 0 < c < d and b < d):
            raise InputError(f"window T1 = {self.T1}, T = {self.T} is empty; it needs 0 <= T1_lo < T1_hi, "
                             "0 < T_lo < T_hi and T1_hi < T_hi")
        object.__setattr__(self, "T1", (float(a), float(b)))
        object.__setattr__(self, "T", (float(c), float(d)))

    @property
    def lo(self) -> np.ndarray:
        return np.array([self.T1[0], self.T[0]])

    @property
    def span(self) -> np.ndarray:
        return np.array([self.T1[1] - self.T1[0], self.T[1] - self.T[0]])

    def to_u(self, P) -> np.ndarray:
        """Normalised coordinates of points ``(T^I, T^II)``, shape ``(..., 2)``."""
        P = np.asarray(P, float)
        return (np.stack([P[..., 0], P[..., 0] + P[..., 1]], axis=-1) - self.lo) / self.span

    def from_u(self, U) -> np.ndarray:
        """Points ``(T^I, T^II)`` of normalised coordinates."""
        V = self.lo + np.asarray(U, float) * self.span
        return np.stack([V[..., 0], V[..., 1] - V[..., 0]], axis=-1)

    def contains(self, P, tol: float = 1e-12) -> np.ndarray:
        """Which points ``(T^I, T^II)`` lie in the window (edges included)."""
        U = self.to_u(P)
        return np.all((U >= -tol) & (U <= 1 + tol), axis=-1)

    def domain(self) -> Domain:
        """The smallest ``(T^I, T^II)`` rectangle holding the window (what a grid scan covers)."""
        return Domain(self.T1, (max(self.T[0] - self.T1[1], 0.0), self.T[1] - self.T1[0]))


class _BandTracer(_Tracer):
    """The continuation walker in window coordinates, with closure and carried-family stops."""

    def __init__(self, prob, band: Band, hmax: float, carried=None, reach: float = 0.0, patience: int = 0):
        super().__init__(prob, np.array(band.T1), np.array(band.T), hmax)
        self.band = band
        self.carried = None if carried is None or not len(carried) else np.asarray(carried, float)
        self.reach, self.patience = reach, patience
        self._free: dict = {}        # point -> far from the carried points and not admissible

    def T(self, u):
        return self.band.from_u(u)

    def grad(self, u, d=1e-7):
        """Forward differences: ``G(u)`` is zero (to round-off) wherever the walker asks (seeds, corrected points)."""
        v = yield from self.g(u + d * np.eye(2))
        return v / d

    def _away(self, q) -> bool:
        """``q`` is farther than ``reach`` from every carried point and its response is not admissible."""
        key = tuple(q)
        if key not in self._free:
            far = np.linalg.norm(self.carried - q, axis=1).min() > self.reach
            self._free[key] = bool(far and not evaluate(self.prob, self.T(q[None])).good[0])
        return self._free[key]

    def halt(self, q, u0, pts, h):
        if len(pts) >= 3 and np.linalg.norm(q - u0) < 0.5 * h:
            if np.linalg.norm(np.asarray(pts) - u0, axis=1).max() > 2 * h:
                return CLOSED_LOOP
        if self.carried is not None and self._away(q) and len(pts) >= self.patience:
            if all(self._away(p) for p in pts[len(pts) - self.patience:]):
                return LEFT_FAMILY
        return None


def _trace_band(tr: _BandTracer, u0: np.ndarray, max_steps: int):
    """Both directions from ``u0`` (a zero of ``G``), as :func:`.continuation.trace` does (a generator)."""
    gr = yield from tr.grad(u0)
    t0 = np.array([gr[1], -gr[0]])
    t0 /= np.linalg.norm(t0) or 1.0
    fwd, _, endf = yield from tr.march(u0, t0, max_steps)
    if endf == CLOSED_LOOP:
        bwd, endb = [], CLOSED_LOOP
    else:
        bwd, _, endb = yield from tr.march(u0, -t0, max_steps)
    U = np.array(bwd[::-1] + [u0] + fwd)
    ends = tuple(WINDOW_EDGE if e == "domain edge" else e for e in (endb, endf))
    return U, ends


PARALLEL_DOFS = 48   #: from this many DOFs on, even two points of ``G`` are evaluated on two threads


def _G(prob: Problem, P: np.ndarray) -> np.ndarray:
    """``G`` at points ``P`` (K, 2), split over the thread pool for large systems (one LU per point)."""
    one = 1 if prob.system.n >= PARALLEL_DOFS else 64
    with single_thread_blas:
        return np.concatenate(map_chunks(lambda a, b: G(prob, P[a:b, 0], P[a:b, 1]), len(P), one))


def _drive(prob: Problem, gen):
    """Run a walker generator, evaluating ``G`` at the points it yields."""
    try:
        P = next(gen)
        while True:
            P = gen.send(_G(prob, P))
    except StopIteration as stop:
        return stop.value


def correct_onto(prob: Problem, band: Band, U, D, reach, steps: int = 4):
    """Move normalised points ``U`` (K, 2) onto the zero set of ``G`` along unit directions ``D`` (K, 2).

    ``G`` is sampled at ``2 steps + 1`` points ``U + s D``, ``|s| <= reach`` (a
    scalar or one per point); the sign change nearest ``s = 0`` is refined to
    round-off with the one bracketed root finder (``G`` changes sign at zeros of
    ``D`` only, never at its poles).

    Returns
    -------
    V : ndarray, shape (K, 2)
        The corrected points (nan rows where ``G`` has no sign change within ``reach``).
    evaluations : int
    """
    U, D = np.atleast_2d(np.asarray(U, float)), np.atleast_2d(np.asarray(D, float))
    K = len(U)
    R = np.broadcast_to(np.asarray(reach, float), (K,))
    s = np.linspace(-1.0, 1.0, 2 * steps + 1)[None, :] * R[:, None]            # (K, 2 steps + 1)
    g = _G(prob, band.from_u(U[:, None, :] + s[..., None] * D[:, None, :]).reshape(-1, 2)).reshape(s.shape)
    neg = g < 0
    V = np.full((K, 2), np.nan)
    k, j = np.nonzero(neg[:, :-1] != neg[:, 1:])
    if not k.size:
        return V, s.size
    order = np.lexsort((np.abs(s[k, j] + s[k, j + 1]), k))
    first = np.r_[True, k[order][1:] != k[order][:-1]]
    k, j = k[order][first], j[order][first]
    count = [s.size]

    def f(idx, x):
        count[0] += idx.size
        return _G(prob, band.from_u(U[k[idx]] + x[:, None] * D[k[idx]]))

    r = solve(f, s[k, j], s[k, j + 1], g[k, j], g[k, j + 1], 4 * np.finfo(float).eps * np.maximum(R[k], 1.0))
    V[k] = U[k] + r.x[:, None] * D[k]
    return V, count[0]


def follow_one(prob: Problem, band: Band, seed, hmax: float, carried=None, reach: float | None = None,
               patience: int = 20, max_steps: int = 20000) -> tuple[np.ndarray, Trace]:
    """The zero curve of ``G`` through one ``seed`` (normalised), both ways (see :func:`follow`).

    Returns the curve in normalised coordinates and as a :class:`Trace` in ``(T^I, T^II)``.
    """
    reach = 8 * hmax if reach is None else reach
    tr = _BandTracer(prob, band, hmax, carried, reach, patience)
    U, ends = _drive(prob, _trace_band(tr, np.asarray(seed, float), max_steps))
    return U, Trace(band.from_u(U), {}, ends, tr.nevals)


def follow(prob: Problem, band: Band, seeds, hmax: float, carried=None, reach: float | None = None,
           patience: int = 20, max_steps: int = 20000) -> list[Trace]:
    """Follow the zero curves of ``G`` through ``seeds`` inside ``band``.

    Parameters
    ----------
    prob : Problem
    band : Band
    seeds : array_like, shape (K, 2)
        Zeros of ``G`` in normalised window coordinates (see :func:`correct_onto`),
        in order along the family; a seed within ``2 hmax`` of a curve already
        followed is skipped (it lies on that curve).
    hmax : float
        Largest step, in normalised coordinates.
    carried : array_like, shape (M, 2), optional
        Normalised points of the family being followed; a walker that stays
        farther than ``reach`` (default ``8 hmax``) from all of them, on
        responses that are not admissible, for ``patience`` steps stops
        (``"left the carried family"``): an admissible stretch is followed to its end.

    Returns
    -------
    list of Trace
        Ordered points ``(T^I, T^II)`` and the reason each end stopped
        (``"window edge"``, ``"closed loop"``, ``"left the carried family"``,
        ``"step failure"``, ``"singular point"``).
    """
    out, done = [], []
    for u in np.atleast_2d(np.asarray(seeds, float)):
        if not np.all(np.isfinite(u)) or any(np.linalg.norm(d - u, axis=1).min() < 2 * hmax for d in done):
            continue
        U, tr = follow_one(prob, band, u, hmax, carried, reach, patience, max_steps)
        done.append(U)
        out.append(tr)
    return out
