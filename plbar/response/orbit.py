"""Closed-form periodic responses over the whole period (batched).

An :class:`Orbits` holds ``P`` periodic responses of one :class:`Problem`
(each a triplet ``(T^I, T^II, phi)`` with its periodic initial state) and
evaluates, at any times, the modal and physical displacements and velocities,
the state I contact reaction and the state II gap, and the impact.  With
Rayleigh damping (``prob.system.damped``) every flow is the damped one and the
reaction has its damper part (FORMULATION §8).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..model import Problem
from ..util.batch import Batch
from ..util.reprs import build, rng
from .flow import flow_matrix, segment
from .onemap import coefficients, states

__all__ = ["Orbits", "orbits", "periodic_state"]


@dataclass(frozen=True)
class Orbits(Batch):
    """``P`` periodic responses of ``prob``.

    Attributes
    ----------
    T1, T2, phi : ndarray, shape (P,)
    eta0, v0 : ndarray, shape (P, n-1)
        State I modal state at ``t = 0`` (periodic initial condition).
    eta_s, v_s : ndarray, shape (P, n)
        State II modal state just after the gap opens (``t = T^I``).
    """

    _shared = ("prob",)

    prob: Problem
    T1: np.ndarray
    T2: np.ndarray
    phi: np.ndarray
    eta0: np.ndarray
    v0: np.ndarray
    eta_s: np.ndarray
    v_s: np.ndarray

    @property
    def T(self) -> np.ndarray:
        return self.T1 + self.T2

    @property
    def W(self) -> np.ndarray:
        """Forcing circular frequency ``2 pi / T``."""
        return 2 * np.pi / self.T

    def __len__(self) -> int:
        return self.T1.size

    def __repr__(self) -> str:
        return build("Orbits", {"P": len(self), "n": self.prob.system.n, "T": rng(self.T),
                                "T1": rng(self.T1), "T2": rng(self.T2), "phi": rng(self.phi)})

    def _cs(self):
        return np.cos(self.phi)[:, None, None], np.sin(self.phi)[:, None, None]

    def state_I(self, tau):
        """Modal ``eta^I, etadot^I`` at ``t = tau`` in ``[0, T^I]``; tau (P, K) -> (P, K, n-1)."""
        s = self.prob.system
        c, sn = self._cs()
        tau = np.asarray(tau, float)[..., None]
        return segment(s.w1, self.prob.f1, self.W[:, None, None], 0.0, tau,
                       self.eta0[:, None, :], self.v0[:, None, :], c, sn, s.zeta[0])

    def state_II(self, tau):
        """Modal ``eta^II, etadot^II`` at ``t = T^I + tau``, tau in ``[0, T^II]``; (P, K) -> (P, K, n)."""
        s = self.prob.system
        c, sn = self._cs()
        tau = np.asarray(tau, float)[..., None]
        return segment(s.w2, self.prob.f2, self.W[:, None, None], self.T1[:, None, None], tau,
                       self.eta_s[:, None, :], self.v_s[:, None, :], c, sn, s.zeta[1])

    def _signal(self, tau, state: int, c: np.ndarray):
        """``sum_j c_j eta_j`` and ``sum_j c_j etadot_j`` in one state at times ``tau`` (P, K).

        Away from resonance each mode is ``alpha cos(w tau) + beta sin(w tau)``
        plus its particular part, and the particular parts of all modes sum
        into one harmonic (one ``cos``/``sin`` per sample instead of a kernel
        per mode).  Modes within ``|w - W| tau_max < 0.05`` of resonance use
        the exact kernels of :mod:`plbar.flow` (no cancellation).  Damped modes
        take the damped flow of every mode (:func:`plbar.response.flow.segment`).
        """
        s, p = self.prob.system, self.prob
        if s.damped:
            return self._signal_damped(np.asarray(tau, float), state, c)
        if state == 1:
            w, f, ts, e0, v0 = s.w1, p.f1, np.zeros_like(self.T1), self.eta0, self.v0
            span = self.T1
        else:
            w, f, ts, e0, v0 = s.w2, p.f2, self.T1, self.eta_s, self.v_s
            span = self.T2
        tau = np.asarray(tau, float)
        W = self.W[:, None]
        th = W * ts[:, None] - self.phi[:, None]                      # (P, 1)
        # near resonance, and a rigid-body mode (w = 0: eta0 + v0 tau), take the exact kernels
        near = (np.abs(w[None, :] - W) * span[:, None] < 0.05) | (w == 0.0)[None, :]   # (P, n)
        d = w[None, :] ** 2 - W ** 2
        g = np.where(near, 0.0, f / np.where(near, 1.0, d))           # particular amplitudes
        ct, st = np.cos(th), np.sin(th)
        alpha = np.where(near, 0.0, e0 - g * ct) * c                  # (P, n)
        wn = np.where(w == 0.0, 1.0, w)
        beta = np.where(near, 0.0, v0 / wn + g * (W / wn) * st) * c
        gsum = (g * c).sum(axis=1)[:, None]                           # (P, 1)
        wt = tau[..., None] * w                                        # (P, K, n)
        co, si = np.cos(wt), np.sin(wt)
        x = np.einsum("pkj,pj->pk", co, alpha) + np.einsum("pkj,pj->pk", si, beta)
        v = np.einsum("pkj,pj->pk", co, beta * w) - np.einsum("pkj,pj->pk", si, alpha * w)
        ph = W * tau + th
        x = x + gsum * np.cos(ph)
        v = v - gsum * W * np.sin(ph)
        if near.any():
            rows = np.flatnonzero(near.any(axis=1))
            cph, sph = np.cos(self.phi[rows])[:, None, None], np.sin(self.phi[rows])[:, None, None]
            sel = near[rows][:, None, :]
            ex, ev = segment(w, f, self.W[rows, None, None], ts[rows, None, None], tau[rows][..., None],
                             e0[rows, None, :], v0[rows, None, :], cph, sph)
            x[rows] += np.sum(np.where(sel, ex, 0.0) * c, axis=-1)
            v[rows] += np.sum(np.where(sel, ev, 0.0) * c, axis=-1)
        return x, v

    def _signal_damped(self, tau, state: int, c: np.ndarray, cv: np.ndarray | None = None):
        """:meth:`_signal` of damped modes: free decay of each mode plus one summed steady harmonic.

        Each mode is ``flow(u) (z0 - z_p(0)) + z_p(u)`` with the steady state
        ``eta_p = Re(f H e^{i(W (ts + u) - phi)})``, ``H = 1 / (w^2 - W^2 + 2 i zeta w W)``;
        the steady parts of all modes sum into one complex amplitude.  Modes with
        ``|w - W + i zeta w| span < 0.05`` (near resonance, little damping, where the
        split would cancel) take the exact kernels of :func:`plbar.response.flow.segment`.
        The velocity signal uses the weights ``cv`` if given (default ``c``).
        """
        cv = c if cv is None else cv
        s, p = self.prob.system, self.prob
        if state == 1:
            w, z, f, ts, e0, v0, span = s.w1, s.zeta1, p.f1, np.zeros_like(self.T1), self.eta0, self.v0, self.T1
        else:
            w, z, f, ts, e0, v0, span = s.w2, s.zeta2, p.f2, self.T1, self.eta_s, self.v_s, self.T2
        W = self.W[:, None]
        den = w * w - W * W + 2j * z * w * W                                    # (P, n)
        near = np.abs(den) * span[:, None] < 0.1 * w
        P = np.where(near, 0.0, f / np.where(near, 1.0, den)) * np.exp(1j * (W * ts[:, None] - self.phi[:, None]))
        h0 = np.where(near, 0.0, e0 - P.real)                                  # transient's initial state
        hv0 = np.where(near, 0.0, v0 - (1j * W * P).real)
        p11, p12, p21, p22 = flow_matrix(w, tau[..., None], z)                  # (P, K, n)
        x = np.einsum("pkj,pj->pk", p11, h0 * c) + np.einsum("pkj,pj->pk", p12, hv0 * c)
        v = np.einsum("pkj,pj->pk", p21, h0 * cv) + np.einsum("pkj,pj->pk", p22, hv0 * cv)
        eW = np.exp(1j * W * tau)                                               # summed steady parts
        x, v = x + ((P @ c)[:, None] * eW).real, v + (1j * W * (P @ cv)[:, None] * eW).real
        if near.any():
            rows = np.flatnonzero(near.any(axis=1))
            cph, sph = np.cos(self.phi[rows])[:, None, None], np.sin(self.phi[rows])[:, None, None]
            ex, ev = segment(w, f, self.W[rows, None, None], ts[rows, None, None], tau[rows][..., None],
                             e0[rows, None, :], v0[rows, None, :], cph, sph, z)
            sel = near[rows][:, None, :]
            x[rows] += np.sum(np.where(sel, ex, 0.0) * c, axis=-1)
            v[rows] += np.sum(np.where(sel, ev, 0.0) * cv, axis=-1)
        return x, v

    def reaction_margin(self, tau):
        """``-R`` in state I at ``t = tau`` (``>= 0`` while in compression, Eq. (4)); (P, K).

        With damping ``R = r_eta . eta + r_v . eta' + r_q cos(W t - phi)`` (FORMULATION §8).
        """
        tau = np.asarray(tau, float)
        s = self.prob.system
        if s.damped:
            x, xv = self._signal_damped(tau, 1, s.r_eta, s.r_v)
            x = x + xv
        else:
            x, _ = self._signal(tau, 1, s.r_eta)
        cosf = np.cos(self.W[:, None] * tau - self.phi[:, None])
        return -(x + self.prob.r_q * cosf)

    def gap_signals(self, tau):
        """Contact displacement ``x_c`` and velocity ``v_c`` in state II at ``t = T^I + tau``; each (P, K)."""
        return self._signal(np.asarray(tau, float), 2, self.prob.system.gap_row)

    def gap(self, tau):
        """Contact displacement ``x_c`` in state II at ``t = T^I + tau`` (``<= 0``, Eq. (5)); (P, K)."""
        return self.gap_signals(tau)[0]

    def max_gap(self, samples: int = 400) -> np.ndarray:
        """``max_t |x_c(t)|`` of each orbit over ``samples`` equally spaced points of state II (the contact node
        moves in state II only); (P,)."""
        u = np.linspace(0.0, 1.0, samples)
        return np.abs(self.gap(self.T2[:, None] * u)).max(axis=1)

    @cached_property
    def amplitude(self) -> np.ndarray:
        """:meth:`max_gap` on 400 points, computed once (``paths.csv``'s ``max_abs_xc`` and the plots)."""
        return self.max_gap(400)

    def contact_velocity(self, tau):
        """Contact velocity ``v_c`` in state II at ``t = T^I + tau``; (P, K)."""
        return self.gap_signals(tau)[1]

    def end(self):
        """Modal state II at ``t = T^-`` (just before the impact): ``eta, etadot`` (P, n)."""
        e, v = self.state_II(self.T2[:, None])
        return e[:, 0], v[:, 0]

    def after_impact(self):
        """State I modal state after the plastic impact at ``t = T`` (Eq. (10)): (P, n-1)."""
        s = self.prob.system
        e, v = self.end()
        return e @ s.P21.T, v @ s.Q21.T

    def residuals(self):
        """Switch residuals from the flow itself: ``e1 = -R(T^I-)``, ``e2 = x_c(T-)``."""
        e1 = self.reaction_margin(self.T1[:, None])[:, 0]
        e2 = self.gap(self.T2[:, None])[:, 0]
        return e1, e2

    def response(self, t):
        """Physical displacements and velocities at absolute times ``t`` in ``[0, T]``.

        Parameters
        ----------
        t : array_like, shape (P, K) or (K,)

        Returns
        -------
        x, v : ndarray, shape (P, K, n)
        state : ndarray of int, shape (P, K)
            1 in state I (``t < T^I``), 2 in state II.
        """
        s = self.prob.system
        t = np.broadcast_to(np.asarray(t, float), (len(self), np.size(t) if np.ndim(t) == 1 else np.shape(t)[1]))
        inI = t < self.T1[:, None]
        e1, v1 = self.state_I(np.minimum(t, self.T1[:, None]))
        e2, v2 = self.state_II(np.maximum(t - self.T1[:, None], 0.0))
        x = np.where(inI[..., None], s.embed(e1 @ s.V1.T), e2 @ s.V2.T)
        v = np.where(inI[..., None], s.embed(v1 @ s.V1.T), v2 @ s.V2.T)
        return x, v, np.where(inI, 1, 2)

    def energies(self, t):
        """Kinetic and potential energy (Eqs. (12)-(13)) at absolute times ``t``; each (P, K)."""
        s = self.prob.system
        t = np.broadcast_to(np.asarray(t, float), (len(self), np.size(t) if np.ndim(t) == 1 else np.shape(t)[1]))
        inI = t < self.T1[:, None]
        e1, v1 = self.state_I(np.minimum(t, self.T1[:, None]))
        e2, v2 = self.state_II(np.maximum(t - self.T1[:, None], 0.0))
        ek = np.where(inI, 0.5 * np.sum(v1 ** 2, -1), 0.5 * np.sum(v2 ** 2, -1))
        ep = np.where(inI, 0.5 * np.sum((s.w1 * e1) ** 2, -1), 0.5 * np.sum((s.w2 * e2) ** 2, -1))
        return ek, ep


def orbits(prob: Problem, T1, T2, phi, co=None) -> Orbits:
    """Periodic responses at given triplets ``(T^I, T^II, phi)``.

    The initial state solves the periodicity system; on a periodic path the
    switch residuals vanish, elsewhere they do not (see :meth:`Orbits.residuals`).
    """
    T1 = np.atleast_1d(np.asarray(T1, float))
    T2 = np.atleast_1d(np.asarray(T2, float))
    phi = np.atleast_1d(np.asarray(phi, float))
    if co is None:
        co = coefficients(prob, T1, T2)
    eta0, v0 = states(co, phi)
    s = prob.system
    W = 2 * np.pi / (T1 + T2)
    e, v = segment(s.w1, prob.f1, W[:, None], 0.0, T1[:, None], eta0, v0,
                   np.cos(phi)[:, None], np.sin(phi)[:, None], s.zeta[0])
    return Orbits(prob, T1, T2, phi, eta0, v0, e @ s.P12.T, v @ s.P12.T)


def periodic_state(orbits: Orbits) -> tuple[np.ndarray, np.ndarray]:
    """Physical state I start ``(x_r, v_r)`` of each orbit at ``t = 0+``: (P, n-1) each."""
    V1 = orbits.prob.system.V1
    return orbits.eta0 @ V1.T, orbits.v0 @ V1.T
