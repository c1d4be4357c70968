"""The check of a tracked family against the full scan of its window on the same mesh.

A carried level (:mod:`.track`) never scans; this module scans its window
(:func:`plbar.find_paths`, the grid of a normal run) and compares:

* **on the curve**: every admissible point of a scan branch that lies next to
  the tracked curves is located on them: its foot on the nearest tracked chord
  is moved onto the zero set of ``G`` along the chord's normal
  (:func:`plbar.paths.correct_onto`), and the distance from the scan point to
  that zero is the point's distance to the tracked curve (0 up to round-off if
  both are the same curve, the curves' separation if not);
* **coverage**: the period range of those scan points against the tracked
  admissible range on the same curves (they differ by less than a grid cell
  where the scan resolves the family).
"""

from __future__ import annotations

import numpy as np

from ...app import Case
from ...paths import Band, correct_onto, find_paths

__all__ = ["compare_with_scan", "on_curves"]


def _chords(curves):
    """Start points, unit directions, lengths and curve index of every chord of ordered curves (normalised)."""
    A, D, Ln, C = [], [], [], []
    for c, U in enumerate(curves):
        if len(U) < 2:
            continue
        d = np.diff(U, axis=0)
        ln = np.linalg.norm(d, axis=1)
        ok = ln > 0
        A.append(U[:-1][ok])
        D.append(d[ok] / ln[ok, None])
        Ln.append(ln[ok])
        C.append(np.full(int(ok.sum()), c))
    if not A:
        return np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0), np.zeros(0, int)
    return np.concatenate(A), np.concatenate(D), np.concatenate(Ln), np.concatenate(C)


def _feet(S: np.ndarray, A, D, Ln):
    """For each point of ``S``: the foot on its nearest chord, that chord's normal, the distance and the chord."""
    rel = S[:, None, :] - A[None]
    s = np.clip(np.einsum("pcj,cj->pc", rel, D), 0, Ln[None])
    feet = A[None] + s[..., None] * D[None]
    dist = np.linalg.norm(S[:, None, :] - feet, axis=-1)
    k = np.argmin(dist, axis=1)
    i = np.arange(len(S))
    return feet[i, k], np.c_[-D[k, 1], D[k, 0]], dist[i, k], k


def _cells(band: Band, P: np.ndarray, S: np.ndarray, grid) -> float | None:
    """Largest distance of points ``P`` to the nearest of ``S``, in scan grid cells (None if either is empty)."""
    if not (len(P) and len(S)):
        return None
    dom = band.domain()
    cell = np.array([dom.T1[1] - dom.T1[0], dom.T2[1] - dom.T2[0]]) / np.asarray(grid, float)
    d = np.abs(P[:, None, :] - S[None]) / cell
    return float(d.max(axis=2).min(axis=1).max())


def on_curves(prob, band: Band, S: np.ndarray, curves, near: float):
    """Distance (in periods) of points ``S`` (K, 2) to ordered zero curves ``curves`` (lists of (M, 2) points).

    The foot of each point on its nearest chord is moved onto the zero set of
    ``G`` along the chord's normal (within a few times the foot's distance); the
    distance to that zero is 0 (round-off) for a point of the same curve and the
    curves' separation otherwise.  ``inf`` for points farther than ``near``
    (normalised) from every chord.  Also returns the index of the nearest curve.
    """
    A, D, Ln, C = _chords([band.to_u(c) for c in curves])
    out = np.full(len(S), np.inf)
    if not (len(A) and len(S)):
        return out, np.full(len(S), -1)
    feet, nrm, dist, k = _feet(band.to_u(S), A, D, Ln)
    sel = dist < near
    if sel.any():       # a reach of a few times the foot's distance: the nearest curve, not a neighbour's
        V, _ = correct_onto(prob, band, feet[sel], nrm[sel], np.maximum(4 * dist[sel], 1e-9))
        d = np.abs(band.from_u(V) - S[sel]).max(axis=1)
        out[sel] = np.where(np.isfinite(d), d, np.inf)
    return out, C[k]


def compare_with_scan(level: dict, case: Case, grid=(200, 200), near: float = 0.015, tol: float = 1e-9,
                      paths=None) -> dict:
    """Scan the window of ``level`` on the mesh of ``case`` and compare both ways (see the module docstring).

    ``paths`` (a :class:`plbar.Paths` of the same case, e.g. the full solve's) replaces the scan.

    Returns
    -------
    dict
        ``tracked_on_scan``: largest distance (relative to the anchor period) of
        a tracked admissible point on the scan's branches to them;
        ``tracked_off_scan``, ``tracked_off_points``, ``tracked_off_cells``: the
        tracked admissible points on no scan branch (stretches the scan does not
        resolve), and how far (in grid cells) they lie from the scan's points;
        ``branches``: the scan branches holding tracked points;
        ``scan_on_tracked``: largest distance of those branches' points to the
        tracked curves; ``off``: how many of their points lie off the tracked
        curves (beyond ``tol``), and the period range of those; ``tracked``,
        ``scan_points``: counts; ``scan_branches``: branches in the window.
    """
    prob = case.problem() if paths is None else paths.prob
    band = Band(tuple(level["band"]["T1"]), tuple(level["band"]["T"]))
    paths = find_paths(prob, band.domain(), grid) if paths is None else paths
    A = level["A"]
    brs = [(b.id, np.c_[b.T1, b.T2]) for b in paths.branches]
    good = [np.asarray(p["good"], bool) for p in level["pieces"]]
    Pt = np.concatenate([np.c_[p["T1"], p["T2"]][g] for p, g in zip(level["pieces"], good)]) \
        if level["pieces"] else np.zeros((0, 2))
    d1, near1 = on_curves(prob, band, Pt, [P for _, P in brs], near)
    d1 = d1 / A
    held = sorted({brs[c][0] for c, d in zip(near1, d1) if d < tol})
    S = np.concatenate([P for i, P in brs if i in held]) if held else np.zeros((0, 2))
    S = S[band.contains(S)]
    d2, _ = on_curves(prob, band, S, [np.c_[p["T1"], p["T2"]] for p in level["pieces"]], near)
    d2 = d2 / A
    off = d2 >= tol
    miss = d1 >= tol
    return {"tracked": int(len(Pt)), "tracked_on_scan": float(d1[~miss].max()) if (~miss).any() else None,
            "tracked_off_scan": int(miss.sum()),
            "tracked_off_range": [float(Pt[miss].sum(1).min()), float(Pt[miss].sum(1).max())] if miss.any() else None,
            "tracked_off_cells": _cells(band, Pt[miss], S, grid),
            "tracked_off_points": Pt[miss].tolist(),
            "branches": held, "scan_points": int(len(S)),
            "scan_on_tracked": float(d2[~off].max()) if (~off).any() else None, "off": int(off.sum()),
            "off_range": [float(S[off].sum(1).min()), float(S[off].sum(1).max())] if off.any() else None,
            "scan_branches": len(brs)}
