"""Fig. 3: every DOF over two periods at the paths' points nearest to the paper's red and green points.

Usage: python fig_3_time_histories.py [OUT_DIR]   (default ./plbar-figures; PNG and PDF)
Environment: PLBAR_GRID="N1,N2" scan grid (default 200,200).
"""
import os
import sys

from plbar.studies.paper import figures as plots

GRID = tuple(int(v) for v in os.environ.get("PLBAR_GRID", "200,200").split(","))

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "plbar-figures"
    for f in plots.fig3_time_histories(out, grid=GRID):
        print(f)
