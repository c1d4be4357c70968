"""Benchmark of the refinement study (issue 13): families followed through N with the full model.

Run from the repository root (not part of the test suite)::

    python tests/bench/bench_refine.py            # everything (~10 min on 2 cores)
    python tests/bench/bench_refine.py --quick    # the acceptance command only (N <= 256)

1. The acceptance command, in-process and timed:
   ``plbar refine --model fe --element P1 --mass lumped --n 8 16 32 64 128 256 --family T0_II/2
   --end-mass 0.5`` (target < 5 min): time per level, G evaluations, the fitted exponent of the carried
   levels' time against N, and the cost of one G evaluation against N.
2. N = 400 carried from the same family (target < 5 min for that level).
3. Side by side in this process, the baseline a user had before: the 200 x 200 scan of the same window
   (``find_paths``) at N = 32 and 64, against the carried level: the time ratio, and the tracked family
   against the scan's branches on the curve (``compare_with_scan``, target 1e-9).

Writes ``tests/bench/results_refine.json``.
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import plbar
from plbar.paths import Band, find_paths
from plbar.response import scan_G
from plbar.studies import run_refine
from plbar.studies.refine.anchors import parse_anchor
from plbar.studies.refine.track import TrackSettings, carry_level
from plbar.studies.refine.track_check import compare_with_scan

NS = (8, 16, 32, 64, 128, 256)
HERE = Path(__file__).parent


def _levels(folder: Path) -> list[dict]:
    files = sorted((folder / "levels").rglob("N*.json"))
    return [json.loads(f.read_text())["levels"][0] for f in files]


def g_cost(n: int, reps: int = 6) -> float:
    """Seconds per evaluation of G at one point (FE P1 lumped, end mass 0.5, N elements)."""
    prob = plbar.Case(model="fe", n=n, end_mass=0.5).problem()
    scan_G(prob, np.array([0.3]), np.array([2.7]))
    t0 = time.perf_counter()
    for _ in range(reps):
        scan_G(prob, np.array([0.3]), np.array([2.7]))
    return (time.perf_counter() - t0) / reps


def acceptance(folder: Path) -> dict:
    t0 = time.perf_counter()
    case = plbar.Case(model="fe", element="P1", mass="lumped", end_mass=0.5)
    r = run_refine([case], NS, ["T0_II/2"], TrackSettings(), folder, progress=False)
    total = time.perf_counter() - t0
    lv = _levels(folder)
    carried = [x for x in lv if x["status"] != "seed"]
    n = np.array([x["n"] for x in carried], float)
    t = np.array([x["time"] for x in carried])
    expo = float(np.polyfit(np.log(n[n >= 32]), np.log(t[n >= 32]), 1)[0])
    return {"total_s": total, "levels": [{k: x[k] for k in ("n", "status", "time", "evaluations")} |
                                         {"admissible": int(sum(sum(p["good"]) for p in x["pieces"]))} for x in lv],
            "fitted_exponent_time_vs_N": expo, "rows": [{k: row[k] for k in ("n", "xi_max", "T_mid_T0I",
                                                                             "loss_ratio")} for row in r["rows"]]}


def n400(folder: Path) -> dict:
    lv = _levels(folder)[-1]
    case = plbar.Case(model="fe", n=400, end_mass=0.5)
    t0 = time.perf_counter()
    new = carry_level(lv, case, parse_anchor("T0_II/2"), TrackSettings())
    return {"time_s": time.perf_counter() - t0, "status": new["status"], "evaluations": new["evaluations"],
            "admissible": int(sum(sum(p["good"]) for p in new["pieces"]))}


def baseline(folder: Path, n: int) -> dict:
    lv = [x for x in _levels(folder) if x["n"] == n][0]
    case = plbar.Case(model="fe", n=n, end_mass=0.5)
    band = Band(tuple(lv["band"]["T1"]), tuple(lv["band"]["T"]))
    t0 = time.perf_counter()
    paths = find_paths(case.problem(), band.domain(), (200, 200))
    t_scan = time.perf_counter() - t0
    cmp = compare_with_scan(lv, case, paths=paths)
    return {"n": n, "scan_s": t_scan, "carried_s": lv["time"], "ratio": t_scan / lv["time"],
            "scan_branches": len(paths.branches), "compare": cmp}


def main(argv) -> None:
    warnings.simplefilter("ignore")
    quick = "--quick" in argv
    out = {"g_cost_s": {n: g_cost(n) for n in (32, 64, 128, 256, 400)}}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "acc"
        out["acceptance"] = acceptance(folder)
        print(f"acceptance command: {out['acceptance']['total_s']:.1f} s (target < 300 s); carried levels' time ~ "
              f"N^{out['acceptance']['fitted_exponent_time_vs_N']:.2f}")
        for x in out["acceptance"]["levels"]:
            print(f"  N = {x['n']:4d}: {x['status']:12s} {x['time']:7.1f} s, {x['evaluations']:6d} G evaluations, "
                  f"{x['admissible']} admissible points")
        print("  one G evaluation: " + ", ".join(f"N = {n}: {1e3 * t:.1f} ms" for n, t in out["g_cost_s"].items()))
        if not quick:
            out["n400"] = n400(folder)
            print(f"N = 400 carried from N = 256: {out['n400']['time_s']:.1f} s (target < 300 s), "
                  f"{out['n400']['status']}, {out['n400']['evaluations']} evaluations")
            out["baseline"] = [baseline(folder, n) for n in (32, 64)]
            for b in out["baseline"]:
                c = b["compare"]
                print(f"N = {b['n']}: 200 x 200 scan of the window {b['scan_s']:.1f} s ({b['scan_branches']} "
                      f"branches) vs carried level {b['carried_s']:.1f} s: ratio {b['ratio']:.0f}x; tracked "
                      f"admissible points on the scan's curves to {c['tracked_on_scan']}, the scan's family branches "
                      f"on the tracked curves to {c['scan_on_tracked']} ({c['tracked_off_scan']} tracked and "
                      f"{c['off']} scan points beyond the other side)")
    (HERE / "results_refine.json").write_text(json.dumps(out, indent=2, default=float) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
