"""A bar with a breathing crack: what its impacts dissipate, and why a crack at a free part never settles (issue 41).

A uniform bar (EA = rhoA = L = 1, P1, lumped mass) with a crack at mid-length, ``plbar.Case(model="fe",
crack_at=0.5)``: the crack's two faces are two nodes at ``x = 0.5`` that close in compression and open in tension,
and the contact is their relative displacement (docs/crack.md).

* **Between two clamps** (``supports="clamped-clamped"``), a unit force at ``x = 0.25`` and a little stiffness-
  proportional damping (Rayleigh beta = 0.005): the motion from rest at each forcing period (600 periods, the last
  100 recorded), its xi_eq (Eq. (22) for the motion, FORMULATION §8) on three meshes, N = 16, 32, 64 (``--quick``:
  N = 16, 32, 8 forcing periods, 300 periods each).  The faces
  carry no mass of their own, so the plastic impact between them loses only their nodes' shares of the element
  mass: xi_eq halves with the element size (the continuum's breathing crack dissipates nothing).
* **At a free end** (the default ``supports="clamped-free"``), a unit force at ``x = L``: the outer half floats
  while the crack is open (a rigid-body mode), every contact pushes it away and no force brings it back on average,
  so no periodic motion has a contact (:func:`plbar.model.modes.floats`); from rest the crack opens for good, its
  opening grows linearly over the periods.

Prints the medians of xi_eq per mesh and their ratios, the floating part's last contact and its drift; draws
``cracked_bar.png``.  ``tests/model/test_crack.py`` checks the crack against assemblies and an integrator written in
the test; ``tests/test_examples.py`` runs this script (``--quick``: fewer forcing periods).

Run::

    python examples/cracked_bar.py [output folder] [--quick]
"""

import sys
from pathlib import Path

import numpy as np

import plbar
from plbar.motion import padded, run, steady

QUICK = "--quick" in sys.argv
ARGS = [a for a in sys.argv[1:] if not a.startswith("--")]
OUT = Path(ARGS[0] if ARGS else "plbar-examples/cracked_bar")
T = np.linspace(1.0, 8.0, 8 if QUICK else 57)
MESHES = (16, 32) if QUICK else (16, 32, 64)
PERIODS, RECORD = (300, 50) if QUICK else (600, 100)


def between_clamps(n: int):
    """``(kind, xi_eq)`` of the motions from rest of the crack between two clamps on ``n`` elements."""
    case = plbar.Case(model="fe", n=n, crack_at=0.5, supports="clamped-clamped", load_points=((0.25, 1.0),),
                      rayleigh=(0.0, 0.005))
    s = steady(run(padded(case.problem()), T, 0.0, PERIODS, RECORD))
    return s.kind, s.xi_eq


def floating(Ts=(1.5, 3.0, 6.0), periods: int = 40):
    """The floating crack from rest: per forcing period, the opening at the period boundaries and the events."""
    case = plbar.Case(model="fe", n=16, crack_at=0.5, load_points=((1.0, 1.0),))
    r = run(padded(case.problem()), np.array(Ts), 0.0, periods, periods)
    opening = -r.strobe_x[..., -1]                 # the contact coordinate u = u_inner - u_outer is the last one
    return np.array(Ts), opening, r.events


def main() -> None:
    xi = {}
    for n in MESHES:
        kind, xi[n] = between_clamps(n)
        print(f"crack between two clamps, N = {n:3d}: {int(np.sum(kind == 0))} of {T.size} motions periodic, "
              f"xi_eq median {np.median(xi[n]):.4g}, largest {xi[n].max():.4g}")
    for a, b in zip(MESHES[:-1], MESHES[1:]):
        print(f"  median xi_eq(N = {a}) / xi_eq(N = {b}) = {np.median(xi[a] / xi[b]):.3f} (O(h): 2)")
    Ts, opening, ev = floating()
    for b, Tb in enumerate(Ts):
        last = ev["time"][ev["traj"] == b].max()
        drift = (opening[b, -1] - opening[b, -11]) / (10 * Tb)
        print(f"floating crack, T = {Tb:g}: last contact at t = {last:.4g} (period {last / Tb:.2f} of "
              f"{opening.shape[1] - 1}); the opening then grows by {drift:.4g} per unit time")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:                       # the plot extra is optional
        return
    OUT.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(1, 2, figsize=(11.0, 4.0))
    for n in MESHES:
        ax[0].semilogy(T, xi[n], "o-", ms=3, lw=1, label=f"N = {n}")
    ax[0].set_xlabel("forcing period T (L = c = 1)")
    ax[0].set_ylabel(r"$\xi_{eq}$ of the motion from rest")
    ax[0].set_title("a crack between two clamps: the loss is the mesh's, O(h)")
    ax[0].legend()
    for b, Tb in enumerate(Ts):
        ax[1].plot(np.arange(opening.shape[1]), opening[b], label=f"T = {Tb:g}")
    ax[1].set_xlabel("forcing periods from rest")
    ax[1].set_ylabel("the crack's opening at the period's start")
    ax[1].set_title("a crack at a free part: it opens for good")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig(OUT / "cracked_bar.png", dpi=150)
    print(f"wrote {OUT / 'cracked_bar.png'}")


if __name__ == "__main__":
    main()
