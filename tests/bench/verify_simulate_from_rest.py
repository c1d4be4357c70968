"""Issue 29 item 5: plbar.simulate from rest on FE P1 lumped, end mass 0.5, load at 0.37 L, T = 2.5 (L = c = 1).

Before the fix: N = 64 raised scipy's "f(a) and f(b) must have different signs", and N = 32 reported an opening at
t = 0.0112 and impacts at 0.0174 and 0.2448 that plbar.motion.run does not see.  This script prints
(1) plbar.simulate against plbar.motion.run over 20 periods at N = 32 and 64 (events and times);
(2) the independent evidence at N = 32 on the first state I segment: (a) scipy solve_ivp (DOP853, rtol 1e-13,
atol 1e-60) on the physical equations with the margin -R as event, and (b) the exact Taylor series of the motion
from rest in 250-digit decimals: the margin is positive until t = 1.26178 (its values at the old event times are
1e-66 ... 1e-13, far below the ~1e-17 noise of the modal sums).  solve_ivp's own crossings at t < 5e-9 are where
that margin (~ t^40) underflows double precision: signed zeros, no events.  Usage:
``python tests/bench/verify_simulate_from_rest.py`` (about 10 s).
"""

import numpy as np
from scipy.integrate import solve_ivp

import plbar
from plbar.check.simulate import simulate
from plbar.motion import run

T = 2.5
W = 2 * np.pi / T
for N in (32, 64):
    prob = plbar.Case(model="fe", n=N, element="P1", mass="lumped", end_mass=0.5, load_points=((0.37, 1.0),)).problem()
    n = prob.system.n
    s = simulate(prob, T, 0.0, np.zeros(n), np.zeros(n), state=1, n_periods=20)
    r = run(prob, [T], 0.0, periods=20, record=20)
    t, k = np.asarray(r.events["time"]), np.asarray(r.events["kind"])
    m = min(t.size, s.events["time"].size)
    dt = np.abs(t[:m] - s.events["time"][:m]).max()
    ts = s.events["time"]
    print(f"N = {N}: simulate {ts.size} events, motion {t.size}; first {np.round(ts[:3], 8)}; "
          f"same kinds {np.array_equal(k[:m], s.events['kind'][:m])}, max |dt| {dt:.2g}")

N = 32
case = plbar.Case(model="fe", n=N, element="P1", mass="lumped", end_mass=0.5, load_points=((0.37, 1.0),))
prob = case.problem(); M, K, q = prob.system.M, prob.system.K, prob.q
assert np.all(M[-1, :-1] == 0)
Mr, Kr, qr, Kc, qc = np.diag(M)[:-1], K[:-1, :-1], q[:-1], K[-1, :-1], q[-1]
n = Mr.size
def rhs(t, y):
    return np.concatenate([y[n:], (qr * np.cos(W * t) - Kr @ y[:n]) / Mr])
def margin(t, y):
    return -(Kc @ y[:n] - qc * np.cos(W * t))
margin.direction = -1
sol = solve_ivp(rhs, (0, 1.3), np.zeros(2 * n), method="DOP853", rtol=1e-13, atol=1e-60, events=margin,
                dense_output=True)
print("(a) solve_ivp: status", sol.status, "steps", sol.t.size, "events (gap opens):", sol.t_events[0])
for t in (0.011175, 0.017433, 0.079763, 0.244808, 0.6, 1.0, 1.2):
    print(f"    t = {t:<9g} margin -R = {margin(t, sol.sol(t)):.3e}")
from decimal import Decimal as D, getcontext  # noqa: E402
getcontext().prec = 250
A = [[-D(Kr[i, j]) / D(Mr[i]) for j in range(n)] for i in range(n)]
b = [D(qr[i]) / D(Mr[i]) for i in range(n)]
Wd = D(W)
terms = 700
a = [[D(0)] * n, [D(0)] * n]
cm = [D(1)]                      # cos(W t) = sum cm[m] t^m
for m in range(1, terms + 2):
    cm.append(D(0) if m % 2 else -cm[m - 2] * Wd * Wd / (m * (m - 1)))
for m in range(terms):
    am = a[m]
    a.append([(sum(A[i][j] * am[j] for j in range(max(0, i - 1), min(n, i + 2))) + b[i] * cm[m]) / ((m + 1) * (m + 2))
              for i in range(n)])
g = [-sum(D(Kc[i]) * a[m][i] for i in range(n)) + D(qc) * cm[m] for m in range(terms)]
def dmargin(t):
    t = D(t); s = D(0); p = D(1)
    for m in range(terms):
        s += g[m] * p; p *= t
    return s
grid = np.linspace(0.0, 1.26, 253)[1:]
vals = [dmargin(t) for t in grid]
neg = [t for t, v in zip(grid, vals) if v < 0]
print(f"(b) exact Taylor series, 250 digits, {terms} terms: margin at {grid.size} times in (0, 1.26]: "
      f"min {min(vals):.4e}, negative at {len(neg)} of them")
for t in (0.011175, 0.017433, 0.079763, 0.244808, 0.6, 1.0, 1.2, 1.2617, 1.2619):
    print(f"    t = {t:<9g} margin -R = {dmargin(t):.4e}")
print("    last term at t = 1.26:", f"{g[terms - 1] * D(1.26) ** (terms - 1):.2e}")
