"""The real motion at compiled speed (issue 27): this checkout against another, side by side, ratios printed.

Usage (not a test; about 10 minutes on 2 cores, most of it the old checkout)::

    git worktree add --detach /tmp/plbar-old 6efc4a3      # main before the compiled kernel
    python tests/bench/bench_motion.py /tmp/plbar-old [--quick] [--rounds R] [--no-cold]

Each measurement runs in a fresh process with one checkout on ``PYTHONPATH`` (old and new alternate, ``R``
rounds, the best kept), after a warm-up call in that process: what a user sees from the second call of a
session on.  The work, as the issue's table lists it:

* ``one_T``: ``plbar.studies.survey.survey(Case(), T=[12.277])`` (one forcing period, 1,000 periods from rest,
  in this process, its periodic motion polished);
* ``survey``: the default survey, 161 forcing periods in [6, 14] x 1,000 periods
  (``run_survey`` with the local executor on every core, no figure);
* ``fe64``, ``fe256``: FE P1 lumped, N = 64 / 256, end mass 0.5, 50 forcing periods with T/L in [1.5, 4.5]
  x 1,000 periods (the same; ``fe256`` with this checkout only, unless ``--fe256-old``);
* ``run_every``: ``plbar run --no-plot`` on the default case with every signature (old: ``--signatures default``,
  new: the default), a whole command;
* ``run_paper``: ``plbar run --no-plot`` with the paper's class only (old: the default, new:
  ``--signatures paper``).

``--quick`` skips ``fe64``, ``fe256`` and the old ``run_every``.  Unless ``--no-cold``, the cold start is
measured too (an empty numba cache: the first ``plbar run`` and the first survey of a fresh install).
Writes ``tests/bench/results_motion.json``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).parent
NEW = HERE.parents[1]

WORK = r'''
import json, sys, tempfile, time
import numpy as np
import plbar
from plbar.studies import get_executor
from plbar.studies.survey import run_survey, survey

what = sys.argv[1]

def fe(n):
    return plbar.Case(model="fe", n=n, element="P1", mass="lumped", end_mass=0.5)

def one():
    s = survey(plbar.Case(), T=[12.277])
    return {"loss_per_T": float(s.table["loss_per_T"][0]), "kind": str(s.table["kind"][0])}

def surv(case, T):
    def go():
        with tempfile.TemporaryDirectory() as d, get_executor("local") as ex:
            s = run_survey(case, T, 1000, 100, d, executor=ex, plot=False)
        kinds = {k: int(np.sum(s.table["kind"] == k)) for k in ("periodic", "irregular", "failed")}
        return {"kinds": kinds, "energy_residual": float(np.max(np.abs(s.table["energy_residual"])))}
    return go

T0 = {"one_T": one, "survey": surv(plbar.Case(), np.linspace(6, 14, 161))}
if what in ("fe64", "fe256"):
    n = int(what[2:])
    T0[what] = surv(fe(n), np.linspace(1.5, 4.5, 50))          # T / L (L = c = 1: T0_I = 2)
job = T0[what]
warm = sys.argv[2] == "warm"
if warm:
    one()                              # the first call of a session: imports, the compiled kernel loaded
t = time.perf_counter()
out = job()
out["seconds"] = time.perf_counter() - t
print(json.dumps(out))
'''


def _env(path: Path, cache: str | None = None) -> dict:
    env = dict(os.environ, PYTHONPATH=str(path), MPLBACKEND="agg")
    if cache:
        env["NUMBA_CACHE_DIR"] = cache
    return env


def work(path: Path, what: str, warm: bool = True, cache: str | None = None) -> dict:
    out = subprocess.run([sys.executable, "-c", WORK, what, "warm" if warm else "cold"], capture_output=True,
                         text=True, env=_env(path, cache), cwd=tempfile.gettempdir())
    if out.returncode:
        raise RuntimeError(out.stderr[-2000:])
    return json.loads(out.stdout.strip().splitlines()[-1])


def command(path: Path, args: list[str], cache: str | None = None) -> float:
    with tempfile.TemporaryDirectory() as d:
        t = time.perf_counter()
        out = subprocess.run([sys.executable, "-m", "plbar", *args, "--out", str(Path(d) / "out"), "--quiet"],
                             capture_output=True, text=True, env=_env(path, cache), cwd=d)
        if out.returncode:
            raise RuntimeError(out.stderr[-2000:])
        return time.perf_counter() - t


def best(f, rounds: int) -> float:
    return min(f() for _ in range(rounds))


def main(argv) -> None:
    old = Path(argv[0]).resolve()
    before = os.getloadavg()[0]                  # the machine's own load (at the end the benchmark's is in it)
    quick, no_cold = "--quick" in argv, "--no-cold" in argv
    rounds = int(argv[argv.index("--rounds") + 1]) if "--rounds" in argv else 3
    items = ["one_T", "survey"] + ([] if quick else ["fe64", "fe256"])
    rows = {}
    for what in items:
        slow_old = what in ("fe64", "fe256")
        r_new = rounds if what != "fe256" else 1
        r_old = 1 if slow_old else rounds
        new_s, old_s, info = [], [], {}
        for i in range(max(r_new, r_old)):
            if i < r_old and (what != "fe256" or "--fe256-old" in argv):
                d = work(old, what)
                old_s.append(d.pop("seconds"))
                info["old"] = d
            if i < r_new:
                d = work(NEW, what)
                new_s.append(d.pop("seconds"))
                info["new"] = d
        rows[what] = {"old_s": min(old_s) if old_s else None, "new_s": min(new_s), **info}
        print(what, json.dumps(rows[what]), flush=True)
    runs = (("run_every", ["run", "--no-plot", "--signatures", "default"], ["run", "--no-plot"]),
            ("run_paper", ["run", "--no-plot"], ["run", "--no-plot", "--signatures", "paper"]))
    command(NEW, runs[0][2])                     # the numba cache warm for the commands (a fresh install pays once)
    for what, a_old, a_new in runs:
        o = None if (quick and what == "run_every") else best(lambda a_old=a_old: command(old, a_old),
                                                              1 if what == "run_every" else rounds)
        n = best(lambda a_new=a_new: command(NEW, a_new), rounds)
        rows[what] = {"old_s": o, "new_s": n}
        print(what, json.dumps(rows[what]), flush=True)
    if not no_cold:
        with tempfile.TemporaryDirectory() as c1, tempfile.TemporaryDirectory() as c2:
            rows["cold_run"] = {"new_s": command(NEW, ["run", "--no-plot"], cache=c1),
                                "then_s": command(NEW, ["run", "--no-plot"], cache=c1)}
            rows["cold_one_T"] = {"new_s": work(NEW, "one_T", warm=False, cache=c2)["seconds"],
                                  "then_s": work(NEW, "one_T", warm=False, cache=c2)["seconds"]}
        print("cold", json.dumps({k: rows[k] for k in ("cold_run", "cold_one_T")}), flush=True)
    load = os.getloadavg()[0]
    print(f"\n2 cores, load average {before:.2f} before ({'idle' if before < 0.5 else 'busy'}), {load:.2f} at the end "
          "(with the benchmark's own)\n")
    print("| work | old (6efc4a3) | new | old / new |\n|---|---|---|---|")
    for k, r in rows.items():
        o, n = r.get("old_s"), r["new_s"]
        ratio = f"{o / n:.0f}x" if o else "-"
        print(f"| {k} | {'%.3g s' % o if o else 'not run'} | {n:.3g} s | {ratio} |")
    rows["load_average"] = load
    rows["load_average_before"] = before
    (HERE / "results_motion.json").write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
