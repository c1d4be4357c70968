"""Settling motions: a motion still approaching a periodic orbit, told apart from an irregular one (issue 28).

A weakly stable periodic orbit (a Floquet multiplier near 1, no inherent
damping) is approached slowly: after the transient the recorded boundary
states still differ from period to period by more than the survey's repeat
tolerance (:data:`plbar.motion.PERIODIC_TOL`), so the window alone cannot call
the motion periodic.  The evidence is found instead in the orbit:

1. candidate periods ``m``: those whose repeat distance ``|z_(r+m) - z_r|``
   over the window ends below :data:`CANDIDATE` and is smaller over its last
   third than over its first (the first few are tried, smallest first);
2. the exact orbit polished from the last ``2 m`` recorded periods
   (:func:`plbar.periodic.from_motion`, Newton on the chain), reduced to its
   own period (:meth:`plbar.periodic.Orbit.minimal`);
3. its multipliers (:func:`plbar.periodic.monodromy`): it is stable,
   ``max |mu| < 1``;
4. the trajectory approaches it: the distance of every recorded boundary
   state from the orbit's state at the same time (``e_r``, relative to the
   largest state of the window) decreases over the window (a least-squares
   rate ``exp(d log e_r / d r) < 1`` and ``e_R < e_0``) and ends below
   :data:`SETTLED`;
5. it approaches it *as the linearisation says*: the measured rate is the
   contraction per forcing period of one of the orbit's Floquet directions,
   ``|mu_k|^(1/m)``, to :data:`RATE_MATCH` in the logarithm (the slowest one,
   ``max |mu|^(1/m)``, unless that direction is not excited).  A trajectory
   still far from the orbit (its distance governed by the nonlinear flow, or
   about to leave on another transient) does not decay at such a rate.  On
   the default case (600 periods from rest) the motions that the independent
   simulator later sees repeat match their slowest direction to 0.1-15 % (T =
   6.6, 6.9, 7.9, 8.3, 9.3, 10.5, 11.6, 12.0-12.3, 12.9, 13.3); T = 7.3 (37 %) is
   left irregular; T = 9.5, which approaches a 3ZZPZP orbit over the window
   at 0.998 per period while its multipliers give 0.99983 and 0.944, is not
   settling there: carried on, it repeats only after 40,000 periods, on an
   orbit of period 9.

Only then is the motion reported ``periodic`` (with the orbit's period); the
measured ``orbit_distance`` and ``rate`` go into the table beside the orbit's
``max_abs_multiplier``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import PlbarError
from ...periodic import Orbit, from_motion, monodromy, multipliers, orbit_series
from ...motion import M_MAX, Run

__all__ = ["CANDIDATE", "SETTLED", "RATE_MATCH", "Approach", "candidate_periods", "orbit_of", "approach", "settle"]

CANDIDATE = 3e-2   #: repeat distance at the window's end below which a motion is tried as settling
SETTLED = 1e-1     #: distance from its stable orbit at the window's end below which a motion may have settled
RATE_MATCH = 0.25  #: relative difference of log(rate) and log(|mu_k|^(1/m)) allowed for a linear approach


@dataclass(frozen=True)
class Approach:
    """How a trajectory's recorded window approaches an exact orbit.

    Attributes
    ----------
    orbit : Orbit
        The exact orbit (its own period).
    multipliers : ndarray
        Its Floquet multipliers over its ``m`` forcing periods, by decreasing modulus.
    distance : ndarray, shape (R + 1,)
        ``e_r``: distance of the recorded boundary state ``r`` from the orbit's state at the same time,
        relative to the largest state of the window.
    rate : float
        Least-squares contraction of ``e_r`` per forcing period (``exp`` of the slope of ``log e_r``).
    """

    orbit: Orbit
    multipliers: np.ndarray
    distance: np.ndarray
    rate: float

    @property
    def max_abs_multiplier(self) -> float:
        return float(np.abs(self.multipliers[0]))

    @property
    def stable(self) -> bool:
        return bool(self.max_abs_multiplier < 1.0)

    @property
    def linear_rates(self) -> np.ndarray:
        """The contraction per forcing period along each Floquet direction, ``|mu_k|^(1/m)`` (non-zero ones)."""
        a = np.abs(self.multipliers)
        return a[a > 1e-12] ** (1.0 / self.orbit.sig.m)

    @property
    def settled(self) -> bool:
        """Stable, approached (``rate < 1``, last distance below the first), within :data:`SETTLED` and at the
        rate of one of its Floquet directions (:data:`RATE_MATCH`)."""
        e = self.distance
        if not (self.stable and self.rate < 1.0 and e[-1] < e[0] and e[-1] <= SETTLED):
            return False
        lr = self.linear_rates
        return bool(np.any(np.abs(np.log(self.rate) / np.log(lr[lr < 1.0]) - 1.0) <= RATE_MATCH))


def _states(r: Run, b: int) -> np.ndarray:
    return np.concatenate([r.strobe_x[b], r.strobe_v[b]], axis=1)


def candidate_periods(z: np.ndarray, m_max: int = M_MAX) -> list[int]:
    """The periods ``m`` (increasing) whose repeat distance over the boundary states ``z`` (R + 1, 2n) decreases
    (smaller over the last third of the window than over the first) and ends below :data:`CANDIDATE`; ``m`` up to
    a third of the window."""
    scale = max(float(np.linalg.norm(z, axis=1).max()), 1e-300)
    R = z.shape[0] - 1
    out = []
    for m in range(1, min(m_max, R // 3) + 1):
        d = np.linalg.norm(z[m:] - z[:-m], axis=1) / scale
        k = max(1, d.size // 3)
        if d[-1] <= CANDIDATE and d[-k:].max() < d[:k].max():
            out.append(m)
    return out


def orbit_of(prob, r: Run, b: int, m: int) -> Orbit:
    """The exact orbit of the last ``2 m`` recorded periods of trajectory ``b`` (its own period).

    Raises :class:`plbar.PlbarError` (Newton does not converge) or ``ValueError`` (the switches are not
    opening/impact pairs).
    """
    o = from_motion(prob, r, b, m, max(0, r.record - 2 * m))
    return o.minimal() if o.period < o.sig.m else o


def approach(r: Run, b: int, orb: Orbit) -> Approach:
    """How trajectory ``b``'s window approaches the exact orbit ``orb`` (see :class:`Approach`).

    The orbit's ``t = 0`` is an impact at an absolute time ``t_0`` with ``phi_orbit = phi - W t_0`` (mod 2 pi),
    known modulo ``T``; of the ``m`` orbit states at the boundaries, the rotation nearest the last recorded state
    is the one compared throughout the window.
    """
    T = float(r.T[b])
    W = 2 * np.pi / T
    p = orb.sig.m
    R = r.record
    z = _states(r, b)
    scale = max(float(np.linalg.norm(z, axis=1).max()), 1e-300)
    t_first = (r.periods - R) * T
    lag = np.mod((float(r.phi[b]) - orb.phi) / W - t_first, T)      # first boundary + lag = an impact of the orbit
    xs, vs, _ = orbit_series(orb).response(np.mod(-lag + np.arange(p) * T, p * T))
    B = np.concatenate([xs, vs], axis=1)         # orbit state at boundary i (mod p) after t_first
    rows = np.arange(R + 1)
    j = int(np.argmin([np.linalg.norm(z[R] - B[(R + j) % p]) for j in range(p)]))
    e = np.linalg.norm(z - B[(rows + j) % p], axis=1) / scale
    with np.errstate(divide="ignore"):
        slope = np.polyfit(rows, np.log(np.maximum(e, 1e-300)), 1)[0]
    mu = multipliers(monodromy(orb.prob, orb.sig, orb.T, orb.phi, orb.chain))
    return Approach(orb, mu, e, float(np.exp(slope)))


def settle(prob, r: Run, b: int, tries: int = 3) -> Approach | None:
    """The stable orbit trajectory ``b`` has settled on (:attr:`Approach.settled`), or ``None``.

    The first ``tries`` candidate periods are tried in turn (an orbit of period 5 approached through complex
    multipliers may also show a decreasing repeat distance at ``m = 1``, whose switches are not an orbit's).
    """
    if int(r.status[b]) != 0:
        return None
    tried = set()
    for m in candidate_periods(_states(r, b))[:tries]:
        try:
            orb = orbit_of(prob, r, b, m)
            if orb.sig.m in tried:
                continue
            tried.add(orb.sig.m)
            a = approach(r, b, orb)
        except (PlbarError, ValueError, np.linalg.LinAlgError):
            continue
        if a.settled:
            return a
    return None
