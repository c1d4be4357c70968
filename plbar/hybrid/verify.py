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

from ..motion import STUCK, Start, padded, run
from .solve import HybridOrbit

__all__ = ["admissible", "expected_events"]


def expected_events(orb: HybridOrbit) -> tuple[np.ndarray, np.ndarray]:
    """Times and kinds (1 opening, 2 impact) of the orbit's switches in ``[0, m T]``."""
    times, kinds = [], []
    t = 0.0
    for i, positive in enumerate(orb.sig.dwell):
        t += orb.durations[2 * i]
        times.append(t)
        kinds.append(1)
        t += orb.durations[2 * i + 1]
        times.append(t)
        kinds.append(2)
    return np.array(times), np.array(kinds)


def admissible(orbits, tol: float = 1e-9) -> np.ndarray:
    """One verdict per orbit (all of one problem): the simulation from its state meets exactly its switches."""
    orbits = list(orbits)
    if not orbits:
        return np.zeros(0, bool)
    prob = orbits[0].prob
    pad = padded(prob)
    m1 = prob.system.w1.size
    B = len(orbits)
    eta, vel = np.zeros((B, pad.m)), np.zeros((B, pad.m))
    for b, o in enumerate(orbits):
        eta[b, :m1], vel[b, :m1] = o.z0[:m1], o.z0[m1:]
    mmax = max(o.sig.m for o in orbits)
    T = np.array([o.T for o in orbits])
    phi = np.array([o.phi for o in orbits])
    r = run(pad, T, phi, mmax + 1, mmax + 1, Start(np.full(B, STUCK), eta, vel), accounts=False)
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
