"""COCO's impact oscillator in plbar: a structure of one DOF with a gap and a coefficient of restitution.

The forced oscillator of COCO's ``hspo`` demo ``impact`` (Recipes for Continuation, Example 15.2):
``x'' + 0.1 x' + x = cos(w t)``, a stop at ``x = 1``, Newton's law with ``e = 0.8``.  plbar poses it as a
structure of one DOF (``M = K = 1``, ``C = 0.1``, the contact on that DOF, ``gap = 1``, ``restitution = 0.8``),
finds the demo's orbit of one impact per period at ``w = 1`` in closed form (class ``1R``), its Floquet
multipliers, and follows the whole branch over the forcing period ``T`` (from ``T0 / 4`` to ``T0 = 2 pi``).

Prints the orbit (period, impact velocity, the forcing's phase at the impact, multipliers), the branch's range and
its stable stretch; draws the impact velocity along the branch (stable solid, unstable dashed), the demo's orbit
marked: ``impact_oscillator.png``.  ``tests/periodic/test_peer_coco_impact.py`` checks the orbit against an
integrator written in the test; ``tests/test_examples.py`` runs this script.

Run::

    python examples/impact_oscillator.py [output folder]      # default ./plbar-examples/impact_oscillator
"""

import sys
from pathlib import Path

import numpy as np

import plbar
from plbar.periodic import ONE_REBOUND, admissible, find_branches, monodromy, multipliers, zero_dwell

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else "plbar-examples/impact_oscillator")
K, C, A, D, E = 1.0, 0.1, 1.0, 1.0, 0.8

structure = plbar.Structure(M=np.eye(1), K=K * np.eye(1), contact=[1.0], q=[A], rayleigh=(C, 0.0), restitution=E,
                            gap=D)
prob = plbar.problem(structure)
T = 2 * np.pi
orbits = zero_dwell(prob, T, ONE_REBOUND)
orbit = next(o for o, ok in zip(orbits, admissible(orbits)) if ok)
mu = multipliers(monodromy(prob, orbit.sig, orbit.T, orbit.phi, orbit.chain))
branches = find_branches(prob, (T / 4, T))


def main() -> None:
    print(f"COCO's orbit at w = 1: period {orbit.T:.6f}, impact velocity {orbit.v_impact[0]:.6f} "
          f"(after it {-E * orbit.v_impact[0]:.6f}), forcing phase at the impact {np.mod(-orbit.phi, 2 * np.pi):.6f}")
    verdict = "stable" if abs(mu).max() < 1 else "unstable"
    print(f"  multipliers {mu[0]:.5f}, {mu[1]:.5f}: |mu| = {abs(mu[0]):.5f} ({verdict})")
    print(f"  impact loss per period {orbit.loss_per_T:.6f}, damper's {orbit.viscous:.6f}, xi_eq {orbit.xi:.5f}")

    for b in branches:
        st = b.T[b.stable]
        print(f"branch {b.id} {b.sig}: {len(b)} points, T in [{b.T.min():.4f}, {b.T.max():.4f}], "
              f"{int(b.stable.sum())} stable" + (f" (T in [{st.min():.4f}, {st.max():.4f}])" if st.size else ""))

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:                       # the plot extra is optional
        return
    OUT.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7.0, 4.0))
    for b in branches:
        v = np.array([o.v_impact[0] for o in b.orbits])
        for stable, style in ((True, "-"), (False, "--")):
            ax.plot(b.T, np.where(b.stable == stable, v, np.nan), style, color="tab:blue",
                    label=f"{b.sig}, {'stable' if stable else 'unstable'}")
    ax.plot([orbit.T], [orbit.v_impact[0]], "o", color="k", label="COCO's demo orbit (w = 1)")
    ax.set_xlabel("forcing period T = 2 pi / w")
    ax.set_ylabel("impact velocity")
    ax.set_title("x'' + 0.1 x' + x = cos(w t), stop at x = 1, e = 0.8")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(OUT / "impact_oscillator.png", dpi=150)
    print(f"wrote {OUT / 'impact_oscillator.png'}")


if __name__ == "__main__":
    main()
