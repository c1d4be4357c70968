"""Every response of every signature that plbar run reports, checked independently (issue 20).

For the default case with ``--signatures default`` (or ``--fe``: FE P1 lumped N = 16, end mass 0.5, Rayleigh 1 %),
every point of every branch of another signature with T in the window [6, 14] (FE: [1.5, 3.9]):

* residuals recomputed from the flow (relative) <= 1e-12;
* the independent simulator (``plbar.simulate``, its own flow, sampling 20x denser than its default) started
  from the orbit's state meets the orbit's switches at the same times (1e-9 m T), nothing before m T, and
  returns to the start (1e-9 relative);
* the energy balance: work of the load = impact losses (+ viscous loss) (1e-9 of the energy exchanged).

Points with a segment shorter than a few samples (grazing) are beyond any sampled event search; they are
counted and checked by the certified replay (:func:`plbar.periodic.admissible`) instead.

    python tests/bench/verify_signatures.py [--fe]
"""

from __future__ import annotations

import sys
import time

import numpy as np

import plbar
import plbar.check.segments as seg
from plbar.check import simulate
from plbar.periodic import admissible, expected_events

PER_RAD = 50.0


def check(o) -> dict:
    prob = o.prob
    x0, v0 = o.start
    sim = simulate(prob, o.T, o.phi, x0, v0, state=1, n_periods=o.sig.m)
    et, ek = expected_events(o)
    span = o.sig.m * o.T
    n = et.size
    same = np.array_equal(sim.events["kind"][:n], ek) and bool(np.all(sim.events["time"][n:] >= span * (1 - 1e-9)))
    dt = float(np.max(np.abs(sim.events["time"][:n] - et)) / span) if sim.events["time"].size >= n else np.inf
    z = np.concatenate([sim.strobe_x[-1][:-1], sim.strobe_v[-1][:-1]])
    z0 = np.concatenate([x0[:-1], v0[:-1]])
    back = float(np.max(np.abs(z - z0)) / np.max(np.abs(z0)))
    scale = max(abs(sim.work), sim.energy0)
    balance = abs(sim.work - o.dPL - o.viscous) / scale
    return {"same": same, "dt": dt, "back": back, "balance": balance, "residual": o.residual}


def main(argv):
    fe = "--fe" in argv
    if fe:
        from plbar.model import rayleigh_from_ratio

        case = plbar.Case(model="fe", n=16, end_mass=0.5, rayleigh=rayleigh_from_ratio(0.01, 1.5, 4.5),
                          signatures="default")
        lo, hi = 1.5, 3.9
    else:
        case, lo, hi = plbar.Case(signatures="default"), 6.0, 14.0
    t0 = time.perf_counter()
    res = plbar.solve(case)
    others = [b for b in res.branches if not b.paper]
    print(f"solve ({case.signatures}): {time.perf_counter() - t0:.1f} s, "
          f"{len(others)} branches of other signatures")
    seg.SAMPLES_PER_RAD = PER_RAD
    rows, grazing = [], []
    for b in others:
        for o in b.orbits:
            if not lo <= o.T <= hi:
                continue
            if grazing_point(o):
                grazing.append(o)
                continue
            rows.append(check(o))
    ok = admissible(grazing) if grazing else np.zeros(0, bool)
    same = sum(r["same"] for r in rows)
    print(f"{len(rows)} points checked by the simulator: same switches {same}/{len(rows)}; max event time error "
          f"{max(r['dt'] for r in rows):.2e} m T; back to the start {max(r['back'] for r in rows):.2e}; energy "
          f"balance {max(r['balance'] for r in rows):.2e}; residuals <= {max(r['residual'] for r in rows):.2e}")
    print(f"{len(grazing)} grazing points (a segment shorter than a few samples): certified replay admits "
          f"{int(ok.sum())}/{len(grazing)}; residuals <= {max((o.residual for o in grazing), default=0):.2e}")


def grazing_point(o) -> bool:
    """Beyond a sampled event search: a segment shorter than a few samples, or an impact so slow (below 1e-3 of
    the orbit's velocity scale, its amplitude times the lowest frequency) that the gap's dip before it is
    shallower than the search sees."""
    w = max(float(o.prob.system.w2.max()), 2 * np.pi / o.T)
    short = min(d for d in o.durations if d > 0) * w * PER_RAD <= 4
    slow = o.v_impact.min() < 1e-3 * o.amplitude * float(o.prob.system.w2[0])
    return bool(short or slow)


if __name__ == "__main__":
    main(sys.argv[1:])
