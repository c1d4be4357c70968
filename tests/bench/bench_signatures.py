"""Wall time of ``plbar.solve(Case(signatures="default"))``: this checkout against others, interleaved.

Each run is a fresh process with one checkout on ``PYTHONPATH`` (its numba caches warm: run the script
once to fill them): it solves once (the first solve: imports and cache loads included), then ``--repeat``
times more, and reports the first and the best of the others, with the time of the hybrid part
(:func:`plbar.periodic.find_hybrid`), the seeding simulation and the paper's class.  The checkouts run in
turn, ``--rounds`` times, so a busy machine slows them alike; the best of all is reported, with the ratio
to the first checkout (the reference).

    python tests/bench/bench_signatures.py /path/to/base/checkout [--rounds 3] [--repeat 2] [--damping-ratio Z]


"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parents[2]

CHILD = r"""
import json, sys, time
import plbar
import plbar.app.signatures as AS
import plbar.app.run as R

parts = {}
def timed(mod, name, key):
    f = getattr(mod, name, None)
    if f is None:                     # not in this checkout
        return
    def g(*a, **k):
        t = time.perf_counter()
        try:
            return f(*a, **k)
        finally:
            parts[key] = parts.get(key, 0.0) + time.perf_counter() - t
    setattr(mod, name, g)
timed(AS, "find_hybrid", "hybrid")   # checkouts before the periodic core
timed(R, "find_branches", "hybrid")
timed(AS, "_seeding", "seeds")
timed(R, "find_paths", "paper")
kw = {}
if len(sys.argv) > 2:
    from plbar.model import rayleigh_from_ratio
    kw["rayleigh"] = rayleigh_from_ratio(float(sys.argv[2]), 6.0, 14.0)
out = []
for i in range(1 + int(sys.argv[1])):
    parts.clear()
    t = time.perf_counter()
    res = plbar.solve(plbar.Case(signatures="default", **kw))
    out.append(dict(parts, total=time.perf_counter() - t, branches=len(getattr(res, "hybrid", None) or
                                                                    [b for b in res.branches if not b.paper])))
print(json.dumps({"file": plbar.__file__, "runs": out}))
"""


def run_once(path: str, repeat: int, zeta: str | None) -> dict:
    env = dict(os.environ, PYTHONPATH=str(path))
    args = [sys.executable, "-P", "-c", CHILD, str(repeat)] + ([zeta] if zeta else [])
    done = subprocess.run(args, env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv) -> int:
    opts = {"--rounds": "3", "--repeat": "2", "--damping-ratio": None}
    paths = []
    it = iter(argv)
    for a in it:
        if a in opts:
            opts[a] = next(it)
        else:
            paths.append(a)
    paths = paths + [str(HERE)] if str(HERE) not in paths else paths
    best: dict = {p: {} for p in paths}
    for r in range(int(opts["--rounds"])):
        for p in paths:
            res = run_once(p, int(opts["--repeat"]), opts["--damping-ratio"])
            runs = res["runs"]
            row = {"first": runs[0]["total"]}
            for k in ("total", "hybrid", "seeds", "paper"):
                row[k] = min(x.get(k, float("nan")) for x in runs[1:])
            row["branches"] = runs[-1]["branches"]
            for k, v in row.items():
                best[p][k] = min(best[p].get(k, v), v) if k != "branches" else v
            print(f"round {r}: {p}: " + "  ".join(f"{k} {v:.3f}" if k != "branches" else f"{k} {v}"
                                                  for k, v in row.items()), flush=True)
    ref = best[paths[0]]
    print("best of all rounds (seconds; ratio reference / this):")
    for p in paths:
        b = best[p]
        print(f"  {p}: " + "  ".join(f"{k} {b[k]:.3f} ({ref[k] / b[k]:.2f}x)" for k in ("first", "total", "hybrid",
                                                                                       "seeds", "paper"))
              + f"  branches {b['branches']}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
