"""Pseudo-arclength continuation of the zero curves of ``D(T^I, T^II)``.

The traced function is the bounded, pole-free

``G = sign(det(Id - A)) (a1 b2 - a2 b1) / (a1^2 + b1^2 + a2^2 + b2^2)``,

bounded by 1/2 and signed so that it changes sign at the zeros of ``D`` only
(FORMULATION §4).  (Dividing by ``|(a1, b1)| |(a2, b2)|`` instead would be
singular where one residual vanishes for every phase, a point that zero
curves pass through.)  Curves are traced
in coordinates normalised to the search domain with a tangent predictor, a
corrector along the normal (secant iteration to round-off) and step control
on the corrector effort and the turning angle.

Every grid line the traced curve crosses is intersected exactly, so each
crossing of the grid scan is identified by its grid edge: continuation and
scan share their points to round-off, and a grid crossing that no trace
passed through seeds a new trace.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..model import Problem
from ..response import scan_G as G
from ..util.blas import single_thread_blas
from ..util.progress import progress_bar
from ..util.reprs import build, rng
from ..util.roots import bracketed
from .contour import link

__all__ = ["G", "Seed", "Trace", "trace", "trace_many", "curves"]

EPS = np.finfo(float).eps
SPECULATE = 64   #: traces run in lockstep (at most one speculative seed per marching-squares chain)


@dataclass
class Trace:
    """An ordered traced curve (points in ``(T1, T2)``), with how each end stopped."""

    P: np.ndarray
    edges: dict          # grid edge id -> index into P of the exact crossing point
    ends: tuple[str, str]
    nevals: int = 0

    def __repr__(self) -> str:
        P = np.asarray(self.P, float).reshape(-1, 2)
        return build("Trace", {"points": P.shape[0], "T1": rng(P[:, 0]), "T2": rng(P[:, 1]),
                               "grid_edges": len(self.edges), "ends": self.ends, "nevals": self.nevals})


class Seed(NamedTuple):
    """Where a trace starts: an exact zero ``point`` ``(T1, T2)`` of :func:`G` and the grid ``edge`` it lies on
    (None: none; a closed loop then stops when it returns to its first crossed edge)."""

    point: np.ndarray
    edge: int | None = None


class _Tracer:
    def __init__(self, prob, t1, t2, hmax=None, crossings=None, stop=None):
        self.prob = prob
        self.crossings = crossings
        self.stop = stop or set()
        self.t1, self.t2 = t1, t2
        self.lo = np.array([t1[0], t2[0]])
        self.span = np.array([t1[-1] - t1[0], t2[-1] - t2[0]])
        self.n1, self.n2 = t1.size, t2.size
        self.hmax = hmax or 1.0 / max(self.n1, self.n2)
        self.nevals = 0

    def halt(self, q, u0, pts, h):
        """Why the walker stops at the accepted point ``q`` (None: go on); a hook for :mod:`.follow`."""
        return None

    def T(self, u):
        return self.lo + np.asarray(u) * self.span

    # The methods below are generators: each ``yield`` hands points ``(T1, T2)`` (k, 2) to the driver
    # and receives G there (k,), so that a driver can evaluate many walkers in one batched call.

    def g(self, U):
        U = np.atleast_2d(U)
        self.nevals += len(U)
        return (yield self.T(U))

    def grad(self, u, d=1e-7):
        U = u + d * np.array([[1, 0], [-1, 0], [0, 1], [0, -1]])
        v = yield from self.g(U)
        return np.array([v[0] - v[1], v[2] - v[3]]) / (2 * d)

    def correct(self, p, n, slope, h):
        """Zero of g on the line ``p + s n`` near ``s = 0`` (secant), or None."""
        s0, g0 = 0.0, (yield from self.g(p))[0]
        if g0 == 0:
            return p
        if slope == 0 or not np.isfinite(slope):
            return None
        s1 = -g0 / slope
        for _ in range(30):
            if abs(s1) > 2 * h:
                return None
            g1 = (yield from self.g(p + s1 * n))[0]
            if g1 == 0 or abs(s1 - s0) <= 4 * EPS * (1 + abs(s1)):
                return p + s1 * n
            if g1 == g0:
                return p + s1 * n if abs(g1) < 1e-13 else None
            s0, s1, g0 = s1, s1 - g1 * (s1 - s0) / (g1 - g0), g1
        return None

    def root_on_line(self, axis, value, a, b, guess):
        """Exact zero of g on the grid line ``u_axis = value`` with the other coordinate in ``[a, b]``.

        The one bracketed root finder (:func:`plbar.util.roots.bracketed`) from
        the bracket, started at ``guess``; None if ``g`` does not change sign on the edge.
        """
        def pt(x):
            u = np.empty(2)
            u[axis] = value
            u[1 - axis] = x
            return u

        fa, fb = yield from self.g(np.array([pt(a), pt(b)]))
        if np.sign(fa) == np.sign(fb) or fa == 0 or fb == 0:
            return pt(a) if fa == 0 else (pt(b) if fb == 0 else None)
        gen = bracketed(a, b, fa, fb, 4 * EPS * max(abs(a), abs(b), 1e-3), x0=guess)
        try:
            _, x = next(gen)
            while True:
                _, x = gen.send((yield from self.g(pt(x[0]))))
        except StopIteration as stop:
            return pt(stop.value.x[0])

    def edge_crossings(self, u, q):
        """Crossings of the grid lines between consecutive points ``u -> q``; list of (frac, edge, point).

        With a table of the scan's refined crossings (edge id -> point), the
        point of the crossed edge is taken from it (the same root); without
        one it is located here on the grid line.
        """
        out = []
        grids = ((self.t1 - self.lo[0]) / self.span[0], (self.t2 - self.lo[1]) / self.span[1])
        H = (self.n1 - 1) * self.n2
        for axis in (0, 1):
            g = grids[axis]
            if q[axis] == u[axis]:
                continue
            # lines strictly past u, up to and including q (a point on a line belongs to the step that reached it)
            beyond = ((g - u[axis]) * (g - q[axis]) < 0) | (g == q[axis])
            for k in np.flatnonzero(beyond):
                frac = (g[k] - u[axis]) / (q[axis] - u[axis])
                other = u[1 - axis] + frac * (q[1 - axis] - u[1 - axis])
                og = grids[1 - axis]
                j0 = int(np.clip(np.searchsorted(og, other) - 1, 0, og.size - 2))
                found = None
                for j in (j0, j0 - 1, j0 + 1):
                    if not 0 <= j <= og.size - 2:
                        continue
                    # axis 0 fixed T1 = t1[k]: vertical edge (k, j)-(k, j+1);
                    # axis 1 fixed T2: horizontal (j, k)-(j+1, k)
                    eid = H + k * (self.n2 - 1) + j if axis == 0 else j * self.n2 + k
                    if self.crossings is not None:
                        if eid in self.crossings:
                            found = (eid, (self.crossings[eid] - self.lo) / self.span)
                            break
                    else:
                        pt = yield from self.root_on_line(axis, g[k], og[j], og[j + 1], other)
                        if pt is not None:
                            found = (eid, pt)
                            break
                if found is not None:
                    out.append((frac, found[0], found[1]))
        out.sort(key=lambda x: x[0])
        return out

    def march(self, u0, t0, max_steps, seen=None):
        """Points from ``u0`` along tangent ``t0`` until the domain edge, a closed loop or failure.

        ``seen`` (a set of edge ids, shared by both directions of one trace)
        detects a closed loop: the walker crosses an edge it already crossed.
        """
        pts, edges = [], []
        seen = set() if seen is None else seen
        u, t, h = u0.copy(), t0.copy(), self.hmax
        small = 0
        gr = yield from self.grad(u)
        for _ in range(max_steps):
            n = np.array([-t[1], t[0]])
            slope = gr @ n
            q = yield from self.correct(u + h * t, n, slope, h)
            if q is None:
                h *= 0.5
                if h < 1e-9:
                    return pts, edges, "step failure"
                continue
            small = small + 1 if h < 1e-4 * self.hmax else 0
            if small > 50:
                return pts, edges, "step failure"
            gq = yield from self.grad(q)
            tq = np.array([gq[1], -gq[0]])
            nq = np.linalg.norm(tq)
            if nq == 0:
                return pts, edges, "singular point"
            tq /= nq
            if tq @ t < 0:
                tq = -tq
            ang = np.arccos(np.clip(tq @ t, -1, 1))
            if ang > 0.2 and h > 1e-9:
                h *= 0.5
                continue
            closed = False
            for _frac, eid, pt in (yield from self.edge_crossings(u, q)):
                if eid in seen:
                    closed = True
                    break
                if np.all((pt >= -1e-12) & (pt <= 1 + 1e-12)):
                    seen.add(eid)
                    edges.append((len(pts), eid))
                    pts.append(pt)
                    if eid in self.stop:
                        return pts, edges, "stop edge"
            if closed:
                return pts, edges, "closed loop"
            inside = np.all((q >= 0) & (q <= 1))
            if not inside:
                return pts, edges, "domain edge"
            why = self.halt(q, u0, pts, h)
            if why:
                return pts, edges, why
            pts.append(q)
            u, t, gr = q, tq, gq
            h = min(h * (1.5 if ang < 0.05 else 1.0), self.hmax)
        return pts, edges, "max steps"


def trace(prob: Problem, t1: np.ndarray, t2: np.ndarray, seed: np.ndarray, hmax: float | None = None,
          max_steps: int = 20000, crossings: dict | None = None, seed_edge: int | None = None,
          stop: set | None = None) -> Trace:
    """Trace the zero curve of :func:`G` through ``seed`` (an exact zero, in ``(T1, T2)``).

    Parameters
    ----------
    t1, t2 : ndarray
        Grid axes of the scan (define the domain box and the grid lines).
    seed : ndarray, shape (2,)
    hmax : float, optional
        Largest step in normalised coordinates (default one grid cell).
    crossings : dict, optional
        The scan's refined crossings, edge id -> point ``(T1, T2)``.
    seed_edge : int, optional
        The grid edge the seed lies on (so a closed loop stops when it returns).
    stop : set of int, optional
        Grid edges where a walker stops after recording the crossing (the
        scan found no admissible response there: the branch ends within
        that grid cell).
    """
    return trace_many(prob, t1, t2, [Seed(seed, seed_edge)], hmax, max_steps, crossings, stop)[0]


def trace_many(prob: Problem, t1: np.ndarray, t2: np.ndarray, seeds, hmax: float | None = None,
               max_steps: int = 20000, crossings: dict | None = None, stop: set | None = None,
               drop_crossed: bool = False) -> list[Trace | None]:
    """:func:`trace` from several seeds (:class:`Seed`, or plain points: no seed edge), the walkers in lockstep.

    Each round evaluates the pending points of every walker in one batched
    :func:`G` call; every walker does exactly what :func:`trace` does, so the
    traces are the same (to round-off: a batched evaluation may differ from a
    single one in the last bit).  With ``drop_crossed``, a walker whose seed
    edge an earlier walker (in the order of ``seeds``) has crossed is dropped
    (its entry is None): it would trace the same curve.
    """
    seeds = [sd if isinstance(sd, Seed) else Seed(sd) for sd in seeds]
    seed_edges = [None if sd.edge is None else int(sd.edge) for sd in seeds]
    tracers = [_Tracer(prob, t1, t2, hmax, crossings, stop) for _ in seeds]
    seen = [set() for _ in seeds]
    gens = [_trace(tr, sd.point, max_steps, crossings, e, sn)
            for tr, sd, e, sn in zip(tracers, seeds, seed_edges, seen)]
    out: list = [None] * len(gens)
    pending = {}

    def step(i, value):
        try:
            pending[i] = gens[i].send(value)
        except StopIteration as stop_:
            out[i] = stop_.value
            pending.pop(i, None)

    with single_thread_blas:
        for i in range(len(gens)):
            step(i, None)
        while pending:
            if drop_crossed and len(pending) > 1:
                for j in list(pending):
                    e = seed_edges[j]
                    if e is not None and any(e in seen[i] for i in range(j) if out[i] is not None or i in pending):
                        gens[j].close()
                        del pending[j]
            idx = list(pending)
            if not idx:
                break
            pts = [pending[i] for i in idx]
            allT = np.concatenate(pts) if len(pts) > 1 else pts[0]
            v = G(prob, allT[:, 0], allT[:, 1])
            off = 0
            for i, p in zip(idx, pts):
                step(i, v[off:off + len(p)])
                off += len(p)
    return out


def _trace(tr: _Tracer, seed, max_steps, crossings, seed_edge, seen: set) -> Trace:
    u0 = (np.asarray(seed, float) - tr.lo) / tr.span
    gr = yield from tr.grad(u0)
    t0 = np.array([gr[1], -gr[0]])
    t0 /= np.linalg.norm(t0) or 1.0
    if seed_edge is not None:
        seen.add(int(seed_edge))
    fwd, efwd, endf = yield from tr.march(u0, t0, max_steps, seen)
    if endf == "closed loop":
        bwd, ebwd, endb = [], [], "closed loop"
    else:
        bwd, ebwd, endb = yield from tr.march(u0, -t0, max_steps, seen)
    P = np.array(bwd[::-1] + [u0] + fwd)
    nb = len(bwd)
    edges = {eid: nb - 1 - i for i, eid in ebwd}
    edges.update({eid: nb + 1 + i for i, eid in efwd})
    if seed_edge is not None:
        edges[int(seed_edge)] = nb
    T = tr.T(P)
    if crossings is not None:           # crossing points exactly as the scan refined them
        for eid, i in edges.items():
            T[i] = crossings[eid]
    return Trace(T, edges, (endb, endf), tr.nevals)


def _seed_order(sc, seeds: set) -> tuple[list, dict]:
    """Admissible crossings in marching-squares chain order, and the stretch (chain, run) of each.

    Chains are walks along the zero curves; a run of admissible crossings
    between two others is a "stretch", which one trace usually covers.
    """
    seq, stretch = [], {}
    for ci, chain in enumerate(sorted(link(sc.G, sc.hmask, sc.vmask), key=len, reverse=True)):
        k, prev = 0, False
        for e in chain:
            good = e in seeds
            if good:
                k += not prev
                seq.append(e)
                stretch[e] = (ci, k)
            prev = good
    return seq, stretch


def curves(prob: Problem, sc, zero: np.ndarray, good: np.ndarray, progress: bool = False) -> list:
    """Continuation traces seeded by the admissible crossings of the scan ``sc``.

    Walkers stop at crossings the scan found inadmissible (or not periodic),
    so only the admissible stretches of the zero curves are traced.  The
    traces are those of the sequential rule "seed a trace at every admissible
    crossing, in chain order, that no earlier trace passed through"; to batch
    the walkers they run in lockstep from the first unvisited seed of each of
    the next stretches, a walker whose seed an earlier one crosses is dropped,
    and a trace is used only when the sequential rule reaches its seed
    unvisited.  Returns a list of (points (M, 2), ends).
    """
    ids, P = sc.ids, sc.P
    crossings = {int(e): P[k] for k, e in enumerate(ids) if zero[k]}
    stop = {int(e) for k, e in enumerate(ids) if zero[k] and not good[k]}
    seeds = {int(e) for k, e in enumerate(ids) if good[k]}
    seq, stretch = _seed_order(sc, seeds)
    visited: set[int] = set()
    cache: dict[int, object] = {}
    out = []
    bar = progress_bar(len(seeds), progress, "tracing", "edge")
    for pos, e in enumerate(seq):
        if e in visited:
            continue
        if cache.get(e) is None:
            batch, used = [e], {stretch[e]}
            for e2 in seq[pos + 1:]:
                if len(batch) >= SPECULATE:
                    break
                if stretch[e2] not in used and e2 not in visited and cache.get(e2) is None:
                    used.add(stretch[e2])
                    batch.append(e2)
            trs = trace_many(prob, sc.t1, sc.t2, [Seed(crossings[b], b) for b in batch], crossings=crossings,
                             stop=stop, drop_crossed=True)
            cache.update(zip(batch, trs))
        tr = cache.pop(e)
        bar.update(len((set(tr.edges) - visited) & seeds))
        visited |= set(tr.edges)
        out.append((tr.P, tr.ends))
    bar.close()
    return out
