"""Figs. 5-6: Delta_PL and xi_eq against T and phi; xi_eq along path 1 and path 2.

Usage: python fig_5_6_damping.py [OUT_DIR]   (default ./plbar-figures; PNG and PDF)
Environment: PLBAR_GRID="N1,N2" scan grid (default 200,200).
"""
import os
import sys

from plbar.studies.paper import figures as plots

GRID = tuple(int(v) for v in os.environ.get("PLBAR_GRID", "200,200").split(","))

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "plbar-figures"
    for f in plots.fig5_loss_damping(out, grid=GRID) + plots.fig6_damping_paths(out, grid=GRID):
        print(f)
