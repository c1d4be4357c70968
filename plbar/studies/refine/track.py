"""A family of periodic responses followed from one mesh to the next (mesh refinement, full model).

A *level* is the family on one mesh: the pieces of the zero curves of ``G``
that carry it, inside its period window (:mod:`.anchors`), with every point
evaluated (admissible phase, ``Delta_PL``, ``xi_eq``, impact velocity).  The
first level is *seeded* by the scan (:func:`plbar.find_paths` over the
window, the branch picked by a rule); every next level is *carried*:

1. the previous level's points on and next to its admissible stretches are
   mapped to the new mesh, ``T^I`` scaled by the ratio of the ``T0^I`` and
   ``T^II`` by that of the ``T0^II`` (the periods converge at the element's rate);
2. a mapped point that no curve followed so far passes near is moved onto the
   new zero set along the normal of the carried curve
   (:func:`plbar.paths.correct_onto`);
3. the curve through it is followed inside the window until it closes, reaches
   the window's edge or has left the carried points for a while
   (:func:`plbar.paths.follow`).

The cost of a level is (points followed) x (one LU of size ``2 (n - 1)``),
with the full model, instead of a grid scan of the whole window.  A level is
plain JSON-able data (it is checkpointed by :mod:`.study`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ...app import Case
from ...errors import InputError
from ...paths import Band, correct_onto, evaluate, find_paths, follow_one
from ...response import damping
from ...util.check import show
from .anchors import Anchor, window_band

__all__ = ["TrackSettings", "PICKS", "seed_levels", "carry_level", "level_points", "admissible_runs_of",
           "mark_merges"]

PICKS = ("longest", "xi", "nearest", "all")


@dataclass(frozen=True)
class TrackSettings:
    """How a family is seeded and carried.

    Attributes
    ----------
    width : float
        Relative half-width of the period window.
    grid : (int, int)
        Scan grid of the seed level.
    pick : {"longest", "xi", "nearest", "all"}
        The seed branch: the one with the most admissible points in the window,
        the largest ``xi_eq``, the one nearest the anchor period, or every
        branch in the window (each a family of its own).
    step : float
        Largest continuation step, as a fraction of the window (normalised coordinates).
    reach : float
        How far (in steps) a mapped point may move onto the new curve.
    patience : int
        Steps a walker may stay farther than ``reach`` from every carried point on
        responses that are not admissible (an admissible stretch is followed to its end).
    margin : int
        Points carried beyond each end of an admissible stretch.
    """

    width: float = 0.15
    grid: tuple[int, int] = (200, 200)
    pick: str = "longest"
    step: float = 1.0 / 200
    reach: float = 6.0
    patience: int = 10
    margin: int = 5

    def __post_init__(self):
        if self.pick not in PICKS:
            raise InputError(f"pick = {show(self.pick)} is not allowed; choose {', '.join(PICKS)}")
        if not 0 < self.step <= 0.1:
            raise InputError(f"step = {show(self.step)} must be in (0, 0.1] (a fraction of the window)")
        if not 0 < self.width < 1:
            raise InputError(f"window = {show(self.width)} must be a relative half-width in (0, 1), e.g. 0.15 "
                             "(--window W)")


def _evaluated(prob, P: np.ndarray) -> dict:
    """Admissible phase, residual verdict, ``Delta_PL``, ``xi_eq`` and ``v_c(T^-)`` at points ``P`` (K, 2)."""
    if not len(P):
        return {k: [] for k in ("T1", "T2", "phi", "good", "why", "xi", "dPL", "v_c")}
    ev = evaluate(prob, P)
    d = damping(ev.orbits)
    vc = ev.orbits.contact_velocity(ev.orbits.T2[:, None])[:, 0]
    return {"T1": _finite(P[:, 0]), "T2": _finite(P[:, 1]), "phi": _finite(np.mod(ev.orbits.phi, 2 * np.pi)),
            "good": ev.good.astype(int).tolist(), "why": [str(w) for w in ev.why], "xi": _finite(d.xi),
            "dPL": _finite(d.dPL), "v_c": _finite(vc)}


def _from_branch(b, run) -> dict:
    """The points ``run`` of a branch of :func:`plbar.find_paths` as a piece (already evaluated there)."""
    orb = b.orbits.take(run)
    vc = orb.contact_velocity(orb.T2[:, None])[:, 0]
    return {"T1": _finite(orb.T1), "T2": _finite(orb.T2), "phi": _finite(np.mod(orb.phi, 2 * np.pi)),
            "good": [1] * len(run), "why": [""] * len(run), "xi": _finite(b.xi[run]), "dPL": _finite(b.dPL[run]),
            "v_c": _finite(vc)}


def _finite(a) -> list:
    """A float array as a JSON list (a non-finite value, at a point that is no response, becomes None)."""
    return [float(v) if np.isfinite(v) else None for v in np.asarray(a, float)]


def _header(case: Case, prob, anchor: Anchor, band: Band) -> dict:
    T0I, T0II = prob.system.T0
    L = prob.bar.length
    return {"n": int(case.n_eff), "dofs": int(prob.system.n), "length": float(L), "h": 1.0 / case.n_eff,
            "T0_I": float(T0I), "T0_II": float(T0II), "anchor": str(anchor),
            "A": float(anchor.period(T0I, T0II)), "band": {"T1": list(band.T1), "T": list(band.T)},
            "impact_mass": float(prob.system.impact_mass), "end_mass": float(case.end_mass_value)}


def seed_levels(case: Case, anchor: Anchor, st: TrackSettings, progress: bool = False) -> list[dict]:
    """The first level(s): the scan of the window and the picked branch(es), restricted to the window."""
    t0 = time.perf_counter()
    prob = case.problem()
    band = window_band(anchor, *prob.system.T0, st.width)
    paths = find_paths(prob, band.domain(), st.grid, progress=progress)
    A = anchor.period(*prob.system.T0)
    cands = []
    for b in paths.branches:
        inside = band.contains(np.c_[b.T1, b.T2])
        for run in admissible_runs_of(inside):
            if len(run) >= 2:
                cands.append((b, run))
    if not cands:
        lv = {**_header(case, prob, anchor, band), "pieces": [], "status": "ended",
              "notes": [f"the scan ({st.grid[0]} x {st.grid[1]}) found no admissible branch in the window"],
              "evaluations": int(np.prod(st.grid)), "time": time.perf_counter() - t0}
        return [lv]
    key = {"longest": lambda c: -len(c[1]), "xi": lambda c: -float(c[0].xi[c[1]].max()),
           "nearest": lambda c: float(np.abs(c[0].T[c[1]] / A - 1).min())}
    picked = cands if st.pick == "all" else [min(cands, key=key[st.pick])]
    out = []
    for b, run in picked:
        piece = _from_branch(b, run)
        piece["ends"] = [b.ends[0] if run[0] == 0 else "window edge",
                         b.ends[1] if run[-1] == len(b) - 1 else "window edge"]
        out.append({**_header(case, prob, anchor, band), "pieces": [piece], "status": "seed",
                    "notes": [f"seeded by the scan ({st.grid[0]} x {st.grid[1]}): branch {b.id} of "
                              f"{len(paths.branches)}, {len(run)} admissible points in the window"],
                    "evaluations": int(np.prod(st.grid)), "time": time.perf_counter() - t0})
    return out


def admissible_runs_of(good) -> list[np.ndarray]:
    """Maximal runs of True in a boolean sequence, as index arrays."""
    g = np.r_[False, np.asarray(good, bool), False]
    d = np.flatnonzero(np.diff(g.astype(int)))
    return [np.arange(a, b) for a, b in zip(d[::2], d[1::2])]


def level_points(level: dict, margin: int) -> list[np.ndarray]:
    """The points a level carries, per piece: its admissible stretches and ``margin`` points beside them.

    A level without any admissible point carries all of its points (the zero
    curve is followed on in case the stretch comes back on a finer mesh).
    """
    pieces = level["pieces"]
    anygood = any(any(p["good"]) for p in pieces)
    out = []
    for p in pieces:
        P = np.c_[p["T1"], p["T2"]]
        if not anygood:
            out.append(P)
            continue
        for run in admissible_runs_of(p["good"]):
            a, b = max(run[0] - margin, 0), min(run[-1] + margin + 1, len(P))
            out.append(P[a:b])
    return [P for P in out if len(P)]


def _thin(U: np.ndarray, step: float) -> np.ndarray:
    """Indices of points of an ordered curve at least ``step`` apart (first and last kept)."""
    keep, last = [0], U[0]
    for i in range(1, len(U) - 1):
        if np.linalg.norm(U[i] - last) >= step:
            keep.append(i)
            last = U[i]
    if len(U) > 1:
        keep.append(len(U) - 1)
    return np.array(keep)


def _normals(U: np.ndarray) -> np.ndarray:
    """Unit normals of an ordered curve (central differences; one point: the T direction)."""
    if len(U) < 2:
        return np.array([[0.0, 1.0]])
    t = np.gradient(U, axis=0)
    t /= np.maximum(np.linalg.norm(t, axis=1), 1e-300)[:, None]
    return np.c_[-t[:, 1], t[:, 0]]


def _pieces(prob, band: Band, curves, st: TrackSettings, tick=None):
    """Follow the new zero curves near the carried ``curves`` (normalised): lazily, in curve order.

    A carried point within one step of a curve already followed is skipped (it
    lies on it); any other is moved onto the zero set along the carried curve's
    normal (within ``reach``) and, unless it lands on a curve already followed,
    the curve through it is followed.  Returns the traces, the evaluations and
    the number of carried points that found no zero within reach.  ``tick(j, k)``, if given, is told after each
    of the ``k`` carried points it tries (progress).
    """
    reach = st.reach * st.step
    carried = np.concatenate(curves)
    done, traces, nev, lost = [], [], 0, 0
    thinned = [_thin(U, st.step) for U in curves]
    total, j = sum(len(idx) for idx in thinned), 0
    for U, idx in zip(curves, thinned):
        nrm = _normals(U)
        for i in idx:
            j += 1
            if tick is not None:
                tick(j, total)
            if any(np.linalg.norm(d - U[i], axis=1).min() < st.step for d in done):
                continue
            V, k = correct_onto(prob, band, U[i:i + 1], nrm[i:i + 1], reach)
            nev += k
            v = V[0]
            if not (np.all(np.isfinite(v)) and np.all((v >= 0) & (v <= 1))):
                lost += 1
                continue
            if any(np.linalg.norm(d - v, axis=1).min() < 2 * st.step for d in done):
                continue
            W, tr = follow_one(prob, band, v, st.step, carried, reach, st.patience)
            done.append(W)
            traces.append(tr)
            nev += tr.nevals
    return traces, nev, lost


def carry_level(prev: dict, case: Case, anchor: Anchor, st: TrackSettings, tick=None) -> dict:
    """The family on the mesh of ``case``, carried from the level ``prev`` of a coarser mesh (``tick``: progress,
    :func:`_pieces`)."""
    t0 = time.perf_counter()
    prob = case.problem()
    T0I, T0II = prob.system.T0
    band = window_band(anchor, T0I, T0II, st.width)
    scale = np.array([T0I / prev["T0_I"], T0II / prev["T0_II"]])
    curves = [band.to_u(P * scale) for P in level_points(prev, st.margin)]
    head = _header(case, prob, anchor, band)
    if prev["status"] == "merged" or not curves:
        why = "the family had merged with another (see the earlier notes)" if prev["status"] == "merged" else \
            "nothing to carry: the family had ended"
        return {**head, "pieces": [], "status": "ended", "notes": [why], "evaluations": 0,
                "time": time.perf_counter() - t0}
    traces, nev, lost = _pieces(prob, band, curves, st, tick)
    pieces = []
    for tr in traces:
        piece = _evaluated(prob, np.asarray(tr.P, float))
        piece["ends"] = list(tr.ends)
        pieces.append(piece)
    ncarried = sum(len(U) for U in curves)
    return {**head, "pieces": pieces, **_status(prev, pieces, ncarried, lost), "evaluations": int(nev),
            "time": time.perf_counter() - t0}


def _status(prev: dict, pieces: list, ncarried: int, lost: int) -> dict:
    """``status`` (tracked, split, inadmissible, ended) and notes of a carried level."""
    notes = []
    if lost:
        notes.append(f"{lost} carried point(s) found no zero of G within reach")
    if not pieces:
        return {"status": "ended", "notes": notes + [f"none of the {ncarried} carried points lies near a zero "
                                                     "curve of G on this mesh: the family ends"]}
    before = sum(any(p["good"]) for p in prev["pieces"])
    now = sum(any(p["good"]) for p in pieces)
    runs = sum(len(admissible_runs_of(p["good"])) for p in pieces)
    notes.append(f"{len(pieces)} curve piece(s), {runs} admissible stretch(es)")
    if now == 0:
        return {"status": "inadmissible", "notes": notes + ["no admissible point on the carried curve (every "
                                                            "response switches prematurely or is not periodic)"]}
    return {"status": "split" if now > max(before, 1) else "tracked", "notes": notes}


def mark_merges(levels: list[dict], labels: list[str], st: TrackSettings, share: float = 0.5) -> list[dict]:
    """Mark families of one mesh that run on another's curves (``pick = "all"``): status ``merged``.

    Family ``j`` merges with an earlier family ``i`` when at least ``share`` of
    ``j``'s admissible points lie within half a step of ``i``'s followed curves;
    a merged family is not carried further (its levels end).
    """
    out = [dict(lv) for lv in levels]
    live = [lv["status"] not in ("ended", "merged") and lv["pieces"] for lv in out]
    for j, lv in enumerate(out):
        if not live[j] or lv["status"] == "seed":
            continue
        band = Band(tuple(lv["band"]["T1"]), tuple(lv["band"]["T"]))
        P = np.concatenate([np.c_[p["T1"], p["T2"]][np.asarray(p["good"], bool)] for p in lv["pieces"]])
        if not len(P):
            continue
        U = band.to_u(P)
        for i in range(j):
            if not live[i]:
                continue
            V = band.to_u(np.concatenate([np.c_[p["T1"], p["T2"]] for p in out[i]["pieces"]]))
            near = np.linalg.norm(U[:, None, :] - V[None], axis=2).min(axis=1) < 0.5 * st.step
            if near.mean() >= share:
                out[j] = {**lv, "status": "merged", "notes": lv["notes"] + [
                    f"merged with {labels[i]}: {int(near.sum())} of its {len(U)} admissible points lie on "
                    f"{labels[i]}'s curves; not carried further"]}
                live[j] = False
                break
    return out
