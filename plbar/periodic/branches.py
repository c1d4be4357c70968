"""Branches of periodic responses of every signature, found without the user (FORMULATION §8).

:func:`find_branches` seeds, follows and checks (the paper's class ``1P`` comes from the paper's scan of ``G`` and its
continuation in ``(T^I, T^II)``, :func:`plbar.find_paths`, made branches of this record by :func:`from_paths`):

1. the zero-dwell class ``1Z`` on a grid of the period window (closed form, :func:`.seeds.zero_dwell`); with a
   coefficient of restitution ``e > 0`` the class ``1R`` (one rebound per period) instead, the same closed form;
2. every period doubling met on a branch (a real multiplier through ``-1``) seeds the doubled
   signature (``m = 2``, then ``m = 4``), on the branches of the paper's class (their events,
   :func:`plbar.find_paths`) and on the branches found here;
4. a stuck phase shrinking to zero continues in the signature with that pair of zero dwell;
   where a branch stops being admissible (a premature switch), the switches the bar makes
   instead seed the neighbouring signature (:func:`.seeds.split`), on the paper's branches too;
5. any extra seeds (a simulation's periodic motions: :func:`.seeds.from_motion`); and first of all the curve
   through each of the paper's branches, whose points off them (outside the paper's search domain, past the scan's
   ends) are branches of the paper's class found here.

Every curve is followed both ways in ``T`` (:func:`.follow.follow`: to the window's edge, to a zero duration, or
round a loop once), each point is replayed by the certified simulator (:func:`.verify.admissible`) and gets its
Floquet multipliers (:mod:`.floquet`); a branch is a maximal run of admissible points.  A seed on a curve already
followed (from another seed, or as another rotation of one orbit) is not followed again
(:class:`.followed.Followed`: on a chord, or the same orbit by Newton), so every curve is listed once.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..model import Problem
from ..paths import FOLD_MU, FOLD_T, GRAZING, NEIMARK_SACKER, PERIOD_DOUBLING
from .branch import DWELL_ZERO, PREMATURE, Branch
from .floquet import monodromy, multipliers
from .followed import Followed
from .follow import END_DWELL, FollowSettings, follow
from .seeds import doubled, split, zero_dwell
from .signature import ONE_REBOUND, PAPER, ZERO_DWELL, Signature
from .solve import Orbit, NotConverged, orbit_at, polish
from .verify import admissible

__all__ = ["Branch", "find_branches", "from_paths", "KINDS", "PD", "NS", "FOLD", "GRAZING", "DWELL_ZERO"]

KINDS = ("paper", "default", "all")
PD, NS, FOLD = PERIOD_DOUBLING, NEIMARK_SACKER, FOLD_T
M_MAX = 4                 #: longest orbit (in forcing periods) seeded by period doublings
STABLE_TOL = 1e-9


def _curve(prob, orb: Orbit, window, st) -> tuple[list[Orbit], list[str]]:
    """The whole curve through ``orb`` (both directions), in increasing arclength, and its two ends."""
    up, e_up = follow(prob, orb.sig, orb, window, +1.0, st)
    dn, e_dn = follow(prob, orb.sig, orb, window, -1.0, st, before=up[:0:-1])   # ends where it meets ``up``
    return dn[::-1] + up[1:], [e_dn, e_up]


def _mults(prob, orbs) -> list[np.ndarray]:
    """The Floquet multipliers of each orbit (the eigenvalues of orbits of one signature in one call).

    An orbit whose monodromy is not finite gets nan multipliers (its stability unknown: not stable, and no
    bifurcation is read off it).  This happens on a vertical family, where the forcing period is a multiple of a
    natural period of the free state (the chain N = 3 at T = 2 T_II,3: the free flight's map has the multiplier 1
    and the family's monodromies grow to 1e14, overflowing at some points)."""
    if not orbs:
        return []
    Ms = [monodromy(prob, o.sig, o.T, o.phi, o.chain) for o in orbs]
    finite = [bool(np.isfinite(M).all()) for M in Ms]
    if all(finite) and len({M.shape for M in Ms}) == 1:
        return list(multipliers(np.stack(Ms)))
    return [multipliers(M) if ok else np.full(M.shape[0], np.nan + 0j) for M, ok in zip(Ms, finite)]


def _flags(mus) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per orbit: a real multiplier below -1; a complex pair; the largest modulus of the complex ones."""
    if len({mu.shape for mu in mus}) == 1:
        M = np.stack(mus)
        real = np.abs(M.imag) < 1e-9
        cmod = np.where(real, -np.inf, np.abs(M))
        return np.any(real & (M.real < -1), axis=1), np.any(~real, axis=1), cmod.max(axis=1)
    out = [_flags([mu]) for mu in mus]
    return tuple(np.concatenate([o[j] for o in out]) for j in range(3))


def _events(orbs, mus) -> list[dict]:
    """Folds in ``T`` and the changes of stability along a curve of orbits: a real multiplier through -1
    (period doubling), a complex pair through the unit circle (Neimark-Sacker), and any other change of the
    verdict ``max |mu| < 1 - STABLE_TOL`` classified by the critical multiplier of its unstable side (through +1:
    a fold of the multipliers).  ``index`` is the first point past a change, the point at a fold."""
    ev = []
    if len(orbs) < 2:
        return ev
    pd, cplx, cmax = _flags(mus)
    T = np.array([o.T for o in orbs])
    known = np.array([bool(np.isfinite(mu).all()) for mu in mus])      # a flip needs both points' multipliers
    both = known[1:] & known[:-1]
    flip_pd = (pd[1:] != pd[:-1]) & both
    flip_ns = cplx[1:] & cplx[:-1] & ((cmax[1:] > 1) != (cmax[:-1] > 1)) & both
    st = np.array([bool(np.abs(mu).max() < 1 - STABLE_TOL) if mu.size else True for mu in mus])
    flip_st = (st[1:] != st[:-1]) & both & ~flip_pd & ~flip_ns
    fold = np.r_[False, (T[2:] - T[1:-1]) * (T[1:-1] - T[:-2]) < 0]
    for i in (np.flatnonzero(flip_pd | flip_ns | flip_st | fold) + 1).tolist():
        if flip_pd[i - 1]:
            ev.append({"kind": PD, "index": i, "T": orbs[i].T})
        if flip_ns[i - 1]:
            ev.append({"kind": NS, "index": i, "T": orbs[i].T})
        if flip_st[i - 1]:
            ev.append({"kind": _critical(mus[i] if not st[i] else mus[i - 1]), "index": i, "T": orbs[i].T})
        if fold[i - 1]:
            ev.append({"kind": FOLD, "index": i - 1, "T": orbs[i - 1].T})
    return ev


def _critical(mu) -> str:
    """The kind of a change of stability by its multiplier nearest the unit circle."""
    crit = mu[np.argmin(np.abs(np.abs(mu) - 1.0))]
    if abs(crit.imag) > 1e-6 * abs(crit):
        return NS
    return PD if crit.real < 0 else FOLD_MU


def _zero_dwell_seeds(prob, window, num: int) -> list[Orbit]:
    """One admissible ``1Z`` orbit (``1R`` with restitution) per admissible stretch of the grid (and root)."""
    Ts = np.linspace(window[0], window[1], num)
    sig = ONE_REBOUND if getattr(prob, "restitution", 0.0) else ZERO_DWELL
    per_T = [zero_dwell(prob, T, sig) for T in Ts]
    ok = admissible([o for orbs in per_T for o in orbs])
    seeds, prev, k = [], [], 0
    for orbs in per_T:
        here = [o for o, a in zip(orbs, ok[k:k + len(orbs)]) if a]
        k += len(orbs)
        # a new seed where no admissible root at the previous grid period is near it in phase: with a gap both
        # roots can be admissible (the two sides of a fold), each continuing its own root
        seeds.extend(o for o in here if not any(abs(p.phi - o.phi) <= 0.5 for p in prev))
        prev = here
    return seeds


def _dwell_transition(prob, orb: Orbit) -> list[Orbit]:
    """At a stuck phase shrinking to zero: the same orbit in the signature with that pair of zero dwell."""
    out = []
    d = orb.durations
    for i, positive in enumerate(orb.sig.dwell):
        if positive and d[2 * i] < 1e-3 * orb.T:
            dw = list(orb.sig.dwell)
            dw[i] = False
            sig = Signature(orb.sig.m, tuple(dw), orb.sig.rebound)
            X = [orb.z0]
            vals = []
            for j in range(orb.sig.k):
                if dw[j]:
                    vals.append(d[2 * j])
                vals.append(d[2 * j + 1] + (d[2 * j] if j == i else 0.0))
            try:
                out.append(polish(prob, sig, orb.T, np.concatenate(X + [vals, [orb.phi]])))
            except NotConverged:
                pass
    return out


def _paper_doublings(prob, paper_branches) -> list[Orbit]:
    """Seeds of ``m = 2`` at the period doublings of the paper's branches (the point beyond the crossing)."""
    out = []
    for b in paper_branches:
        for e in b.events:
            if e["kind"] != PD:
                continue
            for i in {max(e["index"] - 1, 0), min(e["index"], len(b) - 1)}:
                orb = b.orbits[i]
                mu = _mults(prob, [orb])[0]
                if np.any(np.abs(mu.imag) < 1e-9 * np.abs(mu) + 1e-12) and np.any(mu.real < -1):
                    out.extend(doubled(prob, orb))
    return out


def _paper_ends(prob, paper_branches, window, st) -> list[Orbit]:
    """Seeds beyond the ends of the paper's branches: a few continuation steps out, then :func:`.seeds.split`."""
    out = []
    short = FollowSettings(h0=st.h0, h_min=st.h_min, h_max=st.h_max, max_points=4, newton=st.newton)
    for b in paper_branches:
        for i in {0, len(b) - 1}:
            orb = b.orbits[i]
            for direction in (1.0, -1.0):
                orbs, _ = follow(prob, PAPER, orb, window, direction, short)
                ok = admissible(orbs[1:])
                bad = [x for x, a in zip(orbs[1:], ok) if not a]
                if bad:
                    out.extend(split(prob, bad[0]))
    return out


def from_paths(prob: Problem, paper_branches) -> list[Branch]:
    """The branches of the paper's class of :func:`plbar.find_paths` (its record: closed-form orbits in
    ``(T^I, T^II, phi)``) as branches of this record: every point the chain's exact orbit of signature ``1P``
    (:func:`.solve.orbit_at`: residuals recomputed from the flow, the loss ``S v_c^2 / 2``, ``xi_eq`` over the
    chain's segments) with its Floquet multipliers and their events (:func:`_mults`, :func:`_events`: as for
    every other signature), and the ends and grazing points the paper's dense admissibility check found."""
    out = []
    for b in paper_branches:
        o = b.orbits
        X = np.concatenate([o.eta0, o.v0, np.c_[o.T1, o.T2, o.phi]], axis=1)
        orbs = tuple(orbit_at(prob, PAPER, float(o.T[i]), X[i]) for i in range(len(b)))
        mus = _mults(prob, list(orbs))
        mx = np.array([np.abs(mu).max() if mu.size else 0.0 for mu in mus])
        ev = _events(orbs, mus) + [{"kind": GRAZING, "index": int(e["index"]), "T": float(e["T"])}
                                   for e in b.events if e["kind"] == GRAZING]
        out.append(Branch(b.id, PAPER, orbs, mx < 1 - STABLE_TOL, mx, sorted(ev, key=lambda e: e["index"]),
                          tuple(b.ends), np.asarray(b.grazing, bool)))
    return out


def find_branches(prob: Problem, window: tuple[float, float], paper_branches=(), extra_seeds=(),
                  kinds: str = "default", grid: int = 400, settings: FollowSettings | None = None,
                  m_max: int = M_MAX, progress=None) -> list[Branch]:
    """Every branch: the paper's class, then every other signature reachable from the seeds (see the module
    docstring).

    ``paper_branches`` are the paper's class (:func:`from_paths` of :func:`plbar.find_paths`: their period
    doublings and ends seed other signatures), ``extra_seeds`` any other orbits.  ``kinds = "paper"`` returns the
    paper's branches alone.  ``progress`` (optional) is called once per curve followed.  The paper's class comes
    first (:func:`_numbered`), ids in that order.
    """
    if kinds == "paper":
        return _numbered(paper_branches, [])
    st = settings or FollowSettings()
    # the curves through the paper's branches are followed first, from a point of each, through their inadmissible
    # stretches as every curve is: where one comes back admissible off the paper's search domain (a stuck phase
    # longer than T0_I / 2) it is a branch of class 1P found here; the paper's own points stay with its branches
    queue = [b.orbits[len(b) // 2] for b in paper_branches] + list(_zero_dwell_seeds(prob, window, grid)) + \
        _paper_doublings(prob, paper_branches) + _paper_ends(prob, paper_branches, window, st) + list(extra_seeds)
    curves, paper = Followed(prob), Followed(prob)
    for b in paper_branches:
        paper.add(b.orbits)
    branches = []
    while queue:
        orb = queue.pop(0)
        if orb.sig.m > m_max:
            continue
        try:
            orb = orb.minimal()                       # a seed that repeats a shorter orbit: that orbit's signature
        except NotConverged:
            continue
        if curves.known(orb):
            continue
        orbs, ends = _curve(prob, orb, window, st)
        if progress is not None:
            progress()
        curves.add(orbs)
        mus = _mults(prob, orbs)
        ok = admissible(orbs)
        if orb.sig.canonical() == PAPER:              # the paper's own points stay with its branches
            ok &= np.array([not paper.known(o) for o in orbs])
        ev = _events(orbs, mus)
        for e in ev:
            if e["kind"] == PD and orb.sig.m * 2 <= m_max:
                i = e["index"]
                beyond = i if np.any(mus[i].real < -1) else i - 1
                queue.extend(doubled(prob, orbs[beyond]))
        for end, o in zip(ends, (orbs[0], orbs[-1])):
            if end == END_DWELL:
                queue.extend(_dwell_transition(prob, o))
        for j in np.flatnonzero(ok[1:] != ok[:-1]):          # the first inadmissible point past each run
            k = j + 1 if ok[j] else j
            queue.extend(split(prob, orbs[k]))
        branches.extend(_admissible_runs(orbs, ok, mus, ev, len(branches), ends))
    return _numbered(paper_branches, branches)


def _numbered(paper_branches, found: list) -> list[Branch]:
    """The paper's branches in their order (ids unchanged: :func:`plbar.find_paths` numbers them by lowest ``T``),
    then those of the paper's class found here (off its domain) by lowest ``T``, then the others as found; ids
    ``0, 1, ...`` in that order."""
    off = sorted((b for b in found if b.paper), key=lambda b: float(b.T.min()))
    rest = [b for b in found if not b.paper]
    return [replace(b, id=i) for i, b in enumerate(list(paper_branches) + off + rest)]


def _admissible_runs(orbs, ok, mus, ev, first_id: int, ends=("", "")) -> list[Branch]:
    """Maximal runs of admissible points as branches, with their events; a run that ends because the next point
    switches prematurely ends in a grazing event, one that ends where a stuck phase shrinks to zero in a
    :data:`DWELL_ZERO` event (the signature changes there: the next one is followed from it)."""
    out = []
    i = 0
    n = len(orbs)
    while i < n:
        if not ok[i]:
            i += 1
            continue
        j = i
        while j < n and ok[j]:
            j += 1
        mx = np.array([np.abs(m).max() for m in mus[i:j]])
        evs = [dict(e, index=e["index"] - i) for e in ev if i <= e["index"] < j]
        for k, beyond, end in ((i, i - 1, ends[0]), (j - 1, j, ends[1])):
            if 0 <= beyond < n:
                evs.append({"kind": GRAZING, "index": k - i, "T": orbs[k].T})
            elif end == END_DWELL:
                evs.append({"kind": DWELL_ZERO, "index": k - i, "T": orbs[k].T})
        why = tuple(PREMATURE if 0 <= beyond < n else end for beyond, end in ((i - 1, ends[0]), (j, ends[1])))
        out.append(Branch(first_id + len(out), orbs[i].sig, tuple(orbs[i:j]), mx < 1 - STABLE_TOL, mx, evs, why))
        i = j
    return out
