"""How well 1,000 periods of the continuum bar determine the loss: the march (events only) at n = 32 merged and
unmerged and at n = 48, 64 merged (m_e = 0.5, s = 0.37, T = 2.5, from rest).  Not a test; about a minute.

The motion is sensitive: a round-off-level change (the pure-Python march against the compiled unmerged one) moves
the 1,000-period loss by ~0.7 %, as do the merge and the grid; the loss per period over the last 500 periods
agrees to ~1 %, over the last 10 to ~20 %.  Prints one line per run.
"""
import time

import numpy as np

import plbar.continuum as pc
from plbar.continuum.stepper import march


def main(T=2.5, P=1000):
    bar = pc.ContinuumBar(end_mass=0.5, s=0.37)
    for n, mg in ((32, True), (32, False), (64, True), (48, True)):
        t = time.perf_counter()
        mc = march(bar, T, P, n, 0.0, None, None, merge=mg)
        e = mc.events
        imp = (e["kind"] == 2) & (e["time"] <= P * T)
        per = np.bincount(np.minimum((e["time"][imp] / T).astype(int), P - 1), e["loss"][imp], minlength=P)
        print(f"n={n} merge={mg}: {time.perf_counter() - t:.1f} s, pieces {mc.line['t0'].size}, impacts {imp.sum()}, "
              f"loss {per.sum():.3f}, loss/period first 500 {per[:500].mean():.5f} last 500 {per[500:].mean():.5f} "
              f"last 10 {per[-10:].mean():.5f}", flush=True)


if __name__ == "__main__":
    main()
