"""What the bar really does: the survey of the default case over the exact branches, and every signature.

Simulates the paper's chain (N = 5, unit force on DOF 1) from rest at 161 forcing periods in [6, 14], 1,000
periods each (the last 100 characterise the motion), on all local cores (about 8 s on 2 cores, every signature
included), and prints what a user who wants one damping ratio needs: the kinds of motion, xi_eq of the real
motion by band of T, and how often the paper's class is what happens.  Draws the survey over the exact branches of
the paper's class (``survey.png``) and the frequency response with every signature (``frequency_response.png``).

Run::

    python examples/real_motion.py [output folder] [--quick]      # default ./plbar-examples/real-motion

``--quick`` (used by the tests): 33 forcing periods in [11, 14], 400 periods each.
"""

import sys
from collections import Counter
from pathlib import Path

import numpy as np

import plbar
from plbar.studies import get_executor
from plbar.studies.survey import run_survey

QUICK = "--quick" in sys.argv
ARGS = [a for a in sys.argv[1:] if not a.startswith("--")]
OUT = Path(ARGS[0] if ARGS else "plbar-examples/real-motion")
T = np.linspace(11.0, 14.0, 33) if QUICK else np.linspace(6.0, 14.0, 161)
PERIODS, RECORD = (400, 40) if QUICK else (1000, 100)


def main():
    res = plbar.solve(plbar.Case(signatures="paper" if QUICK else "default"))
    with get_executor("local") as ex:
        s = run_survey(plbar.Case(), T, PERIODS, RECORD, OUT, executor=ex, overwrite=True, paths=res.paper)
    t = s.table
    kinds = Counter(t["kind"])
    print(f"survey of the default case: {len(t['T'])} forcing periods, {PERIODS} periods each: "
          f"{kinds['periodic']} periodic, {kinds['irregular']} irregular")
    sig = Counter(t["signature"][t["kind"] == "periodic"])
    print("periodic motions by signature: " + ", ".join(f"{k}: {v}" for k, v in sig.most_common()))
    print(f"the paper's class (1P) is what happens at {sig.get('1P', 0)} of {len(t['T'])} forcing periods")
    xi = t["xi_eq"]
    print(f"xi_eq of the real motion: median {np.nanmedian(xi):.4f}, 10 % quantile {np.nanquantile(xi, 0.1):.4f}, "
          f"largest {np.nanmax(xi):.4f}; xi_w median {np.nanmedian(t['xi_w']):.4f}")
    for lo, hi in zip(T.min() + np.arange(4) * np.ptp(T) / 4, T.min() + np.arange(1, 5) * np.ptp(T) / 4):
        sel = (t["T"] >= lo) & (t["T"] <= hi)
        print(f"  T in [{lo:.2f}, {hi:.2f}]: xi_eq median {np.nanmedian(xi[sel]):.4f} "
              f"(min {np.nanmin(xi[sel]):.4f}, max {np.nanmax(xi[sel]):.4f}), "
              f"periodic {int(np.sum(t['kind'][sel] == 'periodic'))}"
              f" of {int(sel.sum())}")
    print(f"energy budget closes to {s.summary['energy_residual_max']:.1e} of the work")
    if not QUICK:
        from plbar.visuals import frequency_response

        frequency_response(res, OUT, "frequency_response")
    print("wrote", ", ".join(str(f) for v in s.files.values() for f in (v if isinstance(v, list) else [v])))
    return s


if __name__ == "__main__":
    main()
