"""The continuum bar against the FE survey simulator (P1 lumped, N elements): impact times of the first periods.

Run: PYTHONPATH=. python tests/bench/continuum_vs_fe.py
"""

import time

import numpy as np

import plbar
import plbar.continuum as pc
from plbar.motion import run


def main(T=2.5, periods=6, Ns=(64, 128, 256, 512)):
    bar = pc.ContinuumBar(end_mass=0.5, s=0.37)
    cr = pc.simulate(bar, T, periods=periods, steps_per_L=256)
    tc = cr.events["time"][cr.events["kind"] == 2]
    print("continuum impacts:", np.array2string(tc, precision=8))
    for N in Ns:
        case = plbar.Case(model="fe", n=N, end_mass=0.5, end_mass_absolute=True, load_points=((0.37, 1.0),),
                          signatures="paper")
        t0 = time.perf_counter()
        r = run(case.problem(), np.array([T]), periods=periods, record=periods)
        ti = r.events["time"][r.events["kind"] == 2]
        print(f"N = {N}: {time.perf_counter() - t0:.1f} s, impacts:", np.array2string(ti, precision=8))
        m = min(3, ti.size, tc.size)
        print(f"   first impacts minus continuum: {np.array2string(ti[:m] - tc[:m], precision=3)}")


if __name__ == "__main__":
    main()
