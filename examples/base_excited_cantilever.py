"""A base-excited cantilever against a tip stop: what the support's shaking does, over (T, a_g / d) (issue 41).

The experimenters' set-up and the earthquake engineer's load: an Euler-Bernoulli cantilever (EI = rhoA = L = 1,
6 Hermite elements, a tip mass 0.5) on a shaking support, its tip a clearance ``d = 0.05`` from a stop fixed to
the support.  The support accelerates as ``a_g cos(2 pi t / T)``; in coordinates relative to the support the load is
``-M t a_g cos(2 pi t / T)`` (docs/base.md).  For forcing periods around the fundamental free one and support
accelerations ``a_g / d`` in 1 .. 64: the motion from rest (400 periods), its ``xi_eq`` and the tip's largest
excursion per period (the survey's ``amp_c_max``) relative to the support: the amplitude study of
``plbar survey --model beam --base 0.05 --gap 0.05 --end-mass 0.5 --end-mass-absolute --amplitudes ...``.

Prints, per ``a_g / d``, how many motions reach the stop and the median and largest ``xi_eq``; draws both maps:
``base_excited_cantilever.png``.  ``tests/app/test_base_case.py`` checks the base excitation against the absolute
motion integrated in the test; ``tests/test_examples.py`` runs this script (``--quick``: fewer cells).

Run::

    python examples/base_excited_cantilever.py [output folder] [--quick]
"""

import sys
from pathlib import Path

import numpy as np

import plbar
from plbar.studies.survey import AMPLITUDES, survey_loads

QUICK = "--quick" in sys.argv
ARGS = [a for a in sys.argv[1:] if not a.startswith("--")]
OUT = Path(ARGS[0] if ARGS else "plbar-examples/base_excited_cantilever")
GAP = 0.05
RATIOS = np.array([1.0, 4.0, 16.0]) if QUICK else 2.0 ** np.arange(0, 7)
T = np.linspace(2.0, 5.0, 7 if QUICK else 61)
PERIODS, RECORD = (200, 20) if QUICK else (400, 40)

# the support's acceleration a_g = (a_g / d) d: a unit factor on a base acceleration of d
case = plbar.Case(model="beam", n=6, end_mass=0.5, end_mass_absolute=True, gap=GAP, base=GAP)
study = survey_loads(case, T, RATIOS, periods=PERIODS, record=RECORD, axis=AMPLITUDES)
XI = study.grid("xi_eq")                                   # (accelerations, forcing periods)
HIT = study.grid("impacts_per_T") > 0
AMP = study.grid("amp_c_max") / GAP                        # the tip's largest excursion over the gap


def main() -> None:
    print(f"base-excited cantilever (6 Hermite elements, tip mass 0.5), a tip stop at d = {GAP:g} on the support")
    for ratio, xi, hit in zip(RATIOS, XI, HIT):
        print(f"  a_g / d = {ratio:5g}: {int(hit.sum()):3d} of {T.size} motions reach the stop; xi_eq median "
              f"{np.nanmedian(xi):.4g}, largest {np.nanmax(xi):.4g}")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:                       # the plot extra is optional
        return
    OUT.mkdir(parents=True, exist_ok=True)
    edges = np.concatenate([[T[0] - (T[1] - T[0]) / 2], (T[1:] + T[:-1]) / 2, [T[-1] + (T[-1] - T[-2]) / 2]])
    redges = np.concatenate([[RATIOS[0] / np.sqrt(2)], np.sqrt(RATIOS[1:] * RATIOS[:-1]), [RATIOS[-1] * np.sqrt(2)]])
    fig, ax = plt.subplots(1, 2, figsize=(11.0, 4.0), sharey=True)
    for a, grid, label in ((ax[0], XI, r"$\xi_{eq}$ of the motion from rest (Eq. 22)"),
                           (ax[1], AMP, "the tip's largest excursion per period (amp_c_max) / d")):
        mesh = a.pcolormesh(edges, redges, grid, cmap="viridis", shading="flat")
        fig.colorbar(mesh, ax=a, label=label)
        a.set_yscale("log")
        a.set_xlabel("forcing period T (EI = rhoA = L = 1)")
    ax[0].set_ylabel("support acceleration over the gap, a_g / d")
    ax[0].set_title("a base-excited cantilever against a tip stop")
    fig.tight_layout()
    fig.savefig(OUT / "base_excited_cantilever.png", dpi=150)
    print(f"wrote {OUT / 'base_excited_cantilever.png'}")


if __name__ == "__main__":
    main()
