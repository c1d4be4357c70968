"""One periodic response at a given forcing period, from a guess, in a fraction of a millisecond.

``plbar.find_response(prob, T, T1_guess)`` finds the response at period ``T``
whose time in state I is nearest the guess: one batched evaluation of the
periodicity system at Chebyshev points around the guess, the exact phase, the
state, the switch residuals recomputed from the flow, the periodicity defect
after one period with the impact, ``Delta_PL`` and ``xi_eq`` (Eq. (22)).

Here the guess comes from the paper's green point (Fig. 5); the response is
then checked independently: admissibility by dense sampling and one period of
the event-driven simulator (``plbar.simulate``) from the returned state.

Run:  python examples/one_response.py
"""

import time

import numpy as np

import plbar
from plbar.response import check
from plbar.check import period_map

prob = plbar.Case().problem()                      # the paper's chain, N = 5, unit force on DOF 1
T1g, T2g = 2.3876, 9.8894                          # the green point, read off the paper's Fig. 5
T = T1g + T2g

r = plbar.find_response(prob, T, T1g)
n = 200
t0 = time.perf_counter()
for _ in range(n):
    plbar.find_response(prob, T, T1g)
dt = (time.perf_counter() - t0) / n

print(f"T = {T:.6f}: T1 = {r.T1:.10f}, T2 = {r.T2:.10f}, phi = {r.phi:.10f}")
print(f"  xi_eq = {r.xi:.6f}, Delta_PL = {r.dPL:.6f}, impact velocity v_c = {r.v_impact:.6f}")
print(f"  switch residuals (relative) e1 = {r.e1:.1e}, e2 = {r.e2:.1e}, periodicity defect {r.periodicity:.1e}")
print(f"  {r.evaluations} evaluations of the periodicity system, {dt * 1e6:.0f} us per call")

# independent checks
adm = check(r.orbit)
print(f"  admissible (no premature switch on (0, T)): {bool(adm.ok[0])}")
xr, vr = r.x0[:-1], r.xdot0[:-1]
x1, v1 = period_map(prob, T, r.phi, xr, vr)
err = np.abs(np.r_[x1 - xr, v1 - vr]).max() / np.abs(np.r_[xr, vr]).max()
print(f"  event-driven simulator, one period from the returned state: back to it within {err:.1e}")
