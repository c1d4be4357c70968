"""The segment chain of a periodic response of any signature, its switching residuals and their exact Jacobian.

Unknowns ``X = (z0, tau, phi)``: the state I modal state ``z0 = (eta^I, etadot^I)``
at ``t = 0+`` (just after the last impact of the orbit), the ``q`` unknown
durations in the order they occur (every positive dwell and every free
phase; a zero dwell is not an unknown) and the forcing phase ``phi``.
Equations ``F(X) = 0`` (as many as unknowns):

* one switching condition per unknown duration: the reaction vanishes at the
  end of a positive dwell (``-R = 0``, Eq. (4)), the gap closes at the end of a
  free phase (``x_c = 0``, Eq. (5));
* ``sum tau = m T``;
* periodicity ``z(m T) = z0`` after the last plastic impact (Eq. (10)).

Each segment is the closed-form modal flow of :mod:`plbar.response.flow`
(``z_end = Phi(tau) z + F_c cos phi + F_s sin phi``); the switches are the
existing ones (opening: embedding; impact: momenta of the other DOFs kept).
The Jacobian is propagated exactly through the chain: ``dz_end/dtau`` is the
vector field at the end of the segment, a later start time shifts the load's
phase (``d/dt_start = -W d/dphi`` of the forced part), and the switch maps and
flows are linear.  For ``m = 1`` and one positive dwell this is the paper's
periodic response (FORMULATION §4) written as a root of ``F``.

:func:`evaluate` walks the chain in compiled code (:mod:`plbar.periodic.kernel.walk`: the
closed-form flows of :mod:`plbar.motion.kernel.closed`, one mode at a time).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property, lru_cache

import numpy as np

from ..errors import InputError
from ..model import Problem
from .packed import ChainModel, Pairs, Walk
from .signature import Signature

__all__ = ["Chain", "Segment", "evaluate", "layout", "switch_maps", "state_data", "model", "dwell_of", "pairs_of",
           "compiled"]


@dataclass(frozen=True)
class Segment:
    """One segment of an evaluated chain: its state (1 or 2), start time, length and modal states at both ends.

    ``col`` is the column of its duration in ``X`` (-1 for none); ``end_kind`` what ends it:
    ``"open"`` (reaction vanishes), ``"impact"`` (gap closes).
    """

    state: int
    t0: float
    tau: float
    z0: np.ndarray
    z1: np.ndarray
    col: int
    end_kind: str


@dataclass(frozen=True)
class Chain:
    """An evaluated chain: residuals ``F``, Jacobian ``J`` (or None), the segments, and the zero-dwell margins.

    ``zero_margins`` holds ``-R`` just after each impact followed by a zero dwell (it must be < 0: the reaction
    pulls at once); ``switch_scale`` the size of the terms of each switching residual (for relative tests);
    ``residual`` the largest relative residual (each switching residual by its ``switch_scale``, the sum of the
    durations by ``T``, the periodicity by the largest component of ``z0``); ``v_impact`` the contact velocity
    just before each impact.  The segments (:class:`Segment`, built on first access) are in ``times`` (start,
    length), ``states`` (start and end state, padded to the larger state: the arrays the compiled code takes)
    and ``kinds`` (the state of each: 1 or 2); ``sizes`` is ``(2 m1, 2 m2)``.
    """

    F: np.ndarray
    J: np.ndarray | None
    zero_margins: np.ndarray
    switch_scale: np.ndarray
    residual: float
    v_impact: np.ndarray = field(repr=False)
    times: np.ndarray = field(repr=False)
    states: np.ndarray = field(repr=False)
    kinds: tuple = field(repr=False)
    sizes: tuple = field(repr=False)

    @cached_property
    def segments(self) -> tuple:
        """The :class:`Segment` of every duration, in order."""
        out = []
        for i, s in enumerate(self.kinds):
            n = self.sizes[s - 1]
            out.append(Segment(s, float(self.times[i, 0]), float(self.times[i, 1]), self.states[i, 0, :n],
                               self.states[i, 1, :n], i, "open" if s == 1 else "impact"))
        return tuple(out)


def layout(prob: Problem, sig: Signature) -> tuple[int, int, int]:
    """``(nz, q, nX)``: the start state's size (state I ``2 m1``; state II ``2 m2`` when the first pair begins with
    a rebound), unknown durations, unknowns.  A rebound (``R``) needs a coefficient of restitution ``e > 0``."""
    if sig.rebounds and not getattr(prob, "restitution", 0.0):
        raise InputError(f"signature {sig} has rebounds (R): they need a coefficient of restitution e > 0 "
                         "(Case(restitution=e), --restitution E); with e = 0 every impact sticks (P or Z)")
    nz = 2 * (prob.system.w2 if sig.rebound[0] else prob.system.w1).size
    q = sig.durations
    return nz, q, nz + q + 1


def state_data(prob: Problem, s: int):
    """``(w, f, c, rq, zeta, cv)`` of state ``s`` (1 or 2): the margin is ``c . eta + cv . etadot + rq cos``
    (``-R`` in state I, with the damper's share ``-r_v``; ``-x_c`` in state II), plus a gap's constant
    (``prob.statics.margin``); ``zeta, cv`` None undamped."""
    sy = prob.system
    damped = bool(getattr(sy, "damped", False))
    if s == 1:
        return (sy.w1, np.asarray(prob.f1, float), -np.asarray(sy.r_eta, float), -float(prob.r_q),
                sy.zeta1 if damped else None, -np.asarray(sy.r_v, float) if damped else None)
    return (sy.w2, np.asarray(prob.f2, float), -np.asarray(sy.gap_row, float), 0.0, sy.zeta2 if damped else None,
            None)


def switch_maps(prob: Problem):
    """The modal switch maps ``(E, G)``: opening ``diag(P12, P12)``, impact ``diag(P21, Q21)`` (cached)."""
    return prob.cached("hybrid_switch_maps", _build_switch_maps)


def rebound_map(prob: Problem) -> np.ndarray:
    """The modal map of a rebound (state II to state II, Newton's law with ``e = prob.restitution``):
    ``diag(I, I - (1 + e) g g^T / |g|^2)``, ``g`` the gap row (``x_c = g . eta``): the positions kept, the
    contact's velocity reversed and scaled by ``e``, the impulse along the contact DOF (cached)."""
    return prob.cached("hybrid_rebound_map", _build_rebound_map)


def _build_rebound_map(prob: Problem) -> np.ndarray:
    g = np.asarray(prob.system.gap_row, float)
    m = g.size
    B = np.eye(2 * m)
    B[m:, m:] -= (1.0 + float(getattr(prob, "restitution", 0.0))) * np.outer(g, g) / float(g @ g)
    return B


def _build_switch_maps(prob: Problem):
    sy = prob.system
    z12 = np.zeros_like(sy.P12)
    E = np.block([[sy.P12, z12], [z12, sy.P12]])
    z21 = np.zeros_like(sy.P21)
    G = np.block([[sy.P21, z21], [z21, sy.Q21]])
    return E, G


def model(prob: Problem) -> ChainModel:
    """The compiled chain's view of the problem (:class:`plbar.periodic.packed.ChainModel`; cached).

    Its ``damping`` is None undamped (the undamped flows are compiled), else a marker array (the damped ones)."""
    return prob.cached("hybrid_kernel_model", _build_model)


def _build_model(prob: Problem):
    tabs = []
    for s in (1, 2):
        w, f, c, rq, zeta, cv = state_data(prob, s)
        none = np.zeros_like(w)
        tabs.append(np.ascontiguousarray(np.stack([w, f, c, none if zeta is None else zeta,
                                                   none if cv is None else cv]), dtype=float))
    E, G = switch_maps(prob)
    damping = np.ones(1) if getattr(prob.system, "damped", False) else None
    st = prob.statics
    offE, offG = np.zeros(E.shape[0]), np.zeros(G.shape[0])
    offE[:st.open_offset.size], offG[:st.impact_offset.size] = st.open_offset, st.impact_offset
    return ChainModel(tabs[0], tabs[1], np.ascontiguousarray(E, float), np.ascontiguousarray(G, float),
                      float(state_data(prob, 1)[3]), np.ascontiguousarray(rebound_map(prob), float), damping,
                      np.ascontiguousarray(st.margin, float), offE, offG)


ZERO, POSITIVE, REBOUND = 0, 1, 2     #: pair kinds of the compiled chain (:func:`dwell_of`)


@lru_cache(maxsize=256)
def dwell_of(sig: Signature) -> np.ndarray:
    """The signature's pair kinds as the compiled chain takes them (:data:`ZERO` 0, :data:`POSITIVE` 1,
    :data:`REBOUND` 2)."""
    out = np.array([REBOUND if r else (POSITIVE if d else ZERO) for d, r in zip(sig.dwell, sig.rebound)], np.int64)
    out.setflags(write=False)
    return out


@lru_cache(maxsize=256)
def pairs_of(sig: Signature) -> Pairs:
    """The signature as the compiled chain takes it (:class:`plbar.periodic.packed.Pairs`)."""
    return Pairs(dwell_of(sig), int(sig.m))


@lru_cache(maxsize=None)
def compiled():
    """The compiled kernel, :mod:`plbar.periodic.kernel` (numba: imported on first use, not with plbar)."""
    from . import kernel

    return kernel


@lru_cache(maxsize=256)
def _plan(sig: Signature) -> tuple:
    """``(pairs, segment states, zero dwells, unknown durations, segments)`` of a signature (``pairs``:
    :func:`pairs_of`)."""
    states = tuple(s for positive in sig.dwell for s in ((1, 2) if positive else (2,)))
    return pairs_of(sig), states, sig.zero - sig.rebounds, sig.durations, len(states)


def evaluate(prob: Problem, sig: Signature, T: float, X, jac: bool = True) -> Chain:
    """Residuals ``F(X)`` (and the exact Jacobian) of the orbit of signature ``sig`` at period ``T`` (compiled:
    :func:`plbar.periodic.kernel.walk.chain`)."""
    md = model(prob)
    pairs, states, zeros, q, nseg = _plan(sig)
    m1, m2 = md.tab1.shape[1], md.tab2.shape[1]
    nX = layout(prob, sig)[2]
    X = np.ascontiguousarray(X, dtype=float)
    if X.shape != (nX,):
        raise ValueError(f"X has shape {X.shape}, the chain of {sig} takes {nX} unknowns")
    w = Walk(np.empty(nX), np.empty((nX, nX) if jac else (0, 0)), np.empty((nseg, 2)),
             np.zeros((nseg, 2, 2 * max(m1, m2))), np.empty(zeros), np.empty(q), np.empty(pairs.dwell.size))
    res = compiled().chain(md, pairs, float(T), X, w)
    return Chain(w.F, w.J if jac else None, w.zero, w.scale, res, w.vimp, w.times, w.zs, states, (2 * m1, 2 * m2))
