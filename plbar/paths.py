"""Periodic paths: scan ``D(T^I, T^II)``, refine, link into ordered branches.

The paper scans the 3D space ``(T^I, T^II, phi)`` (Sec. 4.1).  With ``phi``
eliminated exactly (FORMULATION §4) the paths are the zero set of one scalar
field on the ``(T^I, T^II)`` plane.  This module

1. evaluates ``G = D sign(det(Id - A)) / |a, b|^2`` on a grid in batches (``G`` changes
   sign at the zeros of ``D`` but not at its poles);
2. refines every grid edge with a sign change to machine precision with a
   batched Anderson-Björck (modified regula falsi) iteration;
3. keeps the true zeros (switch residuals at round-off), picks the admissible
   one of ``phi`` and ``phi + pi`` (:mod:`plbar.admissible`);
4. links the crossings into curves with the marching-squares topology and
   cuts them into maximal admissible runs: the branches.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from . import admissible, stability
from .energy import Damping, damping
from ._threads import map_chunks
from .errors import InputError
from .orbit import Orbits, orbits
from .periodic import Coefficients, coefficients, phase
from .system import Problem

__all__ = ["Domain", "Branch", "Paths", "find_paths", "scan_field", "default_domain"]

ZERO_TOL = 1e-7   #: relative switch residual below which a refined crossing is a zero of D
PERIODIC_TOL = 1e-10  #: relative periodicity error (through the flow) a path point must meet


def periodicity_error(orb: Orbits) -> np.ndarray:
    """``|z(T+) - z(0)| / |z(0)|`` with ``z(T+)`` from the closed-form flow and the impact map.

    Rejects points where ``Id - A`` is numerically singular (a free periodic
    motion of the two-state system), whose solve is not trustworthy.
    """
    e, v = orb.after_impact()
    z0 = np.c_[orb.eta0, orb.v0]
    nz = np.linalg.norm(z0, axis=1)
    err = np.linalg.norm(np.c_[e, v] - z0, axis=1)
    return np.divide(err, nz, out=np.full(nz.shape, np.inf), where=nz > 0)


@dataclass(frozen=True)
class Domain:
    """Search domain ``T1 in (T1_lo, T1_hi]``, ``T2 in (T2_lo, T2_hi]``."""

    T1: tuple[float, float]
    T2: tuple[float, float]

    def __post_init__(self):
        from ._check import interval

        for nm in ("T1", "T2"):
            object.__setattr__(self, nm, interval(f"search domain {nm}", getattr(self, nm)))


def default_domain(prob: Problem) -> Domain:
    """The paper's domain ``T^alpha in (0, T0^alpha / 2]`` (Sec. 4.1)."""
    T0I, T0II = prob.system.T0
    return Domain((0.0, T0I / 2), (0.0, T0II / 2))


@dataclass(frozen=True)
class Branch:
    """One ordered curve of admissible periodic responses.

    Attributes
    ----------
    id : int
    orbits : Orbits
        The responses, ordered along the curve.
    damping : Damping
        ``Delta_PL`` and ``xi_eq`` at each point.
    adm : admissible.Admissibility
    e1, e2 : ndarray
        Switch residuals, relative to their scale.
    stab : stability.Stability
        Floquet multipliers, ``max_abs`` and the ``stable`` flag per point.
    ends : (str, str)
        What ended the branch at its first and last point (``"domain edge"``,
        ``"closed loop"``, ``"premature switch (reaction)"``, ``"premature
        switch (gap)"``, ``"impact velocity <= 0"``, ``"not periodic"``, ...).
    events : tuple of dict
        Events detected along the branch (folds in ``T``, grazing, stability
        changes classified by the critical multiplier), each with ``kind``,
        ``index`` (between points ``index`` and ``index + 1``) and ``T1, T2, T``.
    """

    id: int
    orbits: Orbits
    damping: Damping
    adm: admissible.Admissibility
    e1: np.ndarray
    e2: np.ndarray
    stab: "stability.Stability"
    ends: tuple[str, str] = ("", "")
    events: tuple = ()

    @property
    def stable(self):
        return self.stab.stable

    @property
    def max_abs_multiplier(self):
        return self.stab.max_abs

    @property
    def T1(self):
        return self.orbits.T1

    @property
    def T2(self):
        return self.orbits.T2

    @property
    def phi(self):
        return self.orbits.phi

    @property
    def T(self):
        return self.orbits.T

    @property
    def dPL(self):
        return self.damping.dPL

    @property
    def xi(self):
        return self.damping.xi

    @property
    def grazing(self):
        return self.adm.grazing

    def __len__(self):
        return len(self.orbits)


@dataclass(frozen=True)
class Paths:
    """All branches found in a domain, with scan statistics."""

    prob: Problem
    domain: Domain
    grid: tuple[int, int]
    branches: tuple[Branch, ...]
    stats: dict = field(default_factory=dict)

    def points(self) -> Orbits | None:
        """All path points of all branches as one :class:`Orbits` (None if empty)."""
        if not self.branches:
            return None
        b = self.branches
        cat = np.concatenate
        o = [x.orbits for x in b]
        return Orbits(self.prob, cat([x.T1 for x in o]), cat([x.T2 for x in o]), cat([x.phi for x in o]),
                      cat([x.eta0 for x in o]), cat([x.v0 for x in o]), cat([x.eta_s for x in o]),
                      cat([x.v_s for x in o]))


CHUNK_BYTES = 32e6  #: temporaries per batch of :func:`_chunked` (bytes)


def _chunked(prob: Problem, T1, T2, what: str = "coefficients"):
    """:func:`coefficients` (or, with ``what="G"``, only ``G``) in batches of about ``CHUNK_BYTES``."""
    from .periodic import G, _consts, single_thread_blas

    step = max(1, int(CHUNK_BYTES // _consts(prob).bytes_per_point))
    fun = G if what == "G" else coefficients
    with single_thread_blas:
        parts = map_chunks(lambda a, b: fun(prob, T1[a:b], T2[a:b]), T1.size, PAR_CHUNK, step)
    if len(parts) == 1:
        return parts[0]
    if what == "G":
        return np.concatenate(parts)
    return Coefficients(*[np.concatenate([getattr(p, f) for p in parts])
                          for f in Coefficients.__dataclass_fields__])


def scan_field(prob: Problem, domain: Domain, grid: tuple[int, int]):
    """Grid axes and ``G = D sign(det(Id - A)) / |a, b|^2`` on the grid, shape ``(n1, n2)``."""
    n1, n2 = grid
    t1 = np.linspace(domain.T1[0], domain.T1[1], n1 + 1)[1:] if domain.T1[0] == 0 else \
        np.linspace(domain.T1[0], domain.T1[1], n1)
    t2 = np.linspace(domain.T2[0], domain.T2[1], n2 + 1)[1:] if domain.T2[0] == 0 else \
        np.linspace(domain.T2[0], domain.T2[1], n2)
    G1, G2 = np.meshgrid(t1, t2, indexing="ij")
    F = _chunked(prob, G1.ravel(), G2.ravel(), "G").reshape(n1, n2)
    return t1, t2, F


def _illinois(prob, Pa, Pb, Fa, Fb, maxit=100):
    """Batched Anderson-Björck root refinement of ``F`` on segments ``Pa -> Pb`` (each (E, 2))."""
    _illinois.trace = []
    sa, sb = np.zeros(len(Fa)), np.ones(len(Fa))
    last = np.full(len(Fa), np.nan)
    Fa, Fb = Fa.copy(), Fb.copy()
    side = np.zeros(len(Fa), int)
    active = np.ones(len(Fa), bool)
    for it in range(maxit):
        idx = np.flatnonzero(active)
        _illinois.trace.append(idx.size)
        if idx.size == 0:
            break
        fa, fb = Fa[idx], Fb[idx]
        s = (sa[idx] * fb - sb[idx] * fa) / (fb - fa)
        s = np.where((s > sa[idx]) & (s < sb[idx]), s, 0.5 * (sa[idx] + sb[idx]))
        P = Pa[idx] + s[:, None] * (Pb[idx] - Pa[idx])
        F = _chunked(prob, P[:, 0], P[:, 1], "G")
        left = np.sign(F) == np.sign(fa)
        # keep the bracket; scale the stale end's value (Anderson-Bjorck, Illinois fallback)
        prev = np.where(left, fa, fb)
        with np.errstate(divide="ignore", invalid="ignore"):
            m = 1.0 - F / prev
        m = np.where((m > 0) & np.isfinite(m), m, 0.5)
        sa[idx] = np.where(left, s, sa[idx])
        Fa[idx] = np.where(left, F, np.where(side[idx] == -1, m * fa, fa))
        sb[idx] = np.where(left, sb[idx], s)
        Fb[idx] = np.where(left, np.where(side[idx] == 1, m * fb, fb), F)
        side[idx] = np.where(left, 1, -1)
        span = np.abs(Pb[idx] - Pa[idx]).max(axis=1)
        scale = np.abs(Pa[idx] + s[:, None] * (Pb[idx] - Pa[idx])).max(axis=1)
        tiny = 4 * np.finfo(float).eps * scale
        done = (F == 0) | ((sb[idx] - sa[idx]) * span <= tiny) | (np.abs(s - last[idx]) * span <= tiny)
        last[idx] = s
        sa[idx[F == 0]] = s[F == 0]
        sb[idx[F == 0]] = s[F == 0]
        active[idx[done]] = False
    s = np.where(np.abs(Fa) <= np.abs(Fb), sa, sb)
    s = np.where(np.isnan(last), s, last)
    _illinois.iterations = it
    return Pa + s[:, None] * (Pb - Pa)


def _link(F: np.ndarray, hmask: np.ndarray, vmask: np.ndarray):
    """Chains of crossing edges by marching-squares topology.

    Edges are numbered: horizontal (i, j)-(i+1, j) as ``i*n2 + j``; vertical
    (i, j)-(i, j+1) as ``H + i*(n2-1) + j``.  Returns a list of edge-id lists.
    """
    n1, n2 = F.shape
    H = (n1 - 1) * n2
    pos = F >= 0
    bottom = hmask[:, :-1]
    top = hmask[:, 1:]
    left = vmask[:-1, :]
    right = vmask[1:, :]
    cnt = bottom.astype(int) + top + left + right
    I, J = np.meshgrid(np.arange(n1 - 1), np.arange(n2 - 1), indexing="ij")
    eb = I * n2 + J
    et = I * n2 + J + 1
    el = H + I * (n2 - 1) + J
    er = H + (I + 1) * (n2 - 1) + J
    pairs = []
    for i, j in zip(*np.nonzero(cnt == 2)):
        es = [e[i, j] for e, m in ((eb, bottom), (et, top), (el, left), (er, right)) if m[i, j]]
        pairs.append((es[0], es[1]))
    for i, j in zip(*np.nonzero(cnt == 4)):
        centre = (F[i, j] + F[i + 1, j] + F[i, j + 1] + F[i + 1, j + 1]) >= 0
        if centre == pos[i, j]:
            pairs += [(eb[i, j], er[i, j]), (el[i, j], et[i, j])]
        else:
            pairs += [(eb[i, j], el[i, j]), (er[i, j], et[i, j])]
    adj: dict[int, list[int]] = {}
    for a, b in pairs:
        adj.setdefault(int(a), []).append(int(b))
        adj.setdefault(int(b), []).append(int(a))
    nodes = set(int(e) for e in np.flatnonzero(hmask.ravel())) | \
        set(int(H + e) for e in np.flatnonzero(vmask.ravel()))
    seen: set[int] = set()
    chains = []
    for start in sorted(nodes, key=lambda e: (len(adj.get(e, [])), e)):
        if start in seen:
            continue
        chain = [start]
        seen.add(start)
        cur = start
        while True:
            nxt = [e for e in adj.get(cur, []) if e not in seen]
            if not nxt:
                break
            cur = nxt[0]
            seen.add(cur)
            chain.append(cur)
        chains.append(chain)
    return chains


def _choose_phase(prob, P, co, samples=None, amplitudes: list | None = None):
    """Admissible responses at refined zeros: try ``phi`` and ``phi + pi``.

    ``amplitudes``, if a list, receives ``(max |R|, max |x_c|, R(T^I-), x_c(T^-))`` of each orbit
    on the coarse sampling (the same for both phases).
    """
    phi0 = phase(co)
    orb = orbits(prob, P[:, 0], P[:, 1], phi0, co=co)
    cm = admissible.coarse(orb)
    if amplitudes is not None:
        amplitudes += [np.abs(cm[0]).max(axis=1), np.abs(cm[1]).max(axis=1), -cm[0][:, -1], -cm[1][:, -1]]
    a0, a1 = admissible.check_both(orb, samples=samples, coarse_margins=cm)
    flip = a1.ok & ~a0.ok
    if flip.any():
        orb = Orbits(prob, orb.T1, orb.T2, np.where(flip, phi0 + np.pi, phi0), np.where(flip[:, None], -orb.eta0,
                     orb.eta0), np.where(flip[:, None], -orb.v0, orb.v0), np.where(flip[:, None], -orb.eta_s,
                     orb.eta_s), np.where(flip[:, None], -orb.v_s, orb.v_s))
    adm = admissible.Admissibility(*[np.where(flip, getattr(a1, f), getattr(a0, f))
                                     for f in admissible.Admissibility.__dataclass_fields__])
    return orb, adm, a0.ok | a1.ok


def _take_adm(a: admissible.Admissibility, idx) -> admissible.Admissibility:
    return admissible.Admissibility(*[getattr(a, f)[idx] for f in admissible.Admissibility.__dataclass_fields__])


def _take_damp(d: Damping, idx) -> Damping:
    return Damping(*[getattr(d, f)[idx] for f in Damping.__dataclass_fields__])


def _scan(prob, domain, n1, n2):
    """Grid scan and refinement of every sign-change edge: (t1, t2, F, hmask, vmask, ids, P)."""
    t1, t2, F = scan_field(prob, domain, (n1, n2))
    neg = F < 0
    hmask = neg[:-1, :] != neg[1:, :]
    vmask = neg[:, :-1] != neg[:, 1:]
    hi, hj = np.nonzero(hmask)
    vi, vj = np.nonzero(vmask)
    Pa = np.concatenate([np.c_[t1[hi], t2[hj]], np.c_[t1[vi], t2[vj]]])
    Pb = np.concatenate([np.c_[t1[hi + 1], t2[hj]], np.c_[t1[vi], t2[vj + 1]]])
    Fa = np.concatenate([F[hi, hj], F[vi, vj]])
    Fb = np.concatenate([F[hi + 1, hj], F[vi, vj + 1]])
    ids = np.concatenate([hi * n2 + hj, (n1 - 1) * n2 + vi * (n2 - 1) + vj]).astype(int)
    P = _illinois(prob, Pa, Pb, Fa, Fb) if ids.size else np.zeros((0, 2))
    return t1, t2, F, hmask, vmask, ids, P


def _evaluate(prob, P):
    """Everything about the points ``P`` (N, 2) on zero curves: orbits, admissibility, validity.

    In chunks over threads (:func:`plbar._threads.map_chunks`); the sampling of the admissibility
    check is fixed for the whole batch, so the result does not depend on the chunks.
    """
    ns = admissible.n_samples(prob, P.sum(axis=1)) if len(P) else 65
    m = prob.system.w1.size + prob.system.w2.size
    cap = max(16, int(SAMPLE_ELEMENTS // (ns * m)))        # memory: the dense sampling is (points, ns, modes)
    parts = map_chunks(lambda a, b: _evaluate_chunk(prob, P[a:b], ns), len(P), min(PAR_CHUNK // 4, cap), cap)
    if len(parts) == 1:
        return parts[0]
    orb = Orbits(prob, *[np.concatenate([getattr(p[0], f) for p in parts]) for f in
                         ("T1", "T2", "phi", "eta0", "v0", "eta_s", "v_s")])
    adm = admissible.Admissibility(*[np.concatenate([getattr(p[1], f) for p in parts])
                                     for f in admissible.Admissibility.__dataclass_fields__])
    return (orb, adm) + tuple(np.concatenate([p[k] for p in parts]) for k in range(2, 6))


def _evaluate_chunk(prob, P, samples):
    co = _chunked(prob, P[:, 0], P[:, 1])
    phi0 = phase(co)
    c, sn = np.cos(phi0), np.sin(phi0)
    r1 = np.abs(co.a1 * c + co.b1 * sn) / co.e1_scale
    r2 = np.abs(co.a2 * c + co.b2 * sn) / co.e2_scale
    zero = (r1 < ZERO_TOL) & (r2 < ZERO_TOL)
    amp: list = []
    orb, adm, ok = _choose_phase(prob, P, co, samples, amp)
    # the residuals again, from the flow and relative to the orbit's own signal amplitudes: near a pole
    # the cos/sin parts of e1, e2 are huge and cancel, so the coefficient scales above can hide a miss
    # (from the coarse sampling of the admissibility check, whose last samples are at T^I and T^-)
    s1, s2, f1, f2 = amp
    r1 = np.maximum(r1, np.abs(f1) / np.where(s1 > 0, s1, 1.0))
    r2 = np.maximum(r2, np.abs(f2) / np.where(s2 > 0, s2, 1.0))
    zero = (r1 < ZERO_TOL) & (r2 < ZERO_TOL)
    per = periodicity_error(orb)
    periodic = per < PERIODIC_TOL
    why = np.where(~zero, "not a zero of D", np.where(~periodic, "not periodic (Id - A singular)",
                   np.where(ok, "", np.char.add("premature switch (", np.char.add(adm.reason.astype(str), ")")))))
    why = np.where(why == "premature switch (impact)", "impact velocity <= 0", why)
    return orb, adm, zero & periodic & ok, r1, r2, why


def _events(b_T1, b_T2, T, adm, stab) -> list:
    """Folds in T, grazing and stability changes along an ordered branch."""
    ev = []
    dT = np.diff(T)
    for k in np.flatnonzero(dT[:-1] * dT[1:] < 0):
        ev.append(dict(kind="fold in T", index=int(k + 1)))
    g = adm.grazing
    for k in np.flatnonzero(g[1:] & ~g[:-1]):
        ev.append(dict(kind="grazing", index=int(k + 1)))
    st = stab.max_abs < 1
    for k in np.flatnonzero(st[1:] != st[:-1]):
        j = k if not st[k] else k + 1              # the unstable side
        mu = stab.multipliers[j]
        crit = mu[np.argmin(np.abs(np.abs(mu) - 1.0))]
        if abs(crit.imag) > 1e-6 * abs(crit):
            kind = "Neimark-Sacker"
        elif crit.real < 0:
            kind = "period doubling"
        else:
            kind = "fold (mu = +1)"
        ev.append(dict(kind=kind, index=int(k)))
    for e in ev:
        i = e["index"]
        e.update(T1=float(b_T1[i]), T2=float(b_T2[i]), T=float(T[i]))
    return sorted(ev, key=lambda e: e["index"])


def _curves_grid(F, hmask, vmask, ids, P):
    """Marching-squares chains as curves: list of (point indices into P, ends)."""
    where = {int(e): k for k, e in enumerate(ids)}
    out = []
    for chain in _link(F, hmask, vmask):
        out.append(([where[e] for e in chain if e in where], ("grid chain end", "grid chain end")))
    return out


PAR_CHUNK = 2000   #: smallest batch of points worth a thread of its own
SAMPLE_ELEMENTS = 2e7   #: largest (points x samples x modes) array of one admissibility chunk (160 MB)
SPECULATE = 64   #: traces run in lockstep (at most one speculative seed per marching-squares chain)


def _curves_continuation(prob, t1, t2, F, hmask, vmask, ids, P, zero0, good0, progress):
    """Continuation traces seeded by the admissible scan crossings.

    Walkers stop at crossings the scan found inadmissible (or not periodic),
    so only the admissible stretches of the zero curves are traced.
    Returns a list of (points (M, 2), ends).
    """
    from .continuation import trace_many

    crossings = {int(e): P[k] for k, e in enumerate(ids) if zero0[k]}
    stop = {int(e) for k, e in enumerate(ids) if zero0[k] and not good0[k]}
    seeds = {int(e) for k, e in enumerate(ids) if good0[k]}
    # chains are walks along the zero curves; a run of admissible crossings between two others is a
    # "stretch", which one trace usually covers
    seq, stretch = [], {}
    for ci, chain in enumerate(sorted(_link(F, hmask, vmask), key=len, reverse=True)):
        k, prev = 0, False
        for e in chain:
            good = e in seeds
            if good:
                k += not prev
                seq.append(e)
                stretch[e] = (ci, k)
            prev = good
    # The traces are those of the sequential rule "seed a trace at every admissible crossing, in chain
    # order, that no earlier trace passed through".  To batch the walkers, traces are computed in
    # lockstep from the first unvisited seed of each of the next stretches; a walker whose seed an
    # earlier walker crosses is dropped, and a trace is used only when the sequential rule reaches its
    # seed unvisited (else it is discarded).
    visited: set[int] = set()
    cache: dict[int, object] = {}
    curves = []
    bar = _progress(len(seeds), progress, "tracing")
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
            trs = trace_many(prob, t1, t2, [crossings[b] for b in batch], crossings=crossings, seed_edges=batch,
                             stop=stop, drop_crossed=True)
            cache.update(zip(batch, trs))
        tr = cache.pop(e)
        bar.update(len((set(tr.edges) - visited) & seeds))
        visited |= set(tr.edges)
        curves.append((tr.P, tr.ends))
    bar.close()
    return curves


def _progress(total, enabled, desc):
    if enabled:
        from tqdm.auto import tqdm

        return tqdm(total=total, desc=desc, unit="edge", leave=False, delay=1.0)

    class _Null:
        def update(self, *_):
            pass

        def close(self):
            pass

    return _Null()


def find_paths(prob: Problem, domain: Domain | None = None, grid: tuple[int, int] = (200, 200),
               method: str = "continuation", progress: bool = False) -> Paths:
    """All admissible periodic paths of ``prob`` in ``domain``.

    Parameters
    ----------
    prob : Problem
    domain : Domain, optional
        Default: the paper's ``(0, T0^alpha / 2]`` (:func:`default_domain`).
    grid : (int, int)
        Grid points along ``T^I`` and ``T^II`` for the scan of ``D``.
    method : {"continuation", "grid"}
        ``"continuation"``: the scan's crossings seed pseudo-arclength
        continuation (:mod:`plbar.continuation`), so every branch is an
        ordered curve resolved at least as finely as the grid, through the
        scan's own points; ``"grid"``: the scan's crossings linked by the
        marching-squares topology (faster; fragments where two curves come
        closer than a grid cell).
    progress : bool
        Show a progress bar while tracing.

    Returns
    -------
    Paths
        Branches ordered by their smallest period ``T``; each branch ordered
        along its curve.
    """
    if method not in ("continuation", "grid"):
        raise InputError(f"method = {method!r} is not allowed; choose continuation or grid")
    t0 = time.perf_counter()
    domain = domain or default_domain(prob)
    n1, n2 = (int(g) for g in grid)
    if n1 < 3 or n2 < 3:
        raise InputError(f"grid = ({n1}, {n2}) is too coarse; use at least 3 points per axis (default 200 x 200)")
    t1, t2, F, hmask, vmask, ids, P = _scan(prob, domain, n1, n2)
    stats = {"grid": [n1, n2], "method": method, "crossings": int(ids.size), "t_scan": time.perf_counter() - t0}
    if ids.size and hasattr(_illinois, "iterations"):
        stats["refine_iterations"] = _illinois.iterations
    branches: list[Branch] = []
    if ids.size:
        orb0, adm0, good0, r10, r20, why0 = _evaluate(prob, P)
        stats["zeros"] = int((r10 < ZERO_TOL).sum())
        stats["admissible_crossings"] = int(good0.sum())
        t1c = time.perf_counter()
        if method == "grid":
            raw = _curves_grid(F, hmask, vmask, ids, P)
            curves = [(np.asarray(ix, int), ends) for ix, ends in raw]
            allP, orb, adm, good, r1, r2, why = P, orb0, adm0, good0, r10, r20, why0
        else:
            zero0 = (r10 < ZERO_TOL) & (r20 < ZERO_TOL)
            traced = _curves_continuation(prob, t1, t2, F, hmask, vmask, ids, P, zero0, good0, progress)
            sizes = [len(c[0]) for c in traced]
            allP = np.concatenate([c[0] for c in traced]) if traced else np.zeros((0, 2))
            offs = np.r_[0, np.cumsum(sizes)]
            curves = [(np.arange(offs[i], offs[i + 1]), traced[i][1]) for i in range(len(traced))]
            orb, adm, good, r1, r2, why = _evaluate(prob, allP) if len(allP) else (None,) * 6
            stats["traced_points"] = int(len(allP))
        stats["t_curves"] = time.perf_counter() - t1c
        runs = []
        for ix, ends in curves:
            run: list[int] = []
            start_reason = ends[0]
            for pos, k in enumerate(list(ix) + [-1]):
                if k >= 0 and good[k]:
                    if not run:
                        start_reason = ends[0] if pos == 0 else why[ix[pos - 1]]
                    run.append(k)
                elif run:
                    end_reason = ends[1] if k < 0 else why[k]
                    runs.append((run, (str(start_reason), str(end_reason))))
                    run = []
        sel = np.concatenate([r for r, _ in runs]) if runs else np.zeros(0, int)
        if sel.size:
            sorb = orb.take(sel)
            dmp = damping(sorb)
            stb = stability.stability(sorb)
            lookup = {int(k): j for j, k in enumerate(sel)}
            order = sorted(range(len(runs)), key=lambda r: min(orb.T[runs[r][0]]))
            for bid, r in enumerate(order):
                run, ends = runs[r]
                if orb.T[run[0]] > orb.T[run[-1]]:
                    run, ends = run[::-1], ends[::-1]
                jj = [lookup[k] for k in run]
                st = stability.Stability(*[getattr(stb, f)[jj] if np.ndim(getattr(stb, f)) else getattr(stb, f)
                                           for f in stability.Stability.__dataclass_fields__])
                bo, ba = orb.take(run), _take_adm(adm, run)
                branches.append(Branch(bid, bo, _take_damp(dmp, jj), ba, r1[run], r2[run], st, ends,
                                       tuple(_events(bo.T1, bo.T2, bo.T, ba, st))))
        stats["admissible"] = int(sel.size)
    stats["t_total"] = time.perf_counter() - t0
    return Paths(prob, domain, (n1, n2), tuple(branches), stats)
