"""Benchmark of issue #12: load studies on one path solve vs the old per-load sweep.

Run: ``PLBAR_THREADS=1 python tests/bench/bench_loads.py`` (a script, not a test).

For each case: the one path solve (``plbar.solve``), then the load study
beyond it: building ``b, G`` at every path point, ``xi_eq`` and ``Delta_PL``
of 1,000 unit point-force positions, the worst load (``b^T G^+ b / 2`` and
``q*``) and the exact per-element maximum of a moving force.  The old sweep
(``plbar.studies.loads.bruteforce``: one full solve per position through ``plbar.studies.solve_task``)
is timed side by side on ``OLD_SAMPLES`` positions and extrapolated linearly
to 1,000 (every old task is an independent solve of the same size).
"""

import sys
import time

import numpy as np

import plbar
from plbar.studies.loads.forms import load_forms
from plbar.studies import solve_task

POSITIONS = 1000


def _case_dict(case: plbar.Case, s: float) -> dict:
    d = case.to_dict()
    d.update(load_nodes=[], load_points=[[float(s), 1.0]])
    return {"case": d}


def bench(name: str, case: plbar.Case, old_samples: int) -> dict:
    t0 = time.perf_counter()
    res = plbar.solve(case)
    t_solve = time.perf_counter() - t0
    L = res.prob.bar.length
    s = np.linspace(0.0, L, POSITIONS + 1)[1:]
    t1 = time.perf_counter()
    lf = load_forms(res.paths)
    t_forms = time.perf_counter() - t1
    xi, dpl = lf.point_loads(s)
    t_pos = time.perf_counter() - t1 - t_forms
    w = lf.worst()
    t_worst = time.perf_counter() - t1 - t_forms - t_pos
    em = lf.element_max()
    t_new = time.perf_counter() - t1
    t_emax = t_new - t_forms - t_pos - t_worst
    rng = np.random.default_rng(0)
    pick = rng.choice(s[s < L], old_samples, replace=False)
    t2 = time.perf_counter()
    for v in pick:
        solve_task(_case_dict(case, v))
    t_old_each = (time.perf_counter() - t2) / old_samples
    t_old = t_old_each * POSITIONS
    return dict(name=name, dofs=lf.n, points=len(lf), t_solve=t_solve, t_forms=t_forms, t_pos=t_pos,
                t_worst=t_worst, t_emax=t_emax, t_new=t_new, t_old_each=t_old_each, t_old=t_old,
                ratio=t_old / (t_solve + t_new), xi_max=float(xi.max()), worst_max=float(w.xi.max()),
                best_single=float(em.xi.max()))


def main(argv=None) -> int:
    rows = [bench("chain N=5 (grid 200x200)", plbar.Case(), 5),
            bench("FE P1 lumped N=40 (grid 200x200)", plbar.Case(model="fe", n=40, element="P1", mass="lumped"), 1)]
    print(f"{'case':34s} {'dofs':>4s} {'points':>6s} {'solve s':>8s} {'forms':>7s} {'1000 pos':>8s} "
          f"{'worst':>7s} {'elem max':>8s} {'beyond':>7s} {'old/solve':>9s} {'old 1000':>9s} {'ratio':>7s}")
    for r in rows:
        print(f"{r['name']:34s} {r['dofs']:4d} {r['points']:6d} {r['t_solve']:8.3f} {r['t_forms']:7.3f} "
              f"{r['t_pos']:8.3f} {r['t_worst']:7.3f} {r['t_emax']:8.3f} {r['t_new']:7.3f} {r['t_old_each']:9.3f} "
              f"{r['t_old']:9.1f} {r['ratio']:7.0f}")
    print("beyond = forms + 1000 positions + worst + element max (s); old 1000 = old per-position solve x 1000 "
          "(extrapolated from the timed sample); ratio = old 1000 / (solve + beyond)")
    for r in rows:
        print(f"{r['name']}: max xi(1000 positions) = {r['xi_max']:.6g}, best single (exact) = "
              f"{r['best_single']:.6g}, worst load = {r['worst_max']:.6g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
