"""A contact node of a tiny mass (P1, redistributed mass, end mass 1e-6): impacts and openings a few ulps apart.

Issue 44: on N = 32 such a sequence ran for ever (each switch a few ulps after the last: never a zero-length
segment, and each reset the stall count); N = 16 stopped as chattering in 0.1 s.  Every simulation ends in
bounded time with a status and a message.  The simulation runs in a subprocess, so that a regression fails
(by its time limit) instead of hanging the suite.
"""

import json
import subprocess
import sys

import numpy as np

SCRIPT = """
import json, sys, time
import numpy as np
import plbar
from plbar.motion import padded, run
pad = padded(plbar.Case(model="fe", n=32, element="P1", mass="redistributed", end_mass=1e-6).problem())
t0 = time.perf_counter()
r = run(pad, [9.0], 0.0, 1, 1, accounts=False)
print(json.dumps({"status": r.status.tolist(), "stop": r.stop_time.tolist(), "times": r.events["time"].tolist(),
                  "rounds": r.rounds, "messages": r.messages, "repr": repr(r),
                  "seconds": time.perf_counter() - t0}))
"""


def test_impacts_and_openings_ulps_apart_stop_as_chattering():
    p = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    r = json.loads(p.stdout.strip().splitlines()[-1])
    assert r["status"] == [1] and r["rounds"] < 10_000          # bounded work (seconds include a first compile)
    t = np.array(r["times"])
    # the recorded switches end in a run of switches each within 1e-3 of a period of the one before (zero-length
    # stuck phases and flights of a few ulps: either chatter guard, MAX_ZERO or MAX_SHORT, may stop it first)
    gaps = np.diff(t)
    assert gaps.size > 50 and np.all(gaps[-50:] <= 1e-3 * 9.0) and gaps[:10].max() > 1e-3
    assert 0.0 < t[-1] <= r["stop"][0] < 9.0 and r["stop"][0] - t[-1] <= 1e-6 * 9.0
    (msg,) = r["messages"]
    assert msg.startswith("T = 9: stopped at t = ") and "chattering contact" in msg and msg in r["repr"]
