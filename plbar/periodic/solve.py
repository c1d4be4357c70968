"""Exact periodic responses of any signature: Newton on the chain's residuals with its exact Jacobian.

:func:`polish` takes a guess ``(z0, durations, phi)`` at a period ``T`` and
returns a :class:`Orbit` whose residuals, recomputed from the flow of
the returned state, are at round-off (or raises :class:`NotConverged`).  The
orbit's energy follows: the impact loss of every impact, ``S v_c^2 / 2``
(Eq. (14)), summed over the orbit (``dPL``, ``m`` periods) and per forcing
period (``loss_per_T``); ``xi_eq`` of Eq. (22) over all its segments
(FORMULATION §8) and ``xi_w`` (one frequency, the forcing's).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np

from ..errors import PlbarError
from ..model import Problem
from ..util.reprs import build
from .chain import Chain, compiled, dwell_of, evaluate, layout, model, pairs_of
from .signature import Signature

__all__ = ["Orbit", "NotConverged", "polish", "orbit_at", "ACCEPT", "ROUNDOFF"]

ACCEPT = 1e-11     #: largest relative residual Newton accepts as converged
ROUNDOFF = 1e-13   #: the residual every reported orbit reaches (polish tightens to it)
AMPLITUDE_SAMPLES = 400   #: samples of each free phase for ``max |x_c|`` (``paths.csv``'s ``max_abs_xc``)
REPEAT_TOL = 1e-9  #: an orbit repeats a shorter one when its state comes back to this (relative) after it


class NotConverged(PlbarError):
    """Newton did not bring the residuals of a periodic response to round-off."""


@dataclass(frozen=True)
class Orbit:
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
    v_impact : ndarray, shape (k,)
        Contact velocity just before each impact (> 0).
    zero_margins : ndarray
        ``-R`` just after each impact followed by a zero dwell (< 0).
    chain : Chain

    ``dPL`` (impact loss over the orbit, ``m`` periods: the sum of ``S v_c^2 / 2`` over its impacts,
    Eq. (14), times ``1 - e^2`` for a rebound: :attr:`impact_loss`), ``loss_per_T = dPL / m``, ``xi``
    (``xi_eq``, Eq. (22) over all segments) and ``xi_w``
    (one frequency, the forcing's) are computed on first access.
    """

    prob: Problem
    sig: Signature
    T: float
    phi: float
    X: np.ndarray
    durations: np.ndarray
    residual: float
    v_impact: np.ndarray
    zero_margins: np.ndarray
    chain: Chain

    @property
    def z0(self) -> np.ndarray:
        """The modal state at ``t = 0+``: state I, or state II when the first pair begins with a rebound."""
        return self.X[:layout(self.prob, self.sig)[0]]

    @property
    def free_start(self) -> bool:
        """The orbit starts free (just after a rebound: ``z0`` is a state II modal state)."""
        return bool(self.sig.rebound[0])

    @property
    def start(self) -> tuple[np.ndarray, np.ndarray]:
        """Physical displacement and velocity of every DOF at ``t = 0`` (just after the last impact), in the
        contact coordinates: the state I static equilibrium plus the modal state ``z0`` through the state I modes,
        the contact DOF at rest at the stop (stuck); or, after a rebound, state II's equilibrium plus its modal
        state through the state II modes (:class:`plbar.model.Statics`; both 0 without a gap or constant load)."""
        s, st = self.prob.system, self.prob.statics
        z = self.z0
        if self.free_start:
            m = s.w2.size
            return st.x2 + z[:m] @ s.V2.T, z[m:] @ s.V2.T
        m = s.w1.size
        return st.x1 + s.embed(z[:m] @ s.V1.T), s.embed(z[m:] @ s.V1.T)

    @cached_property
    def impact_loss(self) -> np.ndarray:
        """The energy each impact takes (the impact ending pair ``i``): ``S v_c^2 / 2`` (Eq. (14)) where it sticks,
        ``(1 - e^2) S v_c^2 / 2`` where it rebounds (Newton's law, ``e`` the problem's restitution)."""
        S = self.prob.cached("impact_mass", lambda p: p.system.impact_mass)
        e = float(getattr(self.prob, "restitution", 0.0))
        nxt = np.roll(np.array(self.sig.rebound, bool), -1)
        return 0.5 * S * self.v_impact ** 2 * np.where(nxt, 1.0 - e * e, 1.0)

    @cached_property
    def dPL(self) -> float:
        return float(np.sum(self.impact_loss))

    @property
    def loss_per_T(self) -> float:
        return self.dPL / self.sig.m

    @cached_property
    def _psi(self) -> tuple[float, float, float]:
        return _energy(self.prob, self.sig, self.chain, self.T, float(self.X[-1]), compiled().PSI)

    @property
    def xi(self) -> float:
        den = self._psi[0]
        return self.dPL / (2 * den) if den > 0 else 0.0

    @property
    def xi_w(self) -> float:
        kin = self._psi[1]
        return self.dPL / (2 * (2 * np.pi / self.T) * kin) if kin > 0 else 0.0

    @property
    def viscous(self) -> float:
        """Energy taken by inherent damping over the orbit (0 undamped); the work of the load is ``dPL + viscous``."""
        return self._psi[2]

    @property
    def xi_total(self) -> float:
        """The Rayleigh ratio at the forcing frequency plus ``xi_eq`` (the total equivalent ratio)."""
        sy = self.prob.system
        return (float(sy.rayleigh_ratio(2 * np.pi / self.T)) if getattr(sy, "damped", False) else 0.0) + self.xi

    @cached_property
    def period(self) -> int:
        """Its own period in forcing periods: the smallest ``m'`` (a divisor of ``m``) such that the orbit is its first
        ``m'`` periods repeated -- the start of the segment that follows them is at ``m' T`` with the start state
        (to :data:`REPEAT_TOL` of its size) --, ``m`` for a minimal orbit.  A curve of ``m = 2`` followed from a
        period doubling, for one, ends on the ``m = 1`` orbit seen twice."""
        ch = self.chain
        n0 = ch.sizes[ch.kinds[0] - 1]                 # the first segment's state (the rest is padding)
        z = ch.states[0, 0, :n0]
        size = max(float(np.abs(z).max()), 1e-300)
        for p, n in self.sig.parts():
            seg = sum(2 if d else 1 for d in self.sig.dwell[:n])
            if (abs(ch.times[seg, 0] - p * self.T) <= REPEAT_TOL * self.sig.m * self.T
                    and np.abs(ch.states[seg, 0, :n0] - z).max() <= REPEAT_TOL * size):
                return p
        return self.sig.m

    def minimal(self) -> "Orbit":
        """The orbit of its own period (:attr:`period`): its first ``period`` forcing periods, polished, with their
        signature; itself when it is minimal."""
        p = self.period
        if p == self.sig.m:
            return self
        n = next(n for q, n in self.sig.parts() if q == p)
        sig = self.sig.head(p, n)
        nz = layout(self.prob, sig)[0]
        return polish(self.prob, sig, self.T, np.concatenate([self.X[:nz + sig.durations], self.X[-1:]]))

    @cached_property
    def amplitude(self) -> float:
        """``max |x_c|`` over the orbit, sampled on every free phase (:data:`AMPLITUDE_SAMPLES` equally spaced points
        each, its ends included: the paper's class as :meth:`plbar.response.Orbits.max_gap`)."""
        return _energy(self.prob, self.sig, self.chain, self.T, self.phi, compiled().AMPLITUDE)[0]

    def __repr__(self) -> str:
        return build("Orbit", {"sig": str(self.sig), "T": self.T, "phi": self.phi,
                                     "durations": np.array2string(self.durations, precision=5),
                                     "loss_per_T": self.loss_per_T, "xi": self.xi, "residual": self.residual})


def durations_of(sig: Signature, X: np.ndarray, nz: int) -> np.ndarray:
    """The ``2k`` durations (zero dwells filled in) from the unknowns."""
    out = np.zeros(2 * sig.k)
    out[_duration_slots(sig)] = X[nz:nz + sig.durations]
    return out


@lru_cache(maxsize=256)
def _duration_slots(sig: Signature) -> np.ndarray:
    """Where each unknown duration goes among the ``2k`` durations."""
    return np.array([2 * i + s for i, positive in enumerate(sig.dwell) for s in ((0, 1) if positive else (1,))])


def _energy(prob: Problem, sig: Signature, ch: Chain, T: float, phi: float, what: int) -> tuple[float, float, float]:
    """``sum_j w_j Psi_j``, ``sum_j Psi_j`` and the viscous loss ``sum_j 2 zeta_j w_j Psi_j`` over every segment of an
    evaluated chain (Eqs. (20)-(21); damped velocities with inherent damping), or ``(max |x_c|, 0, 0)`` over
    :data:`AMPLITUDE_SAMPLES` samples of every free phase (compiled: :mod:`plbar.periodic.kernel.energy`)."""
    return compiled().energy(model(prob), dwell_of(sig), float(T), float(phi), ch.times, ch.states, what,
                             AMPLITUDE_SAMPLES)


def orbit_at(prob: Problem, sig: Signature, T: float, X, ch: Chain | None = None) -> Orbit:
    """The :class:`Orbit` of unknowns ``X`` (residuals recomputed from the flow, or taken from ``ch``,
    an evaluation of the same ``X`` without Jacobian)."""
    X = np.asarray(X, float)
    ch = ch if ch is not None and ch.J is None else evaluate(prob, sig, T, X, jac=False)
    return Orbit(prob, sig, float(T), float(np.mod(X[-1], 2 * np.pi)), X,
                       durations_of(sig, X, layout(prob, sig)[0]), ch.residual, ch.v_impact, ch.zero_margins, ch)


def polish(prob: Problem, sig: Signature, T: float, X0, maxit: int = 30) -> Orbit:
    """Newton on the chain's residuals from the guess ``X0`` (exact Jacobian, damped by halving; compiled:
    :func:`plbar.periodic.kernel.newton.polish`).

    Raises
    ------
    NotConverged
        If the relative residual does not reach :data:`ACCEPT`, or a duration turns negative.
    """
    K = compiled()
    X = np.array(X0, float)
    nz, q, nX = layout(prob, sig)
    T = float(T)
    if X.shape != (nX,):
        raise ValueError(f"X0 has shape {X.shape}, the chain of {sig} takes {nX} unknowns")
    if K.polish(model(prob), pairs_of(sig), T, X, int(maxit), ROUNDOFF) == K.SINGULAR:
        raise NotConverged(f"singular Jacobian for {sig} at T = {T:.12g}")
    orb = orbit_at(prob, sig, T, X)
    if not orb.residual <= 10 * ROUNDOFF or np.any(X[nz:nz + q] <= 0):
        raise NotConverged(f"{sig} at T = {T:.12g}: residual {orb.residual:.2e} after Newton")
    return orb
