"""xi_eq of the impact against T with inherent Rayleigh damping 0, 1, 2 and 5 % (issue 21).

Two cases: the paper's chain (ratios at T = 8 and 12) and an FE bar, P1 lumped, N = 8, with an
end mass of half the bar's mass (ratios at T = 2 and 4).  Prints, per ratio, the largest xi_eq of
the impact, where, and the total equivalent ratio there (the Rayleigh ratio at that forcing
frequency plus xi_eq), and draws both panels into one figure (PNG and PDF).

Usage: python inherent_damping.py [OUT_DIR]   (default ./plbar-figures)
Environment: PLBAR_GRID="N1,N2" scan grid (default 200,200).
"""
import os
import sys

import plbar
from plbar.studies import ratio_table, with_rayleigh

GRID = tuple(int(v) for v in os.environ.get("PLBAR_GRID", "200,200").split(","))
CASES = {
    "chain N = 5 (the paper), unit force on DOF 1": (plbar.Case(grid=GRID), (8.0, 12.0)),
    "FE P1 lumped N = 8, end mass 0.5, force at L/2": (plbar.Case(model="fe", n=8, element="P1", mass="lumped",
                                                                  end_mass=0.5, grid=GRID), (2.0, 4.0)),
}

runs = {title: with_rayleigh(case, at=at) for title, (case, at) in CASES.items()}
tables = {title: ratio_table(r) for title, r in runs.items()}

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "plbar-figures"
    os.makedirs(out, exist_ok=True)
    for title, rows in tables.items():
        print(title)
        print("  ratio  points  branches  max xi_eq  at T      zeta(W) + xi_eq there  mean xi_eq")
        for r in rows:
            print(f"  {100 * r['ratio']:4.1f} %  {r['points']:6d}  {r['branches']:8d}  {r['xi_max']:.5f}    "
                  f"{r['T_at_max']:8.4f}  {r['xi_total_at_max']:.5f}                {r['xi_mean']:.5f}")
    from plbar.visuals import xi_rayleigh_plot
    from plbar.visuals.style import unit_note

    units = {title: unit_note(case.bar()) for title, (case, _) in CASES.items()}
    for f in xi_rayleigh_plot(list(runs.items()), out, "xi_rayleigh", units=units):
        print(f)
