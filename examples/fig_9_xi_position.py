"""Fig. 9: xi_eq on the path near T0_II/2 against T and load position, chain N = 3..6.

Usage: python fig_9_xi_position.py [OUT_DIR]   (default ./plbar-figures; PNG and PDF)
Environment: PLBAR_GRID="N1,N2" scan grid (default 200,200).
"""
import os
import sys

from plbar.studies.paper import figures as plots

GRID = tuple(int(v) for v in os.environ.get("PLBAR_GRID", "200,200").split(","))

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "plbar-figures"
    for f in plots.fig9_xi_position(out, grid=GRID, per_element=int(os.environ.get('PLBAR_PER_ELEMENT', '4'))):
        print(f)
