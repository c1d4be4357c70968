"""Mesh refinement (paper Sec. 4.3): periods and xi_eq maxima against N.

1. The paper's chain, N = 3..6, unit point load at s/L = 0.05, 0.10, ..., 0.95
   (nodes and linear splits between them): the fundamental periods and the maximum
   xi_eq on the family near T0_II/2 over the load positions, next to the paper's
   maxima (N = 3: 0.0418; N = 4: > 0.5 "artefact"; N = 5: 0.121; N = 6: 0.111).
2. A uniform P1 lumped FE bar (L = 1, EA = rhoA = 1), load at mid-length, N = 4 .. 64,
   with coarser scan grids for large N and T2 searched in [0.5, 1] * T0_II/2
   (PLBAR_FE_NMAX limits the largest N, default 64; N = 64 takes ~90 s on one core at 20x20).
   PLBAR_GRID="N1,N2" sets the chain's scan grid (default 200,200).

Resumable study folders under argv[1] (default ./plbar-refinement).
"""
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from plbar.studies import get_executor
from plbar.studies import refine_study, refine_tables, write_refine_tables
from plbar.studies import run_study

PAPER = {3: "0.0418", 4: ">0.5 (artefact)", 5: "0.121", 6: "0.111"}
PAPER_T0II = {3: 14.12, 4: 18.09, 5: 22.07, 6: 26.06}
FE_GRID = {4: (200, 200), 8: (160, 160), 16: (100, 100), 32: (60, 60), 64: (20, 20)}

if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "plbar-refinement")
    fe_nmax = int(os.environ.get("PLBAR_FE_NMAX", "64"))
    grid = tuple(int(v) for v in os.environ.get("PLBAR_GRID", "200,200").split(","))
    chain = refine_study([3, 4, 5, 6], ("chain",), fracs=np.round(np.arange(1, 20) * 0.05, 2), grid=grid)
    fe_ns = [n for n in FE_GRID if n <= fe_nmax]
    fe = refine_study(fe_ns, ("fe-P1-lumped",), fracs=(0.5,), grid=FE_GRID, T2_frac=(0.5, 1.0))
    with get_executor("local") as ex:
        t0 = time.perf_counter()
        rc = run_study(out / "chain", chain, ex)
        t1 = time.perf_counter()
        rf = run_study(out / "fe-P1-lumped", fe, ex)
        t2 = time.perf_counter()
    tc, tf = refine_tables(chain.tasks, rc), refine_tables(fe.tasks, rf)
    write_refine_tables(out / "chain", tc)
    write_refine_tables(out / "fe-P1-lumped", tf)
    print(f"chain N = 3..6 ({len(chain.tasks)} cases, {t1 - t0:.0f} s):")
    print("  N   T0_I     T0_II (paper)     path 2: T range        max xi_eq  at s/L  | paper max")
    m = tc.maxima
    for i in range(len(m["n"])):
        if m["family"][i] != "T0_II/2":
            continue
        n = m["n"][i]
        if not np.isfinite(m["T_min"][i]):
            print(f"  {n}  {m['T0_I'][i]:7.4f}  {m['T0_II'][i]:7.4f} ({PAPER_T0II[n]:5.2f})   no branch near T0_II/2")
            continue
        print(f"  {n}  {m['T0_I'][i]:7.4f}  {m['T0_II'][i]:7.4f} ({PAPER_T0II[n]:5.2f})   "
              f"[{m['T_min'][i]:7.4f}, {m['T_max'][i]:7.4f}]   {m['xi_max'][i]:.4f}    {m['frac_at_max'][i]:.2f}   "
              f"| {PAPER[n]}")
    print(f"P1 lumped FE bar, load at L/2 ({len(fe.tasks)} cases, {t2 - t1:.0f} s):")
    print("  N    grid      T0_I     T0_II    max xi_eq (T0_I fam., T0_II/2 fam., all branches)")
    m = tf.maxima
    for n in fe_ns:
        r = {m["family"][i]: i for i in range(len(m["n"])) if m["n"][i] == n}
        print(f"  {n:3d}  {FE_GRID[n][0]}x{FE_GRID[n][1]}  {m['T0_I'][r['all']]:.5f}  {m['T0_II'][r['all']]:.5f}  "
              + "  ".join(f"{m['xi_max'][r[f]]:.4f}" if np.isfinite(m["xi_max"][r[f]]) else "  -   "
                          for f in ("T0_I", "T0_II/2", "all")))
    print("observed convergence rates (vs finest N):", json.dumps(tf.rates["fe-P1-lumped"]["all"]))
