"""Measure the periodic responses with rebounds of ``plbar run --restitution E`` against the simulator (issue 31).

Every admissible point of every branch: events vs the simulator's (relative to m T), return after m periods from
a section inside the orbit, loss per period; the multipliers of a sample vs a finite-difference Jacobian of the
simulator's m-period map (the stability verdict).  Prints the worst of each.  Usage:
``python tests/bench/verify_rebound_orbits.py [E ...]`` (default 0.3 0.6).
"""

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "periodic"))

import plbar  # noqa: E402
from plbar.periodic import expected_events, monodromy, multipliers  # noqa: E402
from plbar.periodic.verify import start_of  # noqa: E402
from plbar.motion import Start, padded, run  # noqa: E402
from test_rebound_orbits import _fd_map, _modal, _section, _simulate  # noqa: E402

for e in [float(x) for x in sys.argv[1:]] or [0.3, 0.6]:
    t0 = time.perf_counter()
    res = plbar.solve(plbar.Case(restitution=e))
    others = [b for b in res.branches if not b.paper]
    prob = res.prob
    orbs = [o for b in others for o in b.orbits]
    stable = np.concatenate([b.stable for b in others]) if others else np.zeros(0, bool)
    print(f"e = {e}: {len(others)} branches, {len(orbs)} points ({int(stable.sum())} stable), "
          f"{len({b.label for b in others})} signatures, solve {time.perf_counter() - t0:.1f} s")
    pad = padded(prob)
    st = np.zeros(len(orbs), int)
    eta, vel = np.zeros((len(orbs), pad.m)), np.zeros((len(orbs), pad.m))
    for i, o in enumerate(orbs):
        st[i], eta[i], vel[i] = start_of(o, pad.m)
    mmax = max(o.sig.m for o in orbs)
    r = run(pad, np.array([o.T for o in orbs]), np.array([o.phi for o in orbs]), mmax + 1, mmax + 1,
            Start(st, eta, vel), accounts=False)
    wt = wx = wl = wxs = 0.0
    bad = 0
    mus = [abs(multipliers(monodromy(prob, o.sig, o.T, o.phi, o.chain))[0]) for o in orbs]
    for i, o in enumerate(orbs):
        sel = r.events["traj"] == i
        te, ke = r.events["time"][sel], r.events["kind"][sel]
        et, ek = expected_events(o)
        if not np.array_equal(ke[:et.size], ek):
            bad += 1
            continue
        wt = max(wt, float(np.abs(te[:et.size] - et).max()) / (o.sig.m * o.T))
        ts, state, y = _section(o)
        rs = _simulate(prob, o, ts, state, y[None], o.sig.m, accounts=True)
        back = _modal(prob, state, rs.strobe_x[0, o.sig.m], rs.strobe_v[0, o.sig.m])
        ret = float(np.abs(back - y).max() / np.abs(y).max())
        wx = max(wx, ret)
        wxs = max(wxs, ret / max(1.0, mus[i]))       # round-off amplified by the orbit's own instability
        w = prob.system.w1 if state == 0 else prob.system.w2
        energy = 0.5 * float(np.sum((w * y[:w.size]) ** 2 + y[w.size:] ** 2))
        wl = max(wl, abs(rs.loss[0].sum() / o.sig.m - o.loss_per_T) / max(o.loss_per_T, 1e-3 * energy))
    print(f"  events: kinds differ at {bad} points; times <= {wt:.1e} m T; return <= {wx:.1e} (<= {wxs:.1e} "
          f"|mu|max: largest |mu|max {max(mus):.3g}, {sum(m > 1e3 for m in mus)} points above 1e3); loss <= {wl:.1e}")
    rng = np.random.default_rng(1)
    pick = rng.choice(len(orbs), size=min(60, len(orbs)), replace=False)
    agree = dmax = skipped = at_one = 0
    for i in pick:
        o = orbs[i]
        mu = multipliers(monodromy(prob, o.sig, o.T, o.phi, o.chain))
        try:
            fd = multipliers(_fd_map(prob, o))
        except AssertionError:                       # a perturbed neighbour ends in the other state: near grazing
            skipped += 1
            continue
        if abs(abs(mu[0]) - 1) <= 1e-6:              # a multiplier 1 (a fold): no verdict to confirm
            at_one += 1
            agree += int(abs(abs(fd[0]) - 1) <= 1e-6)
            continue
        agree += int((abs(mu[0]) < 1) == (abs(fd[0]) < 1))
        dmax = max(dmax, float(abs(abs(mu[0]) - abs(fd[0]))) / max(1.0, abs(mu[0])))
    print(f"  Floquet: {agree}/{len(pick) - skipped} verdicts confirmed by the simulator's map ({skipped} skipped: "
          f"a neighbour 1e-7 away switches otherwise; {at_one} at a multiplier 1 within 1e-6, a fold, where both have "
          f"it); |mu|max differs <= {dmax:.1e} of max(1, |mu|max)")
