"""The paper's figures for our numbers (``plbar figures``): solve the cases, then draw (:mod:`plbar.visuals.paper`).

Every ``fig*`` function solves what it needs (unless given results), draws one
figure family and returns the written PNG and PDF paths; :func:`make_all`
draws them all.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...app import Case, solve
from ...errors import InputError
from ...util.progress import progress_bar
from ...visuals import paper
from ..execution import solve_task
from ..loads import assign_families, default_positions
from .points import PAPER_POINTS, exact_point

__all__ = ["families_of", "sample_points", "load_optima",
           "fig2_paths", "fig3_time_histories", "fig4_energies", "fig5_loss_damping",
           "fig6_damping_paths", "fig7_load_responses", "fig8_xi_per_load", "fig9_xi_position", "make_all", "FIGURES"]


def families_of(res) -> list[str]:
    """Family label of each branch of a :class:`plbar.Result`."""
    T0I, T0II = res.paths.prob.system.T0
    return assign_families([(b.T.min(), b.T.max()) for b in res.paths.branches], [len(b) for b in res.paths.branches],
                           T0I, T0II)


def sample_points(res) -> dict:
    """The red and green points on the paths of ``res``: ``{"red": Orbits, "green": Orbits}``, exact
    (:func:`plbar.studies.paper.points.exact_point` at the paper's ``T^I``), or ``{}`` where the case has
    no path there (another chain or load)."""
    out = {}
    for name, (T1, T2, _) in PAPER_POINTS.items():
        try:
            out[name] = exact_point(res.paths.prob, T1, T2)
        except ValueError:                          # no sign change or no admissible orbit: not the paper's case
            return {}
    return out


def _solve(grid, **case):
    return solve(Case(grid=tuple(grid), **{"signatures": "paper", **case}))     # the paper's figures: its class


def _dof_cases(n_dofs, grid):
    return [_solve(grid, load_nodes=((k, 1.0),)) for k in range(1, n_dofs)]


def _one(draw, out, res, grid, points: bool = True):
    res = res or _solve(grid)
    return draw(out, res, families_of(res), sample_points(res)) if points else draw(out, res, families_of(res))


def fig2_paths(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 2: the periodic paths in ``(T1, T2, phi)`` and in the ``T1-T2`` plane."""
    return _one(paper.draw_fig2, out, res, grid)


def fig3_time_histories(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 3: displacement of every DOF over two periods at the red and green points."""
    return _one(paper.draw_fig3, out, res, grid)


def fig4_energies(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 4: kinetic, potential and total energy over two periods; the drop at the impact."""
    return _one(paper.draw_fig4, out, res, grid)


def fig5_loss_damping(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 5: ``Delta_PL`` and ``xi_eq`` against ``T`` and ``phi`` (all branches)."""
    return _one(paper.draw_fig5, out, res, grid, points=False)


def fig6_damping_paths(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 6: ``xi_eq`` against ``T`` separately for path 1 and path 2."""
    return _one(paper.draw_fig6, out, res, grid)


def fig7_load_responses(out, grid=(200, 200), cases=None) -> list[Path]:
    """Fig. 7: responses of every DOF at the red/green points for loads on DOF 1..N-1."""
    cases = cases or _dof_cases(5, grid)
    return paper.draw_fig7(out, cases, [families_of(r) for r in cases])


def fig8_xi_per_load(out, grid=(200, 200), cases=None) -> list[Path]:
    """Fig. 8: ``xi_eq`` along path 1 and path 2 for a unit force on each DOF."""
    cases = cases or _dof_cases(5, grid)
    return paper.draw_fig8(out, cases, [families_of(r) for r in cases])


def load_optima(ns=(3, 4, 5, 6), grid=(200, 200), family: str = "T0_II/2") -> list[dict]:
    """The best single unit force on ``family`` of the chain of each ``N``, as ``plbar sweep-loads -N N`` states it.

    The optimum is over every path point and every position ``s`` on the bar, continuous in ``s`` (the exact
    per-element maximum of :mod:`plbar.studies.loads.extremes`), not over a grid of positions.

    Returns
    -------
    list of dict
        Per ``N``: ``n``, ``xi`` (the largest ``xi_eq``), ``s`` (its position), ``T`` (its forcing period);
        ``None`` in place of the dict where the family has no path.
    """
    from ..loads import sweep_loads

    out = []
    for n in ns:
        st = sweep_loads(Case(model="chain", n=n, grid=tuple(grid)), pairs=False, plot=False, per_element=1)
        e = st.summary["families"].get(family)
        out.append(None if e is None else {"n": n, "xi": e["xi_best_single_max"], "s": e["s_at_best_single"],
                                           "T": e["T_at_best_single"]})
    return out


def fig9_xi_position(out, grid=(200, 200), ns=(3, 4, 5, 6), per_element=4, executor=None) -> list[Path]:
    """Fig. 9: ``xi_eq`` on the family near ``T0^II/2`` against ``T`` and the load position, N = 3..6.

    The colours are the solves at the grid of positions (``per_element`` per element); the star is the
    continuous optimum over ``s`` that ``plbar sweep-loads -N N`` states (:func:`load_optima`).
    """
    allres, labels = [], []
    for n in ns:
        pos = default_positions(n, per_element)
        tasks = [{"case": {"model": "chain", "n": n, "grid": list(grid), "load_points": [[s, 1.0]]}} for s in pos]
        rs = list(executor.map(solve_task, tasks)) if executor else [solve_task(t) for t in tasks]
        allres.append((n, pos, rs))
        labels.append([assign_families([(min(np.add(b["T1"], b["T2"])), max(np.add(b["T1"], b["T2"])))
                                        for b in r["branches"]], [len(b["T1"]) for b in r["branches"]],
                                       r["T0_I"], r["T0_II"]) for r in rs])
    return paper.draw_fig9(out, allres, labels, load_optima(ns, grid))


FIGURES = ("fig2", "fig3", "fig4", "fig56", "fig7", "fig8", "fig9")


def make_all(out, grid=(200, 200), which=None, progress: bool = False) -> list[Path]:
    """Draw the figure families ``which`` (default all of :data:`FIGURES`) into ``out`` (with a progress bar)."""
    which = list(which or FIGURES)
    bad = [w for w in which if w not in FIGURES]
    if bad:
        raise InputError(f"unknown figure(s) {bad}; choose from {', '.join(FIGURES)}")
    files: list[Path] = []
    with progress_bar(len(which) + 2, progress, "figures", "step", delay=0.0) as bar:
        res = _solve(grid) if {"fig2", "fig3", "fig4", "fig56"} & set(which) else None
        bar.update(1)
        cases = _dof_cases(5, grid) if {"fig7", "fig8"} & set(which) else None
        bar.update(1)
        draw = {"fig2": lambda: fig2_paths(out, res), "fig3": lambda: fig3_time_histories(out, res),
                "fig4": lambda: fig4_energies(out, res),
                "fig56": lambda: fig5_loss_damping(out, res) + fig6_damping_paths(out, res),
                "fig7": lambda: fig7_load_responses(out, cases=cases),
                "fig8": lambda: fig8_xi_per_load(out, cases=cases),
                "fig9": lambda: fig9_xi_position(out, grid)}
        for w in which:
            files += draw[w]()
            bar.update(1)
    return files
