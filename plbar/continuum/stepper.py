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

__all__ = ["Start", "Field", "Marched", "march", "OPENING", "IMPACT", "MAX_EVENTS_PER_STEP"]

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
class Field:
    """A start from a given field: the displacement ``u`` and velocity ``v`` at ``t = 0`` on the march's grid
    ``x_j = j L / n`` (``n`` the steps per ``L / c``; linear between its points), at rest on the clamp (``u_0 = v_0 =
    0``), the end at or short of the wall (``u_n <= 0``; at it, held).  The load starts at ``t = 0``.

    The delay line's past is d'Alembert's decomposition of the field (:func:`field_seed`), so the march from it is as
    exact as from rest: the clamped bar released compressed against the wall (Dabaghi et al. 2016) to round-off.
    """

    u: np.ndarray
    v: np.ndarray

    def __post_init__(self):
        for name in ("u", "v"):
            a = np.array(getattr(self, name), float)
            if a.ndim != 1 or a.size < 3 or not np.all(np.isfinite(a)):
                raise InputError(f"the field's {name} must be finite values on the grid x_j = j L / n (n + 1 >= 3 "
                                 f"of them), got shape {a.shape}")
            object.__setattr__(self, name, a)
        if self.u.size != self.v.size:
            raise InputError(f"the field's u and v must be on the same grid, got {self.u.size} and {self.v.size}")
        if self.u[0] != 0.0 or self.v[0] != 0.0:
            raise InputError(f"the field must be at rest on the clamp x = 0, got u = {self.u[0]:g}, v = {self.v[0]:g}")
        if self.u[-1] > 0.0:
            raise InputError(f"the field's end u(L) = {self.u[-1]:g} is past the wall (u(L) <= 0)")


def field_seed(f: Field, c: float, L: float) -> np.ndarray:
    """The delay line's past ``w_out(t)``, ``-2L/c <= t < 0``, of the field ``f``: rows ``a0, a1, jump`` per grid
    step.  With ``w- = v + c u_x`` (leaving through ``x = L``) and ``w+ = v - c u_x``, ``w_out(t) = w-(L + c t, 0)``
    for ``t >= -L/c`` and ``-w+(-L - c t, 0)`` before (reflected by the clamp); linear on each grid step."""
    n = f.u.size - 1
    ux = np.diff(f.u) / (L / n)                         # per cell j = 0 .. n - 1
    late = np.vstack([f.v[:-1] + c * ux, f.v[1:] + c * ux])               # steps -n .. -1: cells 0 .. n-1
    early = np.vstack([-(f.v[1:] - c * ux), -(f.v[:-1] - c * ux)])[:, ::-1]   # steps -2n .. -n-1: cells n-1 .. 0
    a = np.hstack([early, late])
    jump = np.r_[0.0, (a[0, 1:] != a[1, :-1]).astype(float)]
    return np.vstack([a, jump])


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
    seed = np.zeros((3, 0))
    if isinstance(start, Field):
        if start.u.size != n + 1:
            raise InputError(f"the field is on {start.u.size - 1} grid steps; the march has n = {n} per L / c: give "
                             f"u, v on x_j = j L / {n}")
        seed = field_seed(start, bar.c, bar.L)
        start = Start(float(start.u[-1]), float(start.v[-1]), start.u[-1] == 0.0)
        rest = True
    else:
        rest = start is None
    st = start or Start()
    omega = 2 * math.pi / T
    rec, ev, strobes, amp, status, t_err = _kernel(
        MarchBar(float(bar.L), float(bar.c), float(bar.Z), float(bar.end_mass), float(bar.s)),
        MarchLoad(float(bar.q), omega, float(phi), rest),
        MarchStart(float(st.u), float(st.v), bool(st.stuck), float(st.C), float(st.D)), float(T), int(periods),
        int(n), _HOLD[hold], bool(merge), seed)
    if status:
        raise RuntimeError(f"chatter: more than {MAX_EVENTS_PER_STEP} switches in the step at t = {t_err:.6g}")
    dt = bar.L / (bar.c * n)
    k = rec[0]
    line = {"t0": k * dt + rec[1], "t1": k * dt + rec[2], "a0": rec[3].copy(), "a1": rec[4].copy(),
            "C": rec[5].copy(), "D": rec[6].copy(), "jump": rec[7].astype(bool)}
    events = {"time": ev[0].copy(), "kind": ev[1].astype(int), "v": ev[2].copy(), "loss": ev[3].copy()}
    return Marched(dt, omega, line, events, strobes.T.copy(), amp)
