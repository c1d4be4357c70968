"""Every curve of periodic responses is listed once: no two branches of a run hold the same orbit.

Brute force over every pair of branches of one signature, not plbar's test of a seed
(:mod:`plbar.periodic.followed`, chords and Newton from one interpolated piece): from every point of one
branch, Newton at that point's ``T`` from each point of the other (every one, not the nearest), and the same orbit
(sorted durations and loss per period to 1e-7) anywhere is a duplicate.  Branches of the paper's class that the
scan splits where they touch (one shared end) are allowed that one point.

The default chain's run listed the same 1PZ curve five times and the same 2PZ stretches twice (a curve that went
round its loop twice) before the curves were told apart by their orbits.
"""

import numpy as np
import pytest

import plbar
from plbar.periodic import NotConverged, polish


def _key(o):
    return np.concatenate([np.sort(o.durations), [o.loss_per_T]])


def _same(a, b) -> bool:
    u, v = _key(a), _key(b)
    scale = np.r_[np.full(v.size - 1, b.T), max(abs(b.loss_per_T), 1e-9 * b.T)]
    return u.shape == v.shape and bool(np.all(np.abs(u - v) <= 1e-7 * scale))


def _shared(prob, bi, bj) -> int:
    """How many points of branch ``bi`` Newton reaches from some point of ``bj``, at their own ``T``."""
    n = 0
    lo, hi = bj.T.min(), bj.T.max()
    for o in bi.orbits:
        if not lo - 0.05 * (hi - lo + 1e-3) <= o.T <= hi + 0.05 * (hi - lo + 1e-3):
            continue
        for p in sorted(bj.orbits, key=lambda p: abs(p.T - o.T))[:8]:
            try:
                q = polish(prob, p.sig, o.T, p.X)
            except NotConverged:
                continue
            if _same(q, o):
                n += 1
                break
    return n


@pytest.fixture(scope="module")
def default_run():
    return plbar.solve(plbar.Case())


def test_no_two_branches_share_an_orbit(default_run):
    res = default_run
    prob = res.prob
    by_sig = {}
    for b in res.branches:
        by_sig.setdefault(str(b.sig.canonical()), []).append(b)
    dup = []
    for sig, bs in by_sig.items():
        for i, bi in enumerate(bs):
            for j, bj in enumerate(bs):
                if i != j:
                    k = _shared(prob, bi, bj)
                    if k > (1 if bi.paper and bj.paper else 0):
                        dup.append((sig, bi.id, bj.id, k, len(bi)))
    assert not dup, dup
