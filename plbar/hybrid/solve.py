"""Exact periodic responses of any signature: Newton on the chain's residuals with its exact Jacobian.

:func:`polish` takes a guess ``(z0, durations, phi)`` at a period ``T`` and
returns a :class:`HybridOrbit` whose residuals, recomputed from the flow of
the returned state, are at round-off (or raises :class:`NotConverged`).  The
orbit's energy follows: the impact loss of every impact, ``S v_c^2 / 2``
(Eq. (14)), summed over the orbit (``dPL``, ``m`` periods) and per forcing
period (``loss_per_T``); ``xi_eq`` of Eq. (22) over all its segments
(FORMULATION §8) and ``xi_w`` (one frequency, the forcing's).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import PlbarError
from ..model import Problem
from ..response import psi
from ..util.reprs import build
from .chain import Chain, evaluate, layout
from .signature import Signature

__all__ = ["HybridOrbit", "NotConverged", "polish", "orbit_at", "ACCEPT"]

ACCEPT = 1e-11     #: largest relative residual of an accepted orbit


class NotConverged(PlbarError):
    """Newton did not bring the residuals of a periodic response to round-off."""


@dataclass(frozen=True)
class HybridOrbit:
    """One periodic response of signature ``sig`` at period ``T``.

    Attributes
    ----------
    sig : Signature
    T, phi : float
    X : ndarray
        The unknowns ``(z0, durations, phi)`` (:mod:`.chain`).
    durations : ndarray, shape (2k,)
        ``tau^I_1, tau^II_1, ..., tau^I_k, tau^II_k`` (zero for a zero dwell); they sum to ``m T``.
    residual : float
        Largest relative residual recomputed from the flow.
    dPL : float
        Impact loss over the orbit (``m`` periods), the sum of ``S v_c^2 / 2`` over its impacts.
    loss_per_T, xi, xi_w : float
        ``dPL / m``; ``xi_eq`` (Eq. (22) over all segments); ``xi_w`` (one frequency, the forcing's).
    v_impact : ndarray, shape (k,)
        Contact velocity just before each impact (> 0).
    zero_margins : ndarray
        ``-R`` just after each impact followed by a zero dwell (< 0).
    chain : Chain
    """

    prob: Problem
    sig: Signature
    T: float
    phi: float
    X: np.ndarray
    durations: np.ndarray
    residual: float
    dPL: float
    loss_per_T: float
    xi: float
    xi_w: float
    v_impact: np.ndarray
    zero_margins: np.ndarray
    chain: Chain

    @property
    def z0(self) -> np.ndarray:
        return self.X[:2 * self.prob.system.w1.size]

    def __repr__(self) -> str:
        return build("HybridOrbit", {"sig": str(self.sig), "T": self.T, "phi": self.phi,
                                     "durations": np.array2string(self.durations, precision=5),
                                     "loss_per_T": self.loss_per_T, "xi": self.xi, "residual": self.residual})


def _scales(prob: Problem, ch: Chain, X, nz: int, q: int, T: float) -> np.ndarray:
    zs = max(float(np.abs(X[:nz]).max(initial=0.0)), 1e-300)
    return np.concatenate([np.maximum(ch.switch_scale, 1e-300), [T], np.full(nz, zs)])


def durations_of(sig: Signature, X: np.ndarray, nz: int) -> np.ndarray:
    """The ``2k`` durations (zero dwells filled in) from the unknowns."""
    out, col = [], 0
    for positive in sig.dwell:
        if positive:
            out.append(X[nz + col])
            col += 1
        else:
            out.append(0.0)
        out.append(X[nz + col])
        col += 1
    return np.array(out, float)


def _energy(prob: Problem, ch: Chain, T: float, phi: float):
    """``dPL``, ``sum w Psi``, ``sum Psi`` and the impact velocities of an evaluated chain."""
    sy = prob.system
    W = 2 * np.pi / T
    dpl, den, kin, vimp = 0.0, 0.0, 0.0, []
    S = prob.cached("impact_mass", lambda p: p.system.impact_mass)
    for seg in ch.segments:
        w, f = (sy.w1, prob.f1) if seg.state == 1 else (sy.w2, prob.f2)
        m = w.size
        p, _ = psi(w, f, W, seg.t0, seg.tau, seg.z0[:m], seg.z0[m:], np.cos(phi), np.sin(phi))
        den += float(p @ w)
        kin += float(np.sum(p))
        if seg.state == 2:
            vc = float(sy.gap_row @ seg.z1[m:])
            vimp.append(vc)
            dpl += 0.5 * S * vc * vc
    return dpl, den, kin, np.array(vimp)


def orbit_at(prob: Problem, sig: Signature, T: float, X, ch: Chain | None = None) -> HybridOrbit:
    """The :class:`HybridOrbit` of unknowns ``X`` (residuals recomputed here, not trusted)."""
    X = np.asarray(X, float)
    ch = ch if ch is not None and ch.J is None else evaluate(prob, sig, T, X, jac=False)
    nz, q, _ = layout(prob, sig)
    res = float(np.max(np.abs(ch.F) / _scales(prob, ch, X, nz, q, T)))
    dpl, den, kin, vimp = _energy(prob, ch, T, float(X[-1]))
    W = 2 * np.pi / T
    return HybridOrbit(prob, sig, float(T), float(np.mod(X[-1], 2 * np.pi)), X, durations_of(sig, X, nz), res,
                       dpl, dpl / sig.m, dpl / (2 * den) if den > 0 else 0.0,
                       dpl / (2 * W * kin) if kin > 0 else 0.0, vimp, ch.zero_margins, ch)


def polish(prob: Problem, sig: Signature, T: float, X0, maxit: int = 30) -> HybridOrbit:
    """Newton on the chain's residuals from the guess ``X0`` (exact Jacobian, damped by halving).

    Raises
    ------
    NotConverged
        If the relative residual does not reach :data:`ACCEPT`, or a duration turns negative.
    """
    X = np.array(X0, float)
    nz, q, _ = layout(prob, sig)
    T = float(T)
    for _ in range(maxit):
        ch = evaluate(prob, sig, T, X)
        sc = _scales(prob, ch, X, nz, q, T)
        r = np.max(np.abs(ch.F) / sc)
        if r <= ACCEPT * 1e-2:
            break
        try:
            dX = np.linalg.solve(ch.J, -ch.F)
        except np.linalg.LinAlgError:
            raise NotConverged(f"singular Jacobian for {sig} at T = {T:.12g}") from None
        lam = 1.0
        for _ in range(20):
            Xn = X + lam * dX
            if np.all(Xn[nz:nz + q] > 0):
                rn = np.max(np.abs(evaluate(prob, sig, T, Xn, jac=False).F) / sc)
                if rn < r or lam < 1e-3:
                    break
            lam *= 0.5
        X = Xn
    orb = orbit_at(prob, sig, T, X)
    if not orb.residual <= ACCEPT or np.any(X[nz:nz + q] <= 0):
        raise NotConverged(f"{sig} at T = {T:.12g}: residual {orb.residual:.2e} after Newton")
    return orb
