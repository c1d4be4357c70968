"""One periodic response of any signature as a time series over its whole orbit (``m`` forcing periods).

:class:`OrbitSeries` answers what :func:`plbar.io.response_data` asks of the
paper's :class:`plbar.Orbits` (``T``, ``T1``, ``T2``, ``phi``, ``take``,
``response``, ``energies``) plus the state I reaction at any time
(``reaction_at``), so export and render work for every signature: ``T`` is
the orbit's period ``m T_forcing``; ``T1`` and ``T2`` the total time stuck
and free over it.
"""

from __future__ import annotations

import numpy as np

from ..response import segment
from .chain import layout, state_data
from .signature import Signature
from .solve import Orbit, polish

__all__ = ["OrbitSeries", "canonical", "from_row"]


def canonical(orb: Orbit) -> tuple[Signature, np.ndarray, float]:
    """The orbit written from the rotation of its canonical signature: ``(sig, durations, phi)``.

    Starting ``r`` pairs later moves ``t = 0`` to ``t_r`` (the impact ending pair ``r - 1``), so the
    load's phase becomes ``phi - W t_r``.
    """
    target = orb.sig.canonical()
    k = orb.sig.k
    for r in range(k):
        if orb.sig.rotated(r) == target:
            d = orb.durations
            t_r = float(np.sum(d[:2 * r]))
            return target, np.concatenate([d[2 * r:], d[:2 * r]]), float(np.mod(orb.phi - 2 * np.pi / orb.T * t_r,
                                                                                   2 * np.pi))
    return orb.sig, orb.durations, orb.phi


def from_row(prob, sig: Signature, T: float, durations, phi: float) -> Orbit:
    """The exact orbit of a table row (its state is recomputed: the chain is affine in it; Newton polishes)."""
    d = np.asarray(durations, float)
    var = []
    for i, positive in enumerate(sig.dwell):
        if positive:
            var.append(d[2 * i])
        var.append(d[2 * i + 1])
    nz = layout(prob, sig)[0]
    return polish(prob, sig, T, np.concatenate([np.zeros(nz), var, [phi]]))


class OrbitSeries:
    """A :class:`Orbit` sampled at any times of its orbit ``[0, m T)`` (see the module docstring)."""

    def __init__(self, orb: Orbit):
        self.orb = orb
        self.prob = orb.prob
        d = orb.durations
        self.T = np.array([orb.sig.m * orb.T])
        self.T1 = np.array([float(d[0::2].sum())])
        self.T2 = np.array([float(d[1::2].sum())])
        self.phi = np.array([orb.phi])
        segs = list(orb.chain.segments)
        self._segs = segs
        self._starts = np.array([s.t0 for s in segs])

    def __len__(self) -> int:
        return 1

    def take(self, idx):
        return self

    def _modal(self, t):
        """Per time: state (1 or 2) and modal ``eta, etadot`` (padded lists)."""
        prob, orb = self.prob, self.orb
        W = 2 * np.pi / orb.T
        t = np.asarray(t, float).ravel()
        j = np.clip(np.searchsorted(self._starts, t, side="right") - 1, 0, len(self._segs) - 1)
        out = []
        for ti, ji in zip(t, j):
            s = self._segs[ji]
            w, f, _, _, zeta, _ = state_data(prob, s.state)
            m = w.size
            e, v = segment(w, f, W, s.t0, ti - s.t0, s.z0[:m], s.z0[m:], np.cos(orb.phi), np.sin(orb.phi),
                           zeta=zeta)
            out.append((s.state, e, v, ti))
        return out

    def response(self, t):
        """Physical ``x, v`` (1, K, n) and state (1, K) at times ``t`` in ``[0, m T)``."""
        sy = self.prob.system
        xs, vs, st = [], [], []
        for s, e, v, _ in self._modal(t):
            if s == 1:
                xs.append(sy.embed(sy.V1 @ e))
                vs.append(sy.embed(sy.V1 @ v))
            else:
                xs.append(sy.V2 @ e)
                vs.append(sy.V2 @ v)
            st.append(s)
        return np.array(xs)[None], np.array(vs)[None], np.array(st)[None]

    def reaction_at(self, t):
        """``-R`` in state I at times ``t`` (0 in state II); (1, K)."""
        sy, prob, orb = self.prob.system, self.prob, self.orb
        W = 2 * np.pi / orb.T
        rv = np.asarray(sy.r_v, float) if getattr(sy, "damped", False) else np.zeros(sy.w1.size)
        out = [-(sy.r_eta @ e + rv @ v + prob.r_q * np.cos(W * ti - orb.phi)) if s == 1 else 0.0
               for s, e, v, ti in self._modal(t)]
        return np.array(out)[None]

    def energies(self, t):
        """Kinetic and potential energy (Eqs. (12)-(13)); each (1, K)."""
        sy = self.prob.system
        ek, ep = [], []
        for s, e, v, _ in self._modal(t):
            w = sy.w1 if s == 1 else sy.w2
            ek.append(0.5 * float(v @ v))
            ep.append(0.5 * float(np.sum((w * e) ** 2)))
        return np.array(ek)[None], np.array(ep)[None]
