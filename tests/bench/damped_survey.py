"""Inherent damping and the real motion (issue 21): surveys with Rayleigh ratios 0, 0.5, 1, 2, 5 %.

For the default case (161 forcing periods in [6, 14], the ratio fixed at T = 6 and 14) and an FE bar (P1 lumped,
N = 16, end mass 0.5, 81 forcing periods with T/L in [1.5, 4.5], the ratio fixed at T = 1.5 and 4.5), 1,000
periods each from rest: the fraction of forcing periods whose motion settles (periodic), the mean xi_eq of the
impact and the mean total ratio, and, where the motion is of the paper's class (1P), the simulated loss per
period against the exact response of ``plbar run`` (``find_response``: the same solver) at that T.

    python tests/bench/damped_survey.py [--quick]
    python tests/bench/damped_survey.py --plot      # docs/img/survey_damping.png from the results file

Writes ``tests/bench/results_damped_survey.json``.
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import plbar
from plbar.model import rayleigh_from_ratio
from plbar.studies import get_executor
from plbar.studies.survey import run_survey

RATIOS = (0.0, 0.005, 0.01, 0.02, 0.05)


def level(base: dict, T, at, ratio: float, periods: int) -> dict:
    case = plbar.Case(**base, rayleigh=rayleigh_from_ratio(ratio, *at) if ratio else None)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as d, get_executor("local") as ex:
        s = run_survey(case, T, periods, periods // 10, d, executor=ex, plot=False)
    t = s.table
    per = t["kind"] == "periodic"
    p1 = per & (t["signature"] == "1P")
    dev = np.abs(t["exact_loss"][p1] / t["loss_per_T"][p1] - 1)
    return {"ratio": ratio, "settled": float(per.mean()), "periodic": int(per.sum()), "points": int(t["T"].size),
            "paper_class": int(p1.sum()), "xi_eq_mean": float(np.nanmean(t["xi_eq"])),
            "xi_total_mean": float(np.nanmean(t["xi_total"])), "xi_eq_max": float(np.nanmax(t["xi_eq"])),
            "loss_dev_1P_max": float(dev.max()) if dev.size else None,
            "energy_residual_max": float(np.nanmax(np.abs(t["energy_residual"]))),
            "seconds": round(time.perf_counter() - t0, 1),
            "xi_eq_by_T": [[float(a), float(b)] for a, b in zip(t["T"], t["xi_eq"])]}


def plot(path=None, out="docs/img") -> None:
    """Draw ``survey_damping.png`` from the results file."""
    from plbar.visuals import survey_damping_plot
    from plbar.visuals.style import unit_note

    d = json.loads((path or Path(__file__).with_name("results_damped_survey.json")).read_text())
    titles = (("chain", "chain N = 5 (the paper's case)", plbar.Case()),
              ("fe16", "FE P1 lumped N = 16, end mass 0.5", plbar.Case(model="fe", n=16, end_mass=0.5)))
    levels = {title: [(r["ratio"], [p[0] for p in r["xi_eq_by_T"]], [p[1] for p in r["xi_eq_by_T"]], r["settled"])
                      for r in d[key]] for key, title, _ in titles}
    print(survey_damping_plot(levels, out, units={title: unit_note(case.bar()) for _, title, case in titles}))


def main(argv):
    if "--plot" in argv:
        return plot()
    quick = "--quick" in argv
    periods = 300 if quick else 1000
    out = {"chain": [], "fe16": []}
    for r in RATIOS:
        out["chain"].append(level({}, np.linspace(6, 14, 41 if quick else 161), (6.0, 14.0), r, periods))
        print("chain", {k: v for k, v in out["chain"][-1].items() if k != "xi_eq_by_T"}, flush=True)
    for r in RATIOS:
        out["fe16"].append(level({"model": "fe", "n": 16, "end_mass": 0.5}, np.linspace(1.5, 4.5, 21 if quick else 81),
                                 (1.5, 4.5), r, periods))
        print("fe16", {k: v for k, v in out["fe16"][-1].items() if k != "xi_eq_by_T"}, flush=True)
    Path(__file__).with_name("results_damped_survey.json").write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
