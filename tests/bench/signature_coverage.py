"""Coverage of the default signatures (issue 20): does plbar run find what the bar settles on from rest?

For every forcing period of a survey where the motion from rest is periodic with stroboscopic period
``m <= 4`` (and was polished into an exact orbit), look for a branch of the same signature in the
result of a solve with the default signatures, and polish that branch's nearest point to the survey's
``T``: covered if its loss per period equals the survey's exact loss (1e-6) and it is stable.

    plbar survey --out SURVEY && python tests/bench/signature_coverage.py SURVEY/survey.csv [--all]
    plbar survey --model fe -N 16 --end-mass 0.5 --damping-ratio 0.01 --at 1.5 4.5 --T 1.5 3.9 --num 81 --out S16
    python tests/bench/signature_coverage.py S16/survey.csv --fe
"""

from __future__ import annotations

import sys

import numpy as np

import plbar
from plbar.periodic import monodromy, multipliers, polish
from plbar.periodic.solve import NotConverged


def _candidates(res, label):
    """``(sig, orbits)`` of every branch of the result with canonical signature ``label``."""
    return [(h.sig, list(h.orbits)) for h in res.branches if h.label == label]   # the paper's class too: one record


def covered(res, T: float, label: str, loss: float):
    prob = res.prob
    for sig, orbs in _candidates(res, label):
        Ts = np.array([o.T for o in orbs])
        if not (Ts.min() - 0.02 * T <= T <= Ts.max() + 0.02 * T):
            continue
        for i in np.argsort(np.abs(Ts - T))[:3]:
            try:
                o = polish(prob, sig, T, orbs[i].X)
            except NotConverged:
                continue
            if abs(o.loss_per_T - loss) <= 1e-6 * loss:
                mu = multipliers(monodromy(prob, o.sig, o.T, o.phi, o.chain))
                return bool(np.abs(mu).max() < 1), o
    return False, None


def case_of(argv, kinds="paper"):
    """The default case, or with ``--fe`` the FE bar of issue 20 (P1 lumped, N = 16, end mass 0.5, Rayleigh 1 %
    at T = 1.5 and 4.5)."""
    if "--fe" in argv:
        from plbar.model import rayleigh_from_ratio

        return plbar.Case(model="fe", n=16, end_mass=0.5, rayleigh=rayleigh_from_ratio(0.01, 1.5, 4.5),
                          signatures=kinds)
    return plbar.Case(signatures=kinds)


def main(argv):
    import csv

    rows = list(csv.DictReader(open(argv[0])))
    import time

    t0 = time.perf_counter()
    kinds = "all" if "--all" in argv else "default"
    res = plbar.solve(case_of(argv, kinds))
    print(f"solve with the {kinds} signatures: {time.perf_counter() - t0:.1f} s")
    tot, hit, table = 0, 0, []
    for r in rows:
        if r["kind"] != "periodic" or int(r["m"]) > 4 or not r["signature"]:
            continue
        tot += 1
        ok, o = covered(res, float(r["T"]), r["signature"], float(r["exact_loss"]))
        hit += ok
        table.append((float(r["T"]), r["signature"], float(r["exact_loss"]), ok))
    for t in table:
        print(f"T = {t[0]:.4f}  {t[1]:8s} loss {t[2]:.8f}  {'found, stable' if t[3] else 'MISSING'}")
    print(f"coverage: {hit} / {tot} = {hit / max(tot, 1):.1%}")


if __name__ == "__main__":
    main(sys.argv[1:])
