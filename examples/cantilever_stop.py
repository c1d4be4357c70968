"""A cantilever against a tip stop with a clearance: xi_eq of the real motion over (T, A / gap) (issue 41).

The classic impacting structure of the experiments (Moon & Shaw 1983, Wagg & Bishop 2002): an Euler-Bernoulli
cantilever (EI = rhoA = L = 1, 6 Hermite elements, a tip mass 0.5), a stop a clearance ``d = 0.05`` from its tip,
a harmonic force ``A cos(2 pi t / T)`` at mid-span.  For every forcing period around the fundamental free one
(``2 pi / 2.016 = 3.12``) and every amplitude over the gap ``A / d`` in 1 .. 64, the motion from rest
(400 periods, the last 40 characterise it) and its ``xi_eq`` (Eq. 22 on the motion): the amplitude study of
``plbar survey --model beam ... --amplitudes``, from Python.  With a
gap the answer depends on ``A / d`` (FORMULATION §9, homogeneity), the curve engineers work with.

Prints, per ``A / d``: how many motions reach the stop, the median and largest ``xi_eq``; draws the
``(T, A / d)`` map: ``cantilever_stop.png``.  ``tests/model/test_beam.py`` checks the beam against its closed forms
and the test's integrator; ``tests/test_examples.py`` runs this script (``--quick``: fewer cells).

Run::

    python examples/cantilever_stop.py [output folder] [--quick]    # default ./plbar-examples/cantilever_stop
"""

import sys
from pathlib import Path

import numpy as np

import plbar
from plbar.studies.survey import AMPLITUDES, survey_loads

QUICK = "--quick" in sys.argv
ARGS = [a for a in sys.argv[1:] if not a.startswith("--")]
OUT = Path(ARGS[0] if ARGS else "plbar-examples/cantilever_stop")
GAP = 0.05
RATIOS = np.array([1.0, 4.0, 16.0]) if QUICK else 2.0 ** np.arange(0, 7)
T = np.linspace(2.0, 5.0, 7 if QUICK else 61)
PERIODS, RECORD = (200, 20) if QUICK else (400, 40)

# the force at mid-span has the amplitude A = (A / d) d: a unit factor on a force of amplitude d
case = plbar.Case(model="beam", n=6, end_mass=0.5, end_mass_absolute=True, gap=GAP, load_points=((0.5, GAP),))
study = survey_loads(case, T, RATIOS, periods=PERIODS, record=RECORD, axis=AMPLITUDES)
XI = study.grid("xi_eq")                                   # (amplitudes, forcing periods)
HIT = study.grid("impacts_per_T") > 0


def main() -> None:
    print(f"cantilever (6 Hermite elements, tip mass 0.5) against a tip stop at d = {GAP:g}; force at mid-span")
    for ratio, xi, hit in zip(RATIOS, XI, HIT):
        print(f"  A / d = {ratio:5g}: {int(hit.sum()):3d} of {T.size} motions reach the stop; xi_eq median "
              f"{np.nanmedian(xi):.4g}, largest {np.nanmax(xi):.4g}")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:                       # the plot extra is optional
        return
    OUT.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(8.0, 4.0))
    edges = np.concatenate([[T[0] - (T[1] - T[0]) / 2], (T[1:] + T[:-1]) / 2, [T[-1] + (T[-1] - T[-2]) / 2]])
    redges = np.concatenate([[RATIOS[0] / np.sqrt(2)], np.sqrt(RATIOS[1:] * RATIOS[:-1]), [RATIOS[-1] * np.sqrt(2)]])
    mesh = ax.pcolormesh(edges, redges, XI, cmap="viridis", shading="flat")
    fig.colorbar(mesh, ax=ax, label=r"$\xi_{eq}$ of the motion from rest (Eq. 22)")
    ax.set_yscale("log")
    ax.set_xlabel("forcing period T (EI = rhoA = L = 1)")
    ax.set_ylabel("force amplitude over the gap, A / d")
    ax.set_title("a cantilever against a tip stop with a clearance")
    fig.tight_layout()
    fig.savefig(OUT / "cantilever_stop.png", dpi=150)
    print(f"wrote {OUT / 'cantilever_stop.png'}")


if __name__ == "__main__":
    main()
