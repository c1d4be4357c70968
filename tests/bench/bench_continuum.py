"""The continuum march at compiled speed (issue 29): side by side with the FE survey simulator, in one process.

Usage (not a test; about 2-4 minutes on 2 cores)::

    python tests/bench/bench_continuum.py [--periods 50 100 200 300 1000] [--no-cold]

Times, for T = 2.5 L/c (n = 32 steps per L/c, end mass 0.5, load at s = 0.37, from rest):

* ``march``: the compiled march alone (:func:`plbar.continuum.stepper.march`, merged pieces);
* ``simulate``: the whole :func:`plbar.continuum.simulate` (march and the accounts: work, bar energy at every
  period boundary, ``int int rhoA v^2`` over the last 10 periods, grid states);
* ``fe64``: :func:`plbar.motion.run` on ``Case(model="fe", n=64, end_mass=0.5, end_mass_absolute=True,
  load_points=((0.37, 1.0),)).problem()``, one forcing period, the same periods (record 10);

each after a warm-up call (compiled code loaded), best of ``--rounds``.  Unless ``--no-cold``, the first call of a
fresh install (an empty numba cache: the continuum kernels compile) is measured in a subprocess.  Prints the
pure-Python march before the kernel (docs/continuum.md, 2026-11-26, 2 busy cores) as the baseline, and the
1,000-period run's accounts against that run's.  Writes ``tests/bench/results_continuum_speed.txt``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).parent
ROOT = HERE.parents[1]

#: the pure-Python march (every breakpoint kept): march alone, and its 1,000-period run in all (simulate)
BASELINE_MARCH = {50: 3.2, 100: 7.6, 200: 28.0}
BASELINE_SIMULATE = {1000: 1082.0}
OLD_1000 = {"impacts": 5251, "loss": 242.67, "work": 247.39, "xi_omega": 0.00524, "residual": 3.7e-12}

COLD = r'''
import time
t = time.perf_counter()
import plbar.continuum as pc
t1 = time.perf_counter()
pc.simulate(pc.ContinuumBar(), 2.5, periods=2, steps_per_L=8)
print(t1 - t, time.perf_counter() - t1)
'''


def _best(f, rounds):
    best, out = float("inf"), None
    for _ in range(rounds):
        t = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t)
    return best, out


def _cold() -> list[str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    lines = []
    with tempfile.TemporaryDirectory() as d:
        env["NUMBA_CACHE_DIR"] = d
        for what in ("cold (empty numba cache: compiles)", "warm (cache filled)"):
            out = subprocess.run([sys.executable, "-c", COLD], env=env, capture_output=True, text=True, check=True)
            imp, first = map(float, out.stdout.split())
            lines.append(f"first simulate call, {what}: {first:.1f} s (import {imp:.1f} s)")
    return lines


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--periods", type=int, nargs="+", default=[50, 100, 200, 300, 1000])
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--no-cold", action="store_true")
    a = ap.parse_args(argv)

    import numpy as np

    import plbar
    import plbar.continuum as pc
    from plbar.continuum.stepper import march
    from plbar.motion import run

    T, n = 2.5, 32
    case = plbar.Case(model="fe", n=64, end_mass=0.5, end_mass_absolute=True, load_points=((0.37, 1.0),))
    bar, prob = pc.from_case(case), case.problem()
    lines = [f"plbar.continuum speed (issue 29), {time.strftime('%Y-%m-%d %H:%M')}, {os.cpu_count()} cores, "
             f"load average before {os.getloadavg()[0]:.2f} (2 cores: above ~1 is a busy machine)",
             f"T = {T}, n = {n}, m_e = {bar.end_mass}, s = {bar.s}; FE: P1 lumped N = 64, plbar.motion.run, one T",
             ""]
    if not a.no_cold:
        lines += _cold() + [""]
    march(bar, T, 2, n, 0.0, None, None)
    pc.simulate(bar, T, periods=2, steps_per_L=n)
    run(prob, [T], periods=2, record=1)
    lines.append(f"{'periods':>8} {'march s':>9} {'pieces':>9} {'simulate s':>11} {'fe64 s':>8} {'sim/fe64':>9} "
                 f"{'old s':>8} {'speed-up':>9}")
    last = None
    for P in a.periods:
        tm, mc = _best(lambda P=P: march(bar, T, P, n, 0.0, None, None), a.rounds)
        ts, r = _best(lambda P=P: pc.simulate(bar, T, periods=P, steps_per_L=n, record=min(P, 10)), a.rounds)
        tf, _ = _best(lambda P=P: run(prob, [T], periods=P, record=10), a.rounds)
        if P in BASELINE_MARCH:
            cmp = f"{BASELINE_MARCH[P]:>8.1f} {BASELINE_MARCH[P] / tm:>8.0f}x (march)"
        elif P in BASELINE_SIMULATE:
            cmp = f"{BASELINE_SIMULATE[P]:>8.0f} {BASELINE_SIMULATE[P] / ts:>8.0f}x (simulate)"
        else:
            cmp = ""
        lines.append(f"{P:>8} {tm:>9.3f} {mc.line['t0'].size:>9} {ts:>11.3f} {tf:>8.3f} {ts / tf:>9.2f} {cmp}")
        last = (P, r)
    lines.append("old pure-Python march (every breakpoint kept; 2 busy cores, docs/continuum.md): march alone "
                 + ", ".join(f"{k} periods {v:g} s" for k, v in BASELINE_MARCH.items())
                 + "; simulate in all " + ", ".join(f"{k} periods {v:g} s" for k, v in BASELINE_SIMULATE.items()))
    lines.append(f"load average after {os.getloadavg()[0]:.2f}")
    if last and last[0] == 1000:
        r = last[1]
        R = r.record
        lines += ["", "1,000 periods (record 10), new vs the pure-Python run:",
                  f"  impacts   {r.impacts.sum():>10d}   old {OLD_1000['impacts']}",
                  f"  loss      {r.loss.sum():>10.2f}   old {OLD_1000['loss']}",
                  f"  work      {r.work.sum():>10.2f}   old {OLD_1000['work']}",
                  f"  xi_omega  {r.xi_omega:>10.5f}   old {OLD_1000['xi_omega']} (last {R} periods)",
                  f"  residual  {r.energy_residual:>10.2e}   old {OLD_1000['residual']:.1e}",
                  f"  loss per period over the last 500: {r.loss[-500:].mean():.5f}, the first 500: "
                  f"{r.loss[:500].mean():.5f}; impacts per period last 500: {r.impacts[-500:].mean():.3f}"]
    text = "\n".join(lines) + "\n"
    print(text)
    (HERE / "results_continuum_speed.txt").write_text(text)
    np.seterr(all="ignore")


if __name__ == "__main__":
    main()
