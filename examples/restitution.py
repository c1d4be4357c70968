"""How far below the paper's plastic upper bound a partly elastic impact puts xi_eq (issue 31).

The paper assumes a perfectly plastic impact and calls its xi_eq (Eq. 22) an upper limit.  With Newton's
impact law (coefficient of restitution e: the contact leaves the wall at e times its speed, each impact loses
(1 - e^2) of Eq. (14)) this simulates the real motion from rest of two bars at every e in 0, 0.1, ..., 1 and
every forcing period of the survey's range (1,000 periods each, the last 100 characterise the motion), on all
local cores:

* the paper's chain (N = 5, unit force on DOF 1), 161 forcing periods in [6, 14] (units m = k = 1);
* an FE bar, P1 lumped, N = 16, with an end mass 0.5 at the contact, 161 forcing periods in [0.75, 2.25] T0^I
  (units L = c = 1, EA = 1).

Writes ``restitution_chain.csv`` / ``restitution_fe.csv`` (one row per (e, T), the survey's columns), their
summaries (``.json``) and the figure ``restitution.png``/``.pdf``, and prints, at every e, xi_eq over the
forcing periods (median, 10-90 %, largest), the median's ratio to the plastic one, and at how many forcing
periods the motion damps more than the plastic impact does at the same T (about 80 s on 2 busy cores).

Run::

    python examples/restitution.py [output folder] [--quick]      # default ./plbar-examples/restitution

``--quick`` (used by the tests): 9 forcing periods, e in 0, 0.3, 0.6, 1, 300 periods each.
"""

import sys
import time
from pathlib import Path

import plbar
from plbar.studies import get_executor
from plbar.studies.survey import default_periods, survey_restitution, write_restitution
from plbar.visuals import survey_restitution_plot

QUICK = "--quick" in sys.argv
ARGS = [a for a in sys.argv[1:] if not a.startswith("--")]
OUT = Path(ARGS[0] if ARGS else "plbar-examples/restitution")
E = (0.0, 0.3, 0.6, 1.0) if QUICK else tuple(round(0.1 * i, 1) for i in range(11))
PERIODS = 300 if QUICK else 1000
CASES = {"chain": (plbar.Case(), "m = k = 1", (8.0, 10.0, 12.0, 13.5)),
         "fe": (plbar.Case(model="fe", n=16, end_mass=0.5), "L = c = 1", None)}
TITLES = {"chain": "the paper's chain, N = 5", "fe": "FE bar P1 lumped, N = 16, end mass 0.5"}


def forcing_periods(case):
    T = default_periods(case)
    return T[::20] if QUICK else T


def report(key, res):
    s = res.summary
    print(f"{TITLES[key]}: {len(res.T)} forcing periods in [{res.T[0]:.4g}, {res.T[-1]:.4g}] x {len(res.restitutions)} "
          f"e, {PERIODS} periods each, {s['seconds']:.0f} s; energy budget closes to {s['energy_residual_max']:.1e}")
    print("     e  xi_eq: median (10 %,  90 %)   largest  ratio to e = 0  above e = 0 at  xi_w median  loss/T median"
          "  periodic")
    for e, d in s["by_e"].items():
        x, w, loss = d["xi_eq"], d["xi_w"], d["loss_per_T"]
        ratio = "" if d["ratio_to_plastic"] is None else f"{d['ratio_to_plastic']:.3f}"
        above = "" if d["above_plastic"] is None else f"{d['above_plastic']} T"
        print(f"  {float(e):4.2f}        {x['median']:.4f} ({x['q10']:.4f}, {x['q90']:.4f})    {x['max']:.4f}"
              f"        {ratio:>6}  {above:>14}       {w['median']:.4f}         {loss['median']:.4f}"
              f"  {d['kinds']['periodic']:>8}")


def conclusion(results):
    for key, res in results.items():
        by = res.summary["by_e"]
        r = {e: by[f"{e:g}"]["ratio_to_plastic"] for e in (0.3, 0.6) if f"{e:g}" in by}
        if r and "0" in by:
            print(f"{TITLES[key]}: e = 0.3-0.6 puts the median xi_eq at "
                  + " and ".join(f"{100 * v:.0f} % (e = {e:g})" for e, v in r.items())
                  + f" of the plastic upper bound {by['0']['xi_eq']['median']:.4f}")


def main():
    t0 = time.perf_counter()
    results, files = {}, []
    with get_executor("local") as ex:
        for key, (case, _, _) in CASES.items():
            res = survey_restitution(case, forcing_periods(case), E, PERIODS, executor=ex)
            results[key] = res
            files += write_restitution(OUT, res, f"restitution_{key}").values()
            report(key, res)
    conclusion(results)
    files += survey_restitution_plot({TITLES[k]: r.table for k, r in results.items()}, OUT, "restitution",
                                     periods={TITLES[k]: v[2] for k, v in CASES.items()},
                                     units={TITLES[k]: v[1] for k, v in CASES.items()})
    print(f"machine time {time.perf_counter() - t0:.0f} s")
    print("wrote", ", ".join(str(f) for f in files))
    return results


if __name__ == "__main__":
    main()
