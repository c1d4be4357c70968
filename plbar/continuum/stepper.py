"""The march in time: the end's closed-form motion step by step, fed by the delay line (compiled: :mod:`.kernel`).

The incoming invariant at ``x = L`` is ``w_in(t) = -w_out(t - 2L/c) + [F(t - (L-s)/c) - F(t - (L+s)/c)] / Z`` (the
wave left the end ``2L/c`` ago, was reflected by the clamp (``w+ = -w-``) and crossed the load twice, each time
gaining ``F / Z``).  So transport is exact, the load enters exactly, and only the end's homogeneous transient
``K exp(-Z tau / m)`` is stored linearly in each piece, and the pieces of a grid step between jumps are merged into
one by an energy-keeping L2 projection (second order).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .bar import ContinuumBar
from .kernel import IMPACT, MAX_EVENTS_PER_STEP, OPENING
from .kernel import march as _kernel
from .kernel.records import MarchBar, MarchLoad, MarchStart

__all__ = ["Start", "Marched", "march", "OPENING", "IMPACT", "MAX_EVENTS_PER_STEP"]

_HOLD = {None: 0, "closed": 1, "open": 2}


@dataclass(frozen=True)
class Start:
    """A start on a harmonic state: the end's ``u, v`` and contact, and the past ``w_out = C cos + D sin`` (the load
    acting since ``t = -inf``).  ``None`` in :func:`~plbar.continuum.simulate` is the rest against the wall."""

    u: float = 0.0
    v: float = 0.0
    stuck: bool = True
    C: float = 0.0
    D: float = 0.0


@dataclass(frozen=True)
class Marched:
    """What the march recorded: the delay line's pieces (absolute times), the events, the end at the cuts."""

    dt: float
    omega: float
    line: dict        #: t0, t1, a0, a1, C, D, jump (arrays over the pieces)
    events: dict      #: time, kind, v, loss
    strobes: np.ndarray   #: (periods, 3): u, v, stuck at the period boundaries
    amp: np.ndarray       #: (periods + 1,): largest -u(L) per period (the last entry is the final boundary's)


def march(bar: ContinuumBar, T: float, periods: int, n: int, phi: float, hold: str | None, start: Start | None,
          merge: bool = True) -> Marched:
    """March ``periods`` of ``T`` on ``dt = L / (c n)`` (``merge=False`` keeps every breakpoint: a reference)."""
    if hold not in _HOLD:
        raise InputError(f"hold = {hold!r} must be None, 'closed' or 'open'")
    st = start or Start()
    omega = 2 * math.pi / T
    rec, ev, strobes, amp, status, t_err = _kernel(
        MarchBar(float(bar.L), float(bar.c), float(bar.Z), float(bar.end_mass), float(bar.s)),
        MarchLoad(float(bar.q), omega, float(phi), start is None),
        MarchStart(float(st.u), float(st.v), bool(st.stuck), float(st.C), float(st.D)), float(T), int(periods),
        int(n), _HOLD[hold], bool(merge))
    if status:
        raise RuntimeError(f"chatter: more than {MAX_EVENTS_PER_STEP} switches in the step at t = {t_err:.6g}")
    dt = bar.L / (bar.c * n)
    k = rec[0]
    line = {"t0": k * dt + rec[1], "t1": k * dt + rec[2], "a0": rec[3].copy(), "a1": rec[4].copy(),
            "C": rec[5].copy(), "D": rec[6].copy(), "jump": rec[7].astype(bool)}
    events = {"time": ev[0].copy(), "kind": ev[1].astype(int), "v": ev[2].copy(), "loss": ev[3].copy()}
    return Marched(dt, omega, line, events, strobes.T.copy(), amp)
