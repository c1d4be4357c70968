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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model import Problem
from ..response import forced_coeffs, free_flow
from .signature import Signature

__all__ = ["Chain", "Segment", "evaluate", "layout", "flow_matrix", "vector_field", "switch_maps"]


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
    pulls at once); ``switch_scale`` the size of the terms of each switching residual (for relative tests).
    """

    F: np.ndarray
    J: np.ndarray | None
    segments: tuple
    zero_margins: np.ndarray
    switch_scale: np.ndarray


def layout(prob: Problem, sig: Signature) -> tuple[int, int, int]:
    """``(nz, q, nX)``: state I size ``2 m1``, unknown durations, unknowns."""
    if getattr(prob.system, "damped", False):   # the chain's flows are undamped (issue 21): never silently
        raise InputError("periodic responses of other signatures do not take inherent (Rayleigh) damping yet; drop "
                         "rayleigh= / --rayleigh, or use plbar.solve for the paper's class, which does")
    nz = 2 * prob.system.w1.size
    q = sig.durations
    return nz, q, nz + q + 1


def flow_matrix(w: np.ndarray, tau: float) -> np.ndarray:
    """The modal free flow over ``tau`` on ``(eta, etadot)``: ``(2m, 2m)``, 2 x 2 blocks per mode."""
    c, s_w, mws, _ = free_flow(w, tau)
    m = w.size
    A = np.zeros((2 * m, 2 * m))
    i = np.arange(m)
    A[i, i] = A[m + i, m + i] = c
    A[i, m + i] = s_w
    A[m + i, i] = mws
    return A


def vector_field(w, f, W, t, phi, z) -> np.ndarray:
    """``dz/dt = (etadot, f cos(W t - phi) - w^2 eta)`` (Eq. (1) in modal form)."""
    m = w.size
    return np.concatenate([z[m:], f * np.cos(W * t - phi) - w * w * z[:m]])


def _state(prob: Problem, s: int):
    sy = prob.system
    if s == 1:
        return sy.w1, np.asarray(prob.f1, float), -np.asarray(sy.r_eta, float), -float(prob.r_q)
    return sy.w2, np.asarray(prob.f2, float), -np.asarray(sy.gap_row, float), 0.0


def switch_maps(prob: Problem):
    """The modal switch maps ``(E, G)``: opening ``diag(P12, P12)``, impact ``diag(P21, Q21)`` (cached)."""
    return prob.cached("hybrid_switch_maps", _build_switch_maps)


def _build_switch_maps(prob: Problem):
    sy = prob.system
    z12 = np.zeros_like(sy.P12)
    E = np.block([[sy.P12, z12], [z12, sy.P12]])
    z21 = np.zeros_like(sy.P21)
    G = np.block([[sy.P21, z21], [z21, sy.Q21]])
    return E, G


class _Walker:
    """Forward propagation of the state and (optionally) of its derivative with respect to ``X``."""

    def __init__(self, prob, sig, T, X, jac):
        self.prob, self.T, self.W = prob, float(T), 2 * np.pi / float(T)
        self.nz, self.q, self.nX = layout(prob, sig)
        self.X = np.asarray(X, float)
        self.phi = float(self.X[-1])
        self.z = self.X[:self.nz].copy()
        self.D = np.eye(self.nz, self.nX) if jac else None
        self.t = 0.0
        self.tcol = np.zeros(self.nX)          # dt/dX: the durations passed so far
        self.jac = jac

    def flow(self, s: int, col: int) -> Segment:
        w, f, _, _ = _state(self.prob, s)
        tau = float(self.X[self.nz + col])
        z0 = self.z
        Phi = flow_matrix(w, tau)
        ec, es, vc, vs = forced_coeffs(w, f, self.W, self.t, tau)
        Fc, Fs = np.concatenate([ec, vc]), np.concatenate([es, vs])
        cp, sp = np.cos(self.phi), np.sin(self.phi)
        z1 = Phi @ z0 + Fc * cp + Fs * sp
        if self.jac:
            dphi = -Fc * sp + Fs * cp
            D = Phi @ self.D
            D[:, -1] += dphi
            D += np.outer(-self.W * dphi, self.tcol)             # a later start shifts the load's phase
            D[:, self.nz + col] += vector_field(w, f, self.W, self.t + tau, self.phi, z1)
            self.D = D
        seg = Segment(s, self.t, tau, z0, z1, col, "open" if s == 1 else "impact")
        self.z = z1
        self.t += tau
        self.tcol[self.nz + col] = 1.0
        return seg

    def margin(self, s: int):
        """``(g, dg/dX, size)`` of the state's margin at the current point (``-R`` in I, ``-x_c`` in II)."""
        w, _, c, rq = _state(self.prob, s)
        m = w.size
        arg = self.W * self.t - self.phi
        g = c @ self.z[:m] + rq * np.cos(arg)
        size = np.abs(c) @ np.abs(self.z[:m]) + abs(rq)
        if not self.jac:
            return g, None, size
        dg = c @ self.D[:m] - rq * np.sin(arg) * (self.W * self.tcol - np.eye(1, self.nX, self.nX - 1)[0])
        return g, dg, size

    def switch(self, M: np.ndarray) -> None:
        self.z = M @ self.z
        if self.jac:
            self.D = M @ self.D


def evaluate(prob: Problem, sig: Signature, T: float, X, jac: bool = True) -> Chain:
    """Residuals ``F(X)`` (and the exact Jacobian) of the orbit of signature ``sig`` at period ``T``."""
    E, G = switch_maps(prob)
    wk = _Walker(prob, sig, T, X, jac)
    F, rows, segs, zero, scale = [], [], [], [], []
    col = 0
    for i, positive in enumerate(sig.dwell):
        if positive:
            segs.append(wk.flow(1, col))
            col += 1
            g, dg, size = wk.margin(1)
            F.append(g)
            rows.append(dg)
            scale.append(size)
        else:
            g, _, _ = wk.margin(1)                               # just after the impact: must pull (< 0)
            zero.append(g)
        wk.switch(E)
        segs.append(wk.flow(2, col))
        col += 1
        g, dg, size = wk.margin(2)
        F.append(g)
        rows.append(dg)
        scale.append(size)
        wk.switch(G)
    nz, q, nX = wk.nz, wk.q, wk.nX
    total = float(np.sum(wk.X[nz:nz + q])) - sig.m * float(T)
    F = np.concatenate([np.array(F), [total], wk.z - wk.X[:nz]])
    J = None
    if jac:
        tot = np.zeros(nX)
        tot[nz:nz + q] = 1.0
        J = np.vstack([np.array(rows), tot[None], wk.D - np.eye(nz, nX)])
    return Chain(F, J, tuple(segs), np.array(zero), np.array(scale))
