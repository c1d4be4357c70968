"""Load positions of the chain N = 5 (paper Sec. 4.2): where is xi_eq largest, and what is the worst load?

One path solve (unit force on DOF 1: any load with a contact response gives the same paths), then
xi_eq of a unit force at every position s in (0, 5] (50 per element, between nodes the paper's
linear split), the node pairs of Fig. 9 and the worst load distribution at every path point
(xi_worst = b^T G^+ b / 2; docs/load_structure.md).  Writes the study folder argv[1] (default
./plbar-load-sweep).  Environment: PLBAR_GRID="N1,N2" (default 200,200).
"""
import os
import sys

import numpy as np

import plbar
from plbar.studies.loads import sweep_loads

GRID = tuple(int(v) for v in os.environ.get("PLBAR_GRID", "200,200").split(","))

OUT = (sys.argv[1] if len(sys.argv) > 1 else "plbar-load-sweep") if __name__ == "__main__" else None
r = sweep_loads(plbar.Case(grid=GRID), OUT, per_element=50, plot=False)      # the one solve; files if run
lf, fam = r.forms, r.families
s = np.linspace(0.0, 5.0, 501)[1:]
xi = lf.xi_point(s)                                      # (path points, positions)
path2 = fam == "T0_II/2"
k, j = np.unravel_index(np.argmax(np.where(path2[:, None], xi, -1.0)), xi.shape)
worst = lf.worst()
w = int(np.argmax(np.where(path2, worst.xi, -1.0)))
best = {"s": float(s[j]), "xi": float(xi[k, j]), "T": float(lf.T[k])}

if __name__ == "__main__":
    files = r.files
    print(f"{len(lf)} path points from one solve (grid {GRID[0]}x{GRID[1]}), {s.size} positions")
    print(f"path 2 (near T0_II/2): max xi_eq of a single force = {best['xi']:.5f} at s = {best['s']:.2f} "
          f"(T = {best['T']:.4f})")
    print(f"path 2: worst load distribution xi_eq = {worst.xi[w]:.5f} at T = {lf.T[w]:.4f}, "
          f"shape q* = {np.round(worst.q[w], 3).tolist()}")
    for sj in (1.0, 2.0, 3.0, 4.0):
        print(f"   s = {sj:.1f}: max xi_eq on path 2 = {lf.xi_point([sj])[path2, 0].max():.5f}")
    print("wrote " + ", ".join(str(f) for f in files.values()))
