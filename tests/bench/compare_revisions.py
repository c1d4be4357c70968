"""Side-by-side speed of two checkouts of plbar (interleaved rounds in fresh processes).

Usage::

    git worktree add --detach /tmp/plbar-old <revision>
    python tests/bench/compare_revisions.py /tmp/plbar-old . [rounds]

Times the default case (``plbar.solve()``), one ``find_response`` (green point)
and the FE P1 lumped bar with N = 10, alternately with each checkout on
``PYTHONPATH``, and prints the medians and ratios (new / old), with the point
counts of both (which must agree).  Not a test.
"""

import json
import os
import statistics
import subprocess
import sys

CODE = r'''
import json, time
import plbar
t = []
for _ in range(3):
    t0 = time.perf_counter(); r = plbar.solve(); t.append(time.perf_counter() - t0)
prob = plbar.Case().problem()
f = []
for _ in range(5):
    t0 = time.perf_counter()
    for _ in range(200):
        plbar.find_response(prob, 12.277, 2.39)
    f.append((time.perf_counter() - t0) / 200)
t0 = time.perf_counter(); r2 = plbar.solve(plbar.Case(model="fe", n=10)); fe = time.perf_counter() - t0
print(json.dumps(dict(solve=min(t), find=min(f), fe10=fe, pts=sum(len(b) for b in r.branches),
                      fe_pts=sum(len(b) for b in r2.branches))))
'''


def main(old: str, new: str, rounds: int = 3) -> None:
    res = {"old": [], "new": []}
    for _ in range(rounds):
        for key, path in (("old", old), ("new", new)):
            env = dict(os.environ, PYTHONPATH=os.path.abspath(path))
            out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, env=env, cwd="/")
            d = json.loads(out.stdout.strip().splitlines()[-1])
            res[key].append(d)
            print(key, d, flush=True)
    for key in ("solve", "find", "fe10"):
        o = statistics.median(d[key] for d in res["old"])
        n = statistics.median(d[key] for d in res["new"])
        print(f"{key:6s}: old {o:.4g} s, new {n:.4g} s, new/old {n / o:.3f}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 3)
