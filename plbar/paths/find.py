"""``find_paths``: scan, curves, evaluation, admissible runs, branches (orchestration only).

1. :mod:`.scan` evaluates ``G`` on a grid and refines every sign change;
2. :mod:`.evaluate` keeps the true zeros and picks the admissible phase;
3. :mod:`.continuation` (or :mod:`.contour`) turns the crossings into ordered curves;
4. the curves are cut into maximal admissible runs, and :mod:`.branches` makes
   them branches with damping and events (stability: the periodic core, :func:`plbar.periodic.from_paths`).
"""

from __future__ import annotations

import time

import numpy as np

from ..errors import InputError
from ..model import Problem
from ..util.progress import progress_bar
from . import continuation
from .branches import Domain, Paths, build_branches, default_domain
from .contour import curves_grid
from .evaluate import ZERO_TOL, evaluate
from .scan import scan

__all__ = ["find_paths", "admissible_runs", "METHODS"]

METHODS = ("continuation", "grid")


def admissible_runs(curves, good, why) -> list:
    """Maximal runs of admissible points along each curve, with what ended them.

    ``curves`` is a list of ``(point indices, (start, end))``; a run that starts or
    ends inside a curve is ended by the reason of its inadmissible neighbour.
    """
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
    return runs


def _traced(prob, sc, ev0, progress, stats):
    """Continuation curves through the scan's admissible crossings, as index runs into a new evaluation."""
    zero0 = (ev0.r1 < ZERO_TOL) & (ev0.r2 < ZERO_TOL)
    traced = continuation.curves(prob, sc, zero0, ev0.good, progress)
    allP = np.concatenate([c[0] for c in traced]) if traced else np.zeros((0, 2))
    offs = np.r_[0, np.cumsum([len(c[0]) for c in traced])]
    stats["traced_points"] = int(len(allP))
    ev = evaluate(prob, allP, progress, "checking path points") if len(allP) else None
    return [(np.arange(offs[i], offs[i + 1]), traced[i][1]) for i in range(len(traced))], ev


def find_paths(prob: Problem, domain: Domain | None = None, grid: tuple[int, int] = (200, 200),
               method: str = "continuation", progress: bool = False) -> Paths:
    """All admissible periodic paths of ``prob`` in ``domain``.

    Parameters
    ----------
    prob : Problem
    domain : Domain, optional
        Default: the paper's ``(0, T0^alpha / 2]`` (:func:`default_domain`).
    grid : (int, int)
        Grid points along ``T^I`` and ``T^II`` for the scan of ``G``.
    method : {"continuation", "grid"}
        ``"continuation"``: the scan's crossings seed pseudo-arclength
        continuation, so every branch is an ordered curve resolved at least as
        finely as the grid, through the scan's own points; ``"grid"``: the
        crossings linked by the marching-squares topology (faster; fragments
        where two curves come closer than a grid cell).
    progress : bool
        Show progress bars (stderr) while scanning and tracing.

    Returns
    -------
    Paths
        Branches ordered by their smallest period ``T``; each ordered along its curve.
    """
    if method not in METHODS:
        raise InputError(f"method = {method!r} is not allowed; choose continuation or grid")
    if prob.affine:
        raise InputError(f"{prob.static_part}: the paper's scan of (T1, T2) (Eqs. (15)-(18)) is written for a stop "
                         "at rest contact (gap 0) and no constant load; with either the periodic responses come from "
                         "the signature search (plbar.solve, plbar run) and the real motion from the survey")
    t0 = time.perf_counter()
    domain = domain or default_domain(prob)
    n1, n2 = (int(g) for g in grid)
    if n1 < 3 or n2 < 3:
        raise InputError(f"grid = ({n1}, {n2}) is too coarse; use at least 3 points per axis (default 200 x 200)")
    sc = scan(prob, domain, (n1, n2), progress=progress)
    stats = {"grid": [n1, n2], "method": method, "crossings": int(sc.ids.size), "t_scan": time.perf_counter() - t0}
    branches = []
    if sc.ids.size:
        stats["refine_iterations"] = sc.iterations
        ev0 = evaluate(prob, sc.P, progress, "checking crossings")
        stats["zeros"] = int((ev0.r1 < ZERO_TOL).sum())
        stats["admissible_crossings"] = int(ev0.good.sum())
        t1c = time.perf_counter()
        if method == "grid":
            curves = [(np.asarray(ix, int), ends) for ix, ends in curves_grid(sc)]
            ev = ev0
        else:
            curves, ev = _traced(prob, sc, ev0, progress, stats)
        stats["t_curves"] = time.perf_counter() - t1c
        runs = admissible_runs(curves, ev.good, ev.why) if ev is not None else []
        with progress_bar(1, progress, "damping", "batch", delay=2.0) as bar:
            branches = build_branches(ev, runs)
            bar.update(1)
        stats["admissible"] = int(sum(len(r) for r, _ in runs))
    stats["t_total"] = time.perf_counter() - t0
    return Paths(prob, domain, (n1, n2), tuple(branches), stats)
