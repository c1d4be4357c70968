"""How studies use their workers (issue 43): parallel efficiency from 1 to all workers, measured, and the task
sizing simulated at 16 and 64 workers from measured trajectory costs.

Usage (not a test; about 3 minutes on 2 cores)::

    python tests/bench/bench_scaling.py [--workers 1 2 ...] [--out tests/bench/results_scaling.json]

For each study -- the default survey (161 forcing periods x 1,000), an FE survey (P1 lumped, N = 64, end mass
0.5, 50 forcing periods x 1,000) and a load study (the default chain, 5 positions x 41 forcing periods x 1,000) --
it times the whole study (``run_survey`` / ``run_survey_loads`` with the local executor, no figure, a fresh folder;
a warm-up run first so that every kernel is loaded from the cache) at each number of workers and prints the
speed-up ``t_1 / t_w`` and the efficiency ``t_1 / (w t_w)``.

Then the cost of every trajectory alone (one forcing period per task, in this process) is measured, a cost model
``c(T) = a + b T`` is fitted to it, and the study's own tasks (as it makes them, submitted costliest first as
:func:`plbar.studies.run_study` does) are list-scheduled on 2, 4, 16 and 64 workers with the measured and the
fitted costs: the efficiency of the task sizing when nothing else (imports, the parent's fixed cost) counts.
"""

from __future__ import annotations

import argparse
import heapq
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent


def _studies():
    import plbar
    from plbar.studies.survey.study import default_periods

    fe = plbar.Case(model="fe", n=64, end_mass=0.5)
    return {"survey": (plbar.Case(), default_periods(plbar.Case(), 161), None),
            "fe64": (fe, default_periods(fe, 50), None),
            "loads": (plbar.Case(), np.linspace(6.0, 14.0, 41), [0.5, 1.5, 2.5, 3.5, 4.5])}


def _run(case, T, positions, workers: int, folder: Path) -> float:
    from plbar.studies import get_executor
    from plbar.studies.survey import run_survey, run_survey_loads

    t0 = time.perf_counter()
    with get_executor("local", workers=workers) as ex:
        if positions is None:
            run_survey(case, T, 1000, None, folder, executor=ex, progress=False, plot=False, paths=False)
        else:
            run_survey_loads(case, T, positions, periods=1000, out=folder, executor=ex, progress=False,
                             plot=False)
    return time.perf_counter() - t0


def _tasks(case, T, positions):
    from plbar.studies.survey.loads import survey_loads_study
    from plbar.studies.survey.study import survey_study

    st = survey_study(case, T, 1000) if positions is None else survey_loads_study(case, T, positions, periods=1000)
    return st.tasks, st.cost


def _costs(case, T, positions) -> dict:
    """Seconds of every trajectory alone, keyed by (position, T)."""
    from plbar.studies.survey.loads import survey_loads_study
    from plbar.studies.survey.study import survey_study
    from plbar.studies.survey.tasks import survey_task

    out = {}
    for s in (positions or [None]):
        for t in T:
            if s is None:
                task = survey_study(case, [t], 1000).tasks[0]
            else:
                task = survey_loads_study(case, [t], [s], periods=1000).tasks[0]
            survey_task(task)                                   # the case's model built once
            t0 = time.perf_counter()
            survey_task(task)
            out[(s, float(t))] = time.perf_counter() - t0
    return out


def _makespan(loads: list[float], workers: int) -> float:
    heap = [0.0] * workers
    for c in sorted(loads, reverse=True):                      # costliest first (Study.cost)
        heapq.heappush(heap, heapq.heappop(heap) + c)
    return max(heap)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, nargs="+", default=sorted({1, os.cpu_count() or 1}))
    ap.add_argument("--out", default=str(HERE / "results_scaling.json"))
    a = ap.parse_args(argv)
    os.environ["PLBAR_THREADS"] = "1"
    res = {}
    for name, (case, T, positions) in _studies().items():
        with tempfile.TemporaryDirectory() as tmp:
            _run(case, T, positions, max(a.workers), Path(tmp) / "warm")
            times = {w: _run(case, T, positions, w, Path(tmp) / f"w{w}") for w in a.workers}
        t1 = times[min(a.workers)] * min(a.workers)
        row = {"wall_s": times, "efficiency": {w: t1 / (w * times[w]) for w in a.workers}}
        costs = _costs(case, T, positions)
        keys = np.array([k[1] for k in costs]), np.array(list(costs.values()))
        b, c0 = np.polyfit(keys[0], keys[1], 1)
        tasks, _ = _tasks(case, T, positions)
        measured = [sum(costs[(t.get("s"), float(x))] for x in t["T"]) for t in tasks]
        fitted = [sum(c0 + b * x for x in t["T"]) for t in tasks]
        row["cost_model"] = {"a_s": c0, "b_s_per_T": b, "corr": float(np.corrcoef(*keys)[0, 1]),
                             "trajectories": len(costs), "tasks": len(tasks), "total_s": float(sum(measured))}
        row["simulated"] = {w: {"measured": sum(measured) / (w * _makespan(measured, w)),
                                "fitted": sum(fitted) / (w * _makespan(fitted, w))} for w in (2, 4, 16, 64)}
        res[name] = row
        eff = ", ".join(f"{w}: {row['efficiency'][w]:.2f} ({times[w]:.2f} s)" for w in a.workers)
        sim = ", ".join(f"{w}: {v['measured']:.2f}" for w, v in row["simulated"].items())
        print(f"{name:7s} measured efficiency {eff}; {len(tasks)} tasks, simulated (measured costs) {sim}; "
              f"cost ~ {c0 * 1e3:.1f} ms + {b * 1e3:.2f} ms x T (corr {row['cost_model']['corr']:.2f})")
    Path(a.out).write_text(json.dumps(res, indent=1, default=str) + "\n")


if __name__ == "__main__":
    main()
