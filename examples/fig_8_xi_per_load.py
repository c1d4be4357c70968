"""Fig. 8: xi_eq along path 1 and path 2 for a unit force on DOF 1, 2, 3, 4.

Usage: python fig_8_xi_per_load.py [OUT_DIR]   (default ./plbar-figures; PNG and PDF)
Environment: PLBAR_GRID="N1,N2" scan grid (default 200,200).
"""
import os
import sys

from plbar.studies.paper import figures as plots

GRID = tuple(int(v) for v in os.environ.get("PLBAR_GRID", "200,200").split(","))

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "plbar-figures"
    for f in plots.fig8_xi_per_load(out, grid=GRID):
        print(f)
