"""The FE side of the refinement table of issue 29: the FE bar under mesh refinement, undamped and damped.

FE bar (L = c = 1, EA = rhoA = 1), end mass 0.5 at the contact, unit point force at s = 0.37, forcing periods
T/L = 2.5 and 3.5, from rest.  For each (element, mass) in P1 lumped, P2 consistent, P2 redistributed (when the
model has it) and N = 8 ... 256:

* the long run: 1,000 periods, the last 999 recorded: loss per period (mean, its standard error by 20 batch
  means), xi_eq, xi_w, impacts per period, the steadiness test (``steady``, ``drift_vMv``), the status;
* the first 20 periods: the first impact times and the contact displacement at 400 equally spaced times (for
  the comparison with the continuum, :mod:`plbar.continuum`, and the observed orders);

undamped and with 1 % Rayleigh damping at (T_a, T_b) = (2, 4) (the same physical damping on every mesh).
Writes ``results_refinement_fe.json`` beside this script.  Usage:
``python tests/bench/refinement_table.py [N ...]`` (default 8 16 32 64 128 256); ``--first`` recomputes only the
first 20 periods of the rows already written.
"""

import json
import sys
import time
from pathlib import Path

import numpy as np

import plbar
from plbar.motion import motion_series, padded, run, steady
from plbar.model import MASSES

NS = [int(x) for x in sys.argv[1:] if not x.startswith("--")] or [8, 16, 32, 64, 128, 256]
TS = (2.5, 3.5)
S_LOAD = 0.37
KINDS = [("P1", "lumped"), ("P2", "consistent")] + ([("P2", "redistributed")] if "redistributed" in MASSES else [])
DAMPINGS = (0.0, 0.01)
OUT = Path(__file__).with_name("results_refinement_fe.json")


def case_of(element, mass, n, xi):
    ray = plbar.rayleigh_from_ratio(xi, 2.0, 4.0) if xi else None
    return plbar.Case(model="fe", n=n, element=element, mass=mass, end_mass=0.5, load_points=((S_LOAD, 1.0),),
                      rayleigh=ray)


def batch_se(x, nb=20):
    x = np.asarray(x, float)
    edges = np.linspace(0, x.size, nb + 1).round().astype(int)
    means = np.array([x[i:j].mean() for i, j in zip(edges[:-1], edges[1:])])
    return float(means.std(ddof=1) / np.sqrt(nb))


def contact_history(prob, T, periods=20, samples=400):
    """First impact times and the contact displacement over the first ``periods`` periods from rest."""
    r = run(padded(prob), np.array([T]), 0.0, periods, periods)
    ms = motion_series(prob, r, 0)
    t = np.linspace(0.0, periods * T, samples + 1)[1:]
    x, _, _ = ms.response(t)
    ev = r.events
    sel = ev["kind"] >= 2
    imp, loss = ev["time"][sel][:200], ev["loss"][sel][:200]     # P2: precursor flights before the front
    return {"status": int(r.status[0]), "impact_times": [float(v) for v in imp],
            "impact_losses": [float(v) for v in loss],
            "t": [float(v) for v in t], "u_c": [float(v) for v in x[:, -1]]}


def first_only():
    """Recompute only the first-20-periods part of every row already in the results (cheap)."""
    rows = json.loads(OUT.read_text())
    for row in rows:
        prob = case_of(row["element"], row["mass"], row["N"], row["xi_rayleigh"]).problem()
        try:
            row["first"] = contact_history(prob, row["T"])
        except Exception as exc:                           # noqa: BLE001 (a failure is a result here)
            row["first"] = {"error": f"{type(exc).__name__}: {exc}"}
    OUT.write_text(json.dumps(rows, indent=1))


def main():
    rows = []
    for xi in DAMPINGS:
        for element, mass in KINDS:
            for n in NS:
                case = case_of(element, mass, n, xi)
                prob = case.problem()
                for T in TS:
                    t0 = time.perf_counter()
                    r = run(padded(prob), np.array([T]), 0.0, 1000, 999)
                    s = steady(r)
                    row = {"xi_rayleigh": xi, "element": element, "mass": mass, "N": n, "T": T,
                           "dofs": int(prob.system.n), "status": int(r.status[0]),
                           "kind": str(s.kind_names[0]), "loss_per_T": float(s.loss_per_T[0]),
                           "loss_se": batch_se(r.loss[0]), "xi_eq": float(s.xi_eq[0]), "xi_w": float(s.xi_w[0]),
                           "impacts_per_T": float(s.impacts_per_T[0]), "steady": int(s.steady[0]),
                           "drift_vMv": float(s.drift_vMv[0]), "drift_loss": float(s.drift_loss[0]),
                           "energy_residual": float(r.energy_residual[0]),
                           "xi_w_windows": [float(r.loss[0, a:b].mean() / (2 * 2 * np.pi / T * r.d_w[0, a:b].mean()))
                                            for a, b in ((0, 100), (200, 300), (899, 999))]}
                    try:
                        row["first"] = contact_history(prob, T)
                    except Exception as exc:               # noqa: BLE001 (a failure is a result here)
                        row["first"] = {"error": f"{type(exc).__name__}: {exc}"}
                    row["seconds"] = round(time.perf_counter() - t0, 2)
                    rows.append(row)
                    print(f"xi={xi} {element} {mass:13s} N={n:4d} T={T}: {row['kind']:9s} status {row['status']} "
                          f"loss {row['loss_per_T']:.5f} +- {row['loss_se']:.5f} xi_w {row['xi_w']:.5f} "
                          f"steady {row['steady']} drift {row['drift_vMv']:+.3f} ({row['seconds']} s)", flush=True)
                    OUT.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    first_only() if "--first" in sys.argv else main()
