"""One periodic response of any signature as a time series over its whole orbit (:func:`orbit_series`), and the
orbit of a table row (:func:`from_row`, :func:`canonical`).

:func:`orbit_series` is the orbit as a :class:`plbar.motion.Series` (one block of pieces: the chain's segments),
what :func:`plbar.io.response_data` samples for export and render of every signature: its ``span`` is the orbit's
period ``m T_forcing``; ``stuck_time`` and ``free_time`` the total time stuck and free over it.
"""

from __future__ import annotations

import numpy as np

from ..motion import Series
from ..util.record import events
from .chain import layout
from .signature import Signature
from .solve import Orbit, polish

__all__ = ["orbit_series", "canonical", "from_row"]


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


def orbit_series(orb: Orbit) -> Series:
    """The orbit ``orb`` as a :class:`plbar.motion.Series` over ``[0, m T)``, its pieces the chain's segments.

    Its events are the switches between the segments (1 opening, 2 impact, 3 rebound; ``loss`` nan: not computed
    here).
    """
    segs = list(orb.chain.segments)
    sy = orb.prob.system
    st = np.array([sg.state for sg in segs])
    cols = max(sy.w1.size, sy.w2.size)
    eta, vel = np.zeros((st.size, cols)), np.zeros((st.size, cols))
    for i, sg in enumerate(segs):                  # z0 = (eta, etadot) of the segment's state
        m = (sy.w1 if sg.state == 1 else sy.w2).size
        eta[i, :m], vel[i, :m] = sg.z0[:m], sg.z0[m:2 * m]
    starts = np.array([sg.t0 for sg in segs])
    kind = np.where(st[1:] == 2, np.where(st[:-1] == 1, 1, 3), 2)
    d = orb.durations
    return Series(prob=orb.prob, T=float(orb.T), phi=float(orb.phi), t0=0.0, span=orb.sig.m * orb.T,
                  periods=int(orb.sig.m), events=events(starts[1:], kind, np.full(kind.size, np.nan)),
                  stuck_time=float(d[0::2].sum()), free_time=float(d[1::2].sum()), block=orb.sig.m * orb.T,
                  starts=starts, blocks=np.zeros(starts.size, int), state=st, eta=eta, vel=vel)
