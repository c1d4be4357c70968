"""The load study of the real motion, checked (issue 28): energy of every cell, and every periodic cell's exact loss.

For the default case (161 forcing periods x 20 positions) or ``--fe`` (FE P1 lumped N = 16, end mass 0.5,
161 x 32 positions), 1,000 periods from rest each (``plbar.studies.survey.run_survey_loads``):

* every cell's energy budget (work - impact losses - change of energy) relative to the work: <= 1e-12;
* every periodic cell: its exact orbit (the survey's polish of that cell, rebuilt here) is replayed over its
  ``m`` periods by the independent event-driven simulator :func:`plbar.check.simulate` (its own flows,
  sampled events, brentq): the state comes back to the start, and the replayed impact losses per period
  equal the table's ``exact_loss`` (1e-8); where the orbit is of the paper's class (``1P``), the paper's
  closed-form solver (:func:`plbar.find_response` at the orbit's stuck time) gives the same loss (1e-8);
* the window's mean loss of a periodic cell still settling is within ``3 x orbit_distance`` of the exact one.

Usage (not a test; ~1 minute for the default case, ~5 with ``--fe``, 2 cores)::

    python tests/bench/verify_survey_loads.py [--fe] [--out DIR]
"""

from __future__ import annotations

import argparse
import json
import shutil
import time
from dataclasses import replace
from pathlib import Path

import numpy as np


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fe", action="store_true")
    ap.add_argument("--out", default=None)
    ap.add_argument("--save", default=None, help="write the numbers as JSON")
    a = ap.parse_args(argv)
    import plbar
    from plbar.check import simulate
    from plbar.motion import padded, run
    from plbar.response import NoResponseError, find_response
    from plbar.studies import get_executor
    from plbar.studies.survey import run_survey_loads
    from plbar.studies.survey.settle import approach, orbit_of, settle

    case = plbar.Case(model="fe", n=16, end_mass=0.5) if a.fe else plbar.Case()
    out = Path(a.out or ("/tmp/verify-survey-loads-fe" if a.fe else "/tmp/verify-survey-loads"))
    shutil.rmtree(out / "tasks", ignore_errors=True)      # a study resumes its finished tasks: start afresh here
    t0 = time.perf_counter()
    with get_executor("local", None, 2) as ex:
        sl = run_survey_loads(case, out=out, executor=ex, overwrite=True, progress=True)
    t_study = time.perf_counter() - t0
    t = sl.table
    energy = float(np.max(np.abs(t["energy_residual"])))
    per = np.flatnonzero(t["kind"] == "periodic")
    worst_replay = worst_loss = worst_paper = worst_window = 0.0
    checked = paper = settling = 0
    missing = []
    for s in np.unique(t["s"][per]):
        rows = per[t["s"][per] == s]
        cs = replace(case, load_nodes=(), load_points=((float(s), 1.0),))
        prob = cs.problem()
        r = run(padded(prob), t["T"][rows], 0.0, sl.summary["periods"], sl.summary["record"])
        for b, i in enumerate(rows):
            if not t["signature"][i]:
                missing.append((float(s), float(t["T"][i])))
                continue
            if t["distance"][i] <= 1e-6:
                orb = approach(r, b, orbit_of(prob, r, b, int(t["m"][i]))).orbit
            else:
                ap_ = settle(prob, r, b)
                orb = ap_.orbit
                settling += 1
                worst_window = max(worst_window, abs(t["loss_per_T"][i] - t["exact_loss"][i])
                                   / (t["exact_loss"][i] * max(3 * t["orbit_distance"][i], 1e-6)))
            m, T = orb.sig.m, orb.T
            x0, v0 = orb.start
            sim = simulate(prob, T, orb.phi, x0, v0, 1, m)
            back = max(np.abs(sim.x - x0).max(), np.abs(sim.v - v0).max()) / max(np.abs(x0).max(), np.abs(v0).max())
            loss = float(sim.impact_losses.sum()) / m
            worst_replay = max(worst_replay, back)
            worst_loss = max(worst_loss, abs(loss - t["exact_loss"][i]) / t["exact_loss"][i])
            if str(orb.sig) == "1P":
                try:
                    fr = find_response(prob, T, float(orb.durations[0]))
                    worst_paper = max(worst_paper, abs(fr.dPL - t["exact_loss"][i]) / t["exact_loss"][i])
                    paper += 1
                except NoResponseError:
                    missing.append((float(s), float(T), "find_response"))
            checked += 1
    res = {"case": "fe P1 N=16 end mass 0.5" if a.fe else "default", "cells": int(t["T"].size),
           "positions": int(np.unique(t["s"]).size), "periodic": int(per.size), "settling": settling,
           "kinds": sl.summary["kinds"], "energy_residual_max": energy, "replayed": checked,
           "replay_back_to_start_max": worst_replay, "replay_loss_rel_max": worst_loss,
           "paper_class_checked": paper, "paper_loss_rel_max": worst_paper,
           "settling_window_over_3_distance_max": worst_window, "no_orbit": missing,
           "seconds_study": round(t_study, 1), "seconds_total": round(time.perf_counter() - t0, 1),
           "position_of_largest_mean_xi_eq": {n: d["position_of_largest_mean_xi_eq"]
                                              for n, d in sl.summary["by_N"].items()}}
    print(json.dumps(res, indent=1))
    if a.save:
        with open(a.save, "w") as f:
            json.dump(res, f, indent=1)


if __name__ == "__main__":
    main()
