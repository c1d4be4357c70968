"""Load-position sweep of the chain N = 5 (paper Sec. 4.2): where is xi_eq largest on path 2?

Solves the paper's chain for a unit point load at 49 positions s = 0.1, 0.2, ..., 4.9
(nodes included; between nodes the load is the paper's linear split), groups the branches
into families (plbar.families) and prints, on the family near T0_II/2 ("path 2"), the
position and value of the maximum xi_eq.  Resumable study folder: argv[1] (default
./plbar-load-sweep).  Environment: PLBAR_GRID="N1,N2" (default 200,200).
"""
import os
import sys

from plbar.studies import get_executor
from plbar.studies import run_study
from plbar.studies import load_sweep_study, sweep_tables, write_sweep_tables

GRID = tuple(int(v) for v in os.environ.get("PLBAR_GRID", "200,200").split(","))

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "plbar-load-sweep"
    study = load_sweep_study(n=5, grid=GRID, per_element=10)
    with get_executor("local") as ex:
        results = run_study(out, study, ex)
    tables = sweep_tables(study.tasks, results)
    write_sweep_tables(out, tables)
    mx = tables.maxima
    print(f"{len(study.tasks)} load positions in (0, 5), grid {GRID[0]}x{GRID[1]}")
    for fam in ("T0_I", "T0_II/2"):
        rows = [i for i, f in enumerate(mx["family"]) if f == fam]
        print(f"family {fam}: {len(rows)} positions, T in [{min(mx['T_min'][i] for i in rows):.4f}, "
              f"{max(mx['T_max'][i] for i in rows):.4f}], largest geometry deviation from s = "
              f"{mx['s1'][0]:g}: {max(mx['geom_dev'][i] for i in rows):.2e}")
    best = tables.summary["best"]["T0_II/2"]["single"]
    print(f"path 2 (near T0_II/2): max xi_eq = {best['xi_max']:.5f} at s = {best['s1']:g} "
          f"(T = {best['T_at_max']:.4f}, T1 = {best['T1_at_max']:.4f}, T2 = {best['T2_at_max']:.4f}, "
          f"phi = {best['phi_at_max']:.4f}, Delta_PL = {best['dPL_at_max']:.4f})")
    for i in [j for j, f in enumerate(mx["family"]) if f == "T0_II/2"][::5]:
        print(f"   s = {mx['s1'][i]:4.2f}: max xi_eq = {mx['xi_max'][i]:.5f}")
