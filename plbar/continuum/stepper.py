"""The march in time: the end's closed-form motion step by step, fed by the delay line (:mod:`.history`).

The incoming invariant at ``x = L`` is ``w_in(t) = -w_out(t - 2L/c) + [F(t - (L-s)/c) - F(t - (L+s)/c)] / Z`` (the
wave left the end ``2L/c`` ago, was reflected by the clamp (``w+ = -w-``) and crossed the load twice, each time
gaining ``F / Z``).  So transport is exact, the load enters exactly, and only the end's homogeneous transient
``K exp(-Z tau / m)`` is stored linearly in each piece (second order).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from .bar import ContinuumBar
from .end import free, impact, lowest, opening, stored_line
from .history import History

__all__ = ["Start", "March", "OPENING", "IMPACT", "MAX_EVENTS_PER_STEP"]

OPENING, IMPACT = 1, 2
#: more switches than this in one grid step is taken as chatter and stops the march
MAX_EVENTS_PER_STEP = 50


@dataclass(frozen=True)
class Start:
    """A start on a harmonic state: the end's ``u, v`` and contact, and the past ``w_out = C cos + D sin`` (the load
    acting since ``t = -inf``).  ``None`` in :func:`~plbar.continuum.simulate` is the rest against the wall."""

    u: float = 0.0
    v: float = 0.0
    stuck: bool = True
    C: float = 0.0
    D: float = 0.0


@dataclass
class March:
    """The mutable state of one march (end state, delay line, events, strobes): a state holder."""

    bar: ContinuumBar
    omega: float
    phi: float
    n: int
    hold: str | None
    start: Start | None
    u: float = 0.0
    v: float = 0.0
    stuck: bool = True
    events: list = field(default_factory=list)
    strobes: list = field(default_factory=list)
    amp: list = field(default_factory=list)

    def __post_init__(self):
        if self.hold not in (None, "closed", "open"):
            raise InputError(f"hold = {self.hold!r} must be None, 'closed' or 'open'")
        self.dt = self.bar.L / (self.bar.c * self.n)
        st = self.start or Start()
        self.u, self.v, self.stuck = st.u, st.v, bool(st.stuck)
        self.hist = History(self.dt, 2 * self.n)
        for k in range(-2 * self.n, 0):
            self.hist.begin(k)
            self.hist.add(k, 0.0, self.dt, 0.0, 0.0, st.C, st.D)
        P = 2 * self.bar.L / self.bar.c
        self.rot = (math.cos(self.omega * P), math.sin(self.omega * P))
        b = self.bar
        self.delays = [] if b.at_end else [((b.L - b.s) / b.c, 1.0), ((b.L + b.s) / b.c, -1.0)]
        self.amp.append(-self.u)

    def force(self, d: float, t: float) -> tuple[float, float]:
        """``(C, D)`` of ``F(t - d) = q cos(omega (t - d) - phi)``, 0 before the load starts (rest start)."""
        if self.start is None and t < d:
            return 0.0, 0.0
        x = self.omega * d + self.phi
        return self.bar.q * math.cos(x), self.bar.q * math.sin(x)

    def forcing(self, t: float) -> tuple[float, float]:
        """``(C, D)`` of ``g``'s load part over a piece holding ``t``: ``Fterm / Z`` in ``w_in``, or ``F_L / Z``."""
        Z = self.bar.Z
        if self.bar.at_end:
            c, s = self.force(0.0, t)
            return c / Z, s / Z
        C = D = 0.0
        for d, sign in self.delays:
            c, s = self.force(d, t)
            C, D = C + sign * c / Z, D + sign * s / Z
        return C, D

    def step(self, k: int, cuts: list[float]) -> None:
        """Advance over grid step ``k``; ``cuts`` (in ``(0, dt)``) are extra breakpoints (period boundaries)."""
        tk, dt = k * self.dt, self.dt
        self.hist.begin(k)
        pts = sorted(set([d - tk for d, _ in self.delays if 0 < d - tk < dt] + list(cuts)))
        h = self.hist
        self.nev = 0
        for i in h.of_step(k - 2 * self.n):
            t0, t1, a0, a1 = h.tau0[i], h.tau1[i], h.a0[i], h.a1[i]
            cr, sr = self.rot
            Cw, Dw = h.C[i] * cr - h.D[i] * sr, h.C[i] * sr + h.D[i] * cr
            slope = (a1 - a0) / (t1 - t0)
            edges = [t0] + [p for p in pts if t0 < p < t1] + [t1]
            for sa, sb in zip(edges[:-1], edges[1:]):
                Cf, Df = self.forcing(tk + 0.5 * (sa + sb))
                if self.bar.at_end:
                    w_in, load = (-(a0 + slope * (sa - t0)), -slope, -Cw, -Dw), (Cf, Df)
                else:
                    w_in, load = (-(a0 + slope * (sa - t0)), -slope, Cf - Cw, Df - Dw), (0.0, 0.0)
                self.piece(k, sa, sb, w_in, load)
                if sb in cuts:
                    self.strobes.append((tk + sb, self.u, self.v, self.stuck))
                    self.amp.append(-self.u)

    def piece(self, k, sa, sb, w_in, load) -> None:
        """March the end over ``[sa, sb]`` of step ``k`` (local times), switching where the closed form says."""
        while sb > sa:
            tau = self.stuck_piece(k, sa, sb, w_in, load) if self.stuck else self.free_piece(k, sa, sb, w_in, load)
            if tau is None:
                return
            l0, l1, C, D = w_in
            w_in = (l0 + l1 * tau, l1, C, D)
            sa += tau
            self.nev += 1
            if self.nev > MAX_EVENTS_PER_STEP:
                raise RuntimeError(f"chatter: more than {MAX_EVENTS_PER_STEP} switches in the step at t = "
                                   f"{k * self.dt:.6g}")

    def g(self, k, sa, w_in, load):
        """The compression ``g(tau) = Z w_in + F_L`` the wall must hold (>= 0 while stuck), on local times."""
        l0, l1, C, D = w_in
        Z, w, ta = self.bar.Z, self.omega, k * self.dt + sa
        Ct, Dt = C + load[0], D + load[1]
        return lambda tau: Z * (l0 + l1 * tau + Ct * np.cos(w * (ta + tau)) + Dt * np.sin(w * (ta + tau)))

    def stuck_piece(self, k, sa, sb, w_in, load):
        """Stuck over ``[sa, sb]``: ``w_out = -w_in`` until the wall would pull (returns that local time or None)."""
        l0, l1, C, D = w_in
        tau = None if self.hold == "closed" else opening(self.g(k, sa, w_in, load), sb - sa)
        te = sb - sa if tau is None else tau
        self.hist.add(k, sa, sa + te, -l0, -(l0 + l1 * te), -C, -D)
        if tau is not None:
            self.events.append((k * self.dt + sa + tau, OPENING, 0.0, 0.0))
            self.stuck, self.u, self.v = False, 0.0, 0.0
        return tau

    def free_piece(self, k, sa, sb, w_in, load):
        """Free over ``[sa, sb]`` in closed form until the end returns to the wall (plastic impact, Eq. (14))."""
        l0, l1, C, D = w_in
        b, h = self.bar, sb - sa
        p = free(k * self.dt + sa, self.u, self.v, l0, l1, C + load[0], D + load[1], self.omega, b.Z, b.end_mass)
        tau = None if self.hold == "open" else impact(p, h)
        te = h if tau is None else tau
        a0, a1 = stored_line(p, te, l0, l1, C, D)
        self.hist.add(k, sa, sa + te, a0, a1, 2 * p.a - C, 2 * p.b - D)
        self.amp[-1] = max(self.amp[-1], -lowest(p, te))
        self.u, self.v = float(p.u(te)), float(p.v(te))
        if tau is None:
            return None
        t = k * self.dt + sa + tau
        self.events.append((t, IMPACT, self.v, 0.5 * b.end_mass * self.v ** 2))
        self.u, self.v = 0.0, 0.0
        self.stuck = self.g(k, sa, w_in, load)(tau) >= 0
        if not self.stuck:
            self.events.append((t, OPENING, 0.0, 0.0))
        return tau
