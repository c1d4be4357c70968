"""Mesh refinement (paper Sec. 4.3) and the continuum check: a family followed through N with the full model.

1. A uniform P1 lumped bar (L = 1, EA = rhoA = 1, unit force at L/2) with a rigid end mass of half the bar's
   mass: the family near T0_II/2, N = 8 ... 256.  The impact loss is Delta_PL = S v_c^2 / 2 exactly, with
   S = M_e + rhoA L / (2 N) here, so Delta_PL / (M_e v_c^2 / 2) -> 1 at rate 1; xi_eq falls to 0 anyway.
2. The same bar without an end mass: xi_eq falls faster (Delta_PL itself ~ h).
3. The paper's chain (N is the model): its path 2, N = 5 ... 48.
4. Why xi_eq falls: the damping denominator of Eq. (22) on the velocity jump that the impact leaves in the
   bar (0 at the clamp, v_c stopped at the contact) grows like (2 / pi) rhoA c v_c^2 ln N (printed against N).

PLBAR_NMAX limits the largest N (default 256; the example test uses 32).  Resumable study folders under
argv[1] (default ./plbar-refinement).  Prints the tables and the continuum check.
"""
import math
import os
import sys
from pathlib import Path

import numpy as np

import plbar
from plbar.studies import run_refine

NMAX = int(os.environ.get("PLBAR_NMAX", "256"))
FE_NS = [n for n in (8, 16, 32, 64, 128, 256) if n <= NMAX]
CHAIN_NS = [n for n in (5, 6, 8, 12, 16, 24, 32, 48) if n <= max(NMAX // 2, 8)]


def table(title: str, r) -> None:
    print(title)
    print("      N  status        adm.  main stretch T/T0_I  largest xi_eq   Delta_PL/(M_e v_c^2/2)")
    for row in r.rows:
        t0 = row["T0_I_L"]
        rng = (f"[{row['T_min_L'] / t0:.5f}, {row['T_max_L'] / t0:.5f}]" if np.isfinite(row["T_min_L"])
               else "-").ljust(21)
        xi = f"{row['xi_max']:.3e}" if np.isfinite(row["xi_max"]) else "-".ljust(9)
        lr = f"{row['loss_ratio']:.6f}" if np.isfinite(row["loss_ratio"]) else "-"
        print(f"  {row['n']:5d}  {row['status']:12s} {row['admissible']:5d}  {rng} {xi}       {lr}")
    for fams in r.rates.values():
        for q in fams.values():
            for name in ("T0_I_L", "T0_II_L", "S/M_e", "T_mid_T0I", "T_spread_T0I", "xi_max"):
                if name in q:
                    c = q[name]
                    if c["rate"] is None:
                        print(f"    {name:13s} no rate: {c['why']}")
                    elif c["caution"]:                      # too few meshes, or values that wander
                        print(f"    {name:13s} no rate stated: {c['caution']}")
                    else:
                        fit = f", fitted {c['fitted']:.3f}" if c["fitted"] is not None else ""
                        lim = f"-> {c['limit']:.6g}: " if c["limit"] is not None else ""
                        print(f"    {name:13s} {lim}rate {c['rate']:.3f} ({c['meshes']} meshes{fit})")
            if q["xi_decay"].get("model") and len(q["xi_decay"]["h"]) >= 4:
                print(f"    xi_max decays like {q['xi_decay']['formula']}")


def jump_energy() -> None:
    print("damping denominator of the velocity v = x (a unit jump at the contact), sum_j w_j etadot_j^2 "
          "(rhoA = c = 1):")
    prev = None
    for n in (16, 32, 64, 128, 256):
        s = plbar.Case(model="fe", n=n, end_mass=0.5).problem().system
        ed = s.V1.T @ (s.M[:-1, :-1] @ s.x[:-1])
        e = float(np.sum(s.w1 * ed ** 2))
        step = "" if prev is None else f"   step / ln 2 = {(e - prev) / math.log(2):.5f} (2/pi = {2 / math.pi:.5f})"
        print(f"  N = {n:4d}: {e:.5f}{step}")
        prev = e


if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "plbar-refinement")
    fe = plbar.Case(model="fe", element="P1", mass="lumped")
    r1 = run_refine([plbar.Case(model="fe", end_mass=0.5)], FE_NS, ["T0_II/2"], out=out / "end-mass")
    table("1. P1 lumped, end mass 0.5 of the bar's mass, family T0_II/2:", r1)
    r2 = run_refine([fe], FE_NS, ["T0_II/2"], out=out / "no-end-mass")
    table("2. P1 lumped, no end mass, family T0_II/2:", r2)
    r3 = run_refine([plbar.Case(model="chain")], CHAIN_NS, ["T0_II/2"], out=out / "chain")
    table("3. the paper's chain, path 2 (T0_II/2):", r3)
    jump_energy()
