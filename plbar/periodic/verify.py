"""Is a computed periodic response what the bar does?  Replayed by the certified batched simulator.

Each orbit is started from its own state (state I just after its last impact,
load phase ``phi``) in :func:`plbar.motion.run`, whose event search cannot miss a
crossing, for ``m`` forcing periods and a little more.  The orbit is
*admissible* when the simulation meets exactly the orbit's switches, in
order and at the predicted times (to ``tol`` of ``m T``), and nothing else
(no premature opening or impact, no grazing contact in between); this is
the admissibility of FORMULATION §4 checked for every segment at once.
"""

from __future__ import annotations

import numpy as np

from ..motion import FREE, IMPACT, OPENS, REBOUND, STICK, STUCK, Start, padded, run
from .chain import state_data
from .solve import Orbit

__all__ = ["admissible", "expected_events", "start_of"]


def expected_events(orb: Orbit) -> tuple[np.ndarray, np.ndarray]:
    """Times and kinds of the orbit's switches in ``[0, m T]``, as the simulator records them: 1 opening, 2 plastic
    impact, 3 rebound, 4 the impact that ends a chattering sequence (restitution ``e > 0``; recorded at the
    accumulation point of the rebounds it stands for, ``2 e v_c / (a (1 - e))`` later, ``a`` the contact's
    acceleration towards the wall: :func:`plbar.motion.kernel.loop.rebound`)."""
    times, kinds = [], []
    t = 0.0
    sig, k = orb.sig, orb.sig.k
    e = float(getattr(orb.prob, "restitution", 0.0))
    for i in range(k):
        if not sig.rebound[i]:
            t += orb.durations[2 * i]
            times.append(t)
            kinds.append(OPENS)
        t += orb.durations[2 * i + 1]
        nxt = (i + 1) % k
        if sig.rebound[nxt]:
            times.append(t)
            kinds.append(REBOUND)
        elif e > 0:
            times.append(t + _accumulation(orb, i, e))
            kinds.append(STICK)
        else:
            times.append(t)
            kinds.append(IMPACT)
    return np.array(times), np.array(kinds)


def _accumulation(orb: Orbit, i: int, e: float) -> float:
    """The time the simulator adds to the sticking impact ending pair ``i``: ``2 e v_c / (a (1 - e))``."""
    if e >= 1.0:
        return 0.0
    seg = sum(2 if d else 1 for d in orb.sig.dwell[:i + 1]) - 1      # the free segment that ends pair i
    s = orb.chain.segments[seg]
    w, f, c, _, zeta, _ = state_data(orb.prob, 2)
    m = w.size
    eta, v = s.z1[:m], s.z1[m:]
    vc = float(orb.v_impact[i])                      # x_c' before the impact (> 0: towards the wall)
    v_after = v + (1.0 + e) * vc * c / float(c @ c)  # the rebound it stands for (c = -gap row)
    load = np.cos(2 * np.pi / orb.T * (s.t0 + s.tau) - orb.phi)
    acc = f * load - w * w * eta - (0.0 if zeta is None else 2.0 * zeta * w * v_after)
    a = float(-c @ acc)                              # x_c'': > 0 presses the contact to the wall
    return 2.0 * e * vc / (a * (1.0 - e)) if a > 0 else 0.0


def start_of(orb: Orbit, m: int) -> tuple[int, np.ndarray, np.ndarray]:
    """The orbit's start for the simulator: its state (``STUCK`` or ``FREE``) and the padded modal ``eta, vel``."""
    n = orb.z0.size // 2
    eta, vel = np.zeros(m), np.zeros(m)
    eta[:n], vel[:n] = orb.z0[:n], orb.z0[n:]
    return (FREE if orb.free_start else STUCK), eta, vel


def admissible(orbits, tol: float = 1e-9) -> np.ndarray:
    """One verdict per orbit (all of one problem): the simulation from its state meets exactly its switches."""
    orbits = list(orbits)
    if not orbits:
        return np.zeros(0, bool)
    prob = orbits[0].prob
    pad = padded(prob)
    B = len(orbits)
    eta, vel, state = np.zeros((B, pad.m)), np.zeros((B, pad.m)), np.zeros(B, int)
    for b, o in enumerate(orbits):
        state[b], eta[b], vel[b] = start_of(o, pad.m)
    mmax = max(o.sig.m for o in orbits)
    T = np.array([o.T for o in orbits])
    phi = np.array([o.phi for o in orbits])
    r = run(pad, T, phi, mmax + 1, mmax + 1, Start(state, eta, vel), accounts=False)
    ok = np.zeros(B, bool)
    order = np.argsort(r.events["traj"], kind="stable")          # each trajectory's events, in their order
    start = np.searchsorted(r.events["traj"][order], np.arange(B + 1))
    times, kinds = r.events["time"][order], r.events["kind"][order]
    for b, o in enumerate(orbits):
        te, ke = times[start[b]:start[b + 1]], kinds[start[b]:start[b + 1]]
        et, ek = expected_events(o)
        span = o.sig.m * o.T
        n = et.size
        extra = te[n:n + 1]                                       # the next switch: not before the end of the orbit
        ok[b] = r.status[b] == 0 and te.size >= n and np.array_equal(ke[:n], ek) and \
            bool(np.all(np.abs(te[:n] - et) <= tol * span)) and bool(np.all(extra >= span * (1 - tol)))
    return ok
