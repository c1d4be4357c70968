"""Benchmark of the survey of the real motion (issue 19): the batched simulator against plbar.simulate.

Run from the repository root (not part of the test suite; best on an idle machine)::

    python tests/bench/bench_survey.py            # everything (~10 min on 2 cores)
    python tests/bench/bench_survey.py --quick    # the default survey and a sample of the baseline

1. The default survey (the paper's chain N = 5, unit force on DOF 1): 161 forcing periods in [6, 14], 1,000
   forcing periods each from rest, last 100 recorded, with the local executor on all cores (target < 30 s),
   exactly what ``plbar survey --no-plot --no-paths`` runs.
2. Side by side in this process, the baseline a user had: ``plbar.simulate`` one forcing period at a time
   (1,000 periods from rest, the same T), on every 4th T (``--quick``: every 16th): seconds per forcing period,
   the ratio, and the loss per period of the two (the same motion where it is periodic).
3. FE P1 lumped, N = 64, end mass 0.5: 50 forcing periods with T / L in [1.5, 4.5], 1,000 periods each
   (target < 10 min), and the baseline on a few of them (``plbar.simulate`` fails on this bar: its sampled
   event search brackets no sign change at some starts; the failures are counted).

Writes ``tests/bench/results_survey.json``.
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import plbar
from plbar.studies import get_executor
from plbar.studies.survey import run_survey

HERE = Path(__file__).parent


def survey_time(case, T, periods=1000, record=100) -> tuple[float, dict]:
    with tempfile.TemporaryDirectory() as d, get_executor("local") as ex:
        t0 = time.perf_counter()
        s = run_survey(case, T, periods, record, d, executor=ex, plot=False)
        return time.perf_counter() - t0, s.table


def baseline(case, T, periods=1000) -> tuple[float, list, int]:
    """``plbar.simulate`` one forcing period at a time: total seconds, loss per period (last 100), failures."""
    prob = case.problem()
    n = prob.system.n
    losses, failed = [], 0
    t0 = time.perf_counter()
    for t in T:
        try:
            sim = plbar.simulate(prob, t, 0.0, np.zeros(n), np.zeros(n), n_periods=periods)
        except Exception:  # noqa: BLE001 - counted: the baseline's own limitation
            failed += 1
            losses.append(float("nan"))
            continue
        last = sim.impact_times > (periods - 100) * t
        losses.append(float(sim.impact_losses[last].sum() / 100))
    return time.perf_counter() - t0, losses, failed


def part(case, T, every: int, periods=1000) -> dict:
    ts, table = survey_time(case, T, periods)
    sub = T[::every]
    tb, losses, failed = baseline(case, sub, periods)
    per_b = tb / sub.size
    per_s = ts / T.size
    sel = np.isin(table["T"], sub)
    mine = table["loss_per_T"][sel]
    periodic = table["kind"][sel] == "periodic"
    dev = np.abs(np.array(losses) - mine) / np.maximum(mine, 1e-300)
    return {"forcing_periods": int(T.size), "periods": periods, "cores": os.cpu_count(), "survey_s": round(ts, 2),
            "baseline_T": int(sub.size), "baseline_s": round(tb, 2), "baseline_failed": failed,
            "baseline_s_per_T": round(per_b, 4), "survey_s_per_T": round(per_s, 4),
            "ratio": round(per_b / per_s, 1),
            "periodic_loss_max_rel_dev": float(np.nanmax(dev[periodic])) if np.any(periodic & np.isfinite(dev))
            else None, "kinds": {k: int(np.sum(table["kind"] == k)) for k in ("periodic", "irregular", "failed")}}


def main(argv) -> None:
    quick = "--quick" in argv
    out = {}
    out["default"] = part(plbar.Case(), np.linspace(6, 14, 161), 16 if quick else 4)
    print("default survey:", json.dumps(out["default"]))
    if not quick:
        fe = plbar.Case(model="fe", n=64, element="P1", mass="lumped", end_mass=0.5)
        out["fe64"] = part(fe, np.linspace(1.5, 4.5, 50), 10)
        print("FE P1 N = 64, end mass 0.5:", json.dumps(out["fe64"]))
    (HERE / "results_survey.json").write_text(json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
