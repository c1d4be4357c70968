"""Everything about candidate path points: the periodic orbit, its phase, validity and admissibility.

A refined zero of ``G`` is a path point if the switch residuals recomputed
from the flow are at round-off (a true zero of ``D``, not a pole), the orbit
is periodic through the flow and the impact (``Id - A`` regular) and one of
``phi``, ``phi + pi`` is admissible (no premature switch, Eqs. (4)-(5)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Problem
from ..response import Admissibility, Orbits, check_both, orbits, phase
from ..response.admissible import coarse, n_samples
from ..util.progress import progress_bar
from ..util.threads import map_chunks
from .scan import PAR_CHUNK, chunked_coefficients

__all__ = ["Evaluated", "evaluate", "periodicity_error", "ZERO_TOL", "PERIODIC_TOL", "NOT_A_ZERO", "NOT_PERIODIC",
           "IMPACT_VELOCITY"]

ZERO_TOL = 1e-7         #: relative switch residual below which a refined crossing is a zero of D
PERIODIC_TOL = 1e-10    #: relative periodicity error (through the flow) a path point must meet
SAMPLE_ELEMENTS = 2e7   #: largest (points x samples x modes) array of one admissibility chunk (160 MB)
NOT_A_ZERO = "not a zero of D"                    #: why a point is no path point (a pole of D)
NOT_PERIODIC = "not periodic (Id - A singular)"   #: ... (a free periodic motion)
IMPACT_VELOCITY = "impact velocity <= 0"          #: ... (the contact node does not come back to the wall)


def periodicity_error(orb: Orbits) -> np.ndarray:
    """``|z(T+) - z(0)| / |z(0)|`` with ``z(T+)`` from the closed-form flow and the impact map (Eq. (10)).

    Rejects points where ``Id - A`` is numerically singular (a free periodic
    motion of the two-state system), whose solve is not trustworthy.
    """
    e, v = orb.after_impact()
    z0 = np.c_[orb.eta0, orb.v0]
    nz = np.linalg.norm(z0, axis=1)
    err = np.linalg.norm(np.c_[e, v] - z0, axis=1)
    return np.divide(err, nz, out=np.full(nz.shape, np.inf), where=nz > 0)


@dataclass(frozen=True)
class Evaluated:
    """Candidate points: orbits (admissible phase where there is one), verdicts, residuals, reasons."""

    orbits: Orbits
    adm: Admissibility
    good: np.ndarray
    r1: np.ndarray
    r2: np.ndarray
    why: np.ndarray

    @classmethod
    def concat(cls, parts) -> "Evaluated":
        parts = list(parts)
        if len(parts) == 1:
            return parts[0]
        return cls(Orbits.concat([p.orbits for p in parts]), Admissibility.concat([p.adm for p in parts]),
                   *[np.concatenate([getattr(p, f) for p in parts]) for f in ("good", "r1", "r2", "why")])


def _choose_phase(prob, P, co, samples=None):
    """Admissible responses at refined zeros: ``phi`` or ``phi + pi`` (the negated response).

    Also returns ``(max |R|, max |x_c|, R(T^I-), x_c(T^-))`` of each orbit on the
    coarse sampling (the same for both phases).
    """
    phi0 = phase(co)
    orb = orbits(prob, P[:, 0], P[:, 1], phi0, co=co)
    cm = coarse(orb)
    amplitudes = [np.abs(cm[0]).max(axis=1), np.abs(cm[1]).max(axis=1), -cm[0][:, -1], -cm[1][:, -1]]
    a0, a1 = check_both(orb, samples=samples, coarse_margins=cm)
    flip = a1.ok & ~a0.ok
    if flip.any():
        f = flip[:, None]
        orb = Orbits(prob, orb.T1, orb.T2, np.where(flip, phi0 + np.pi, phi0), np.where(f, -orb.eta0, orb.eta0),
                     np.where(f, -orb.v0, orb.v0), np.where(f, -orb.eta_s, orb.eta_s), np.where(f, -orb.v_s, orb.v_s))
    adm = Admissibility(*[np.where(flip, getattr(a1, k), getattr(a0, k)) for k in Admissibility.__dataclass_fields__])
    return orb, adm, a0.ok | a1.ok, amplitudes


def _evaluate_chunk(prob, P, samples) -> Evaluated:
    co = chunked_coefficients(prob, P[:, 0], P[:, 1])
    phi0 = phase(co)
    c, sn = np.cos(phi0), np.sin(phi0)
    r1 = np.abs(co.a1 * c + co.b1 * sn) / co.e1_scale
    r2 = np.abs(co.a2 * c + co.b2 * sn) / co.e2_scale
    orb, adm, ok, (s1, s2, f1, f2) = _choose_phase(prob, P, co, samples)
    # the residuals again, from the flow and relative to the orbit's own signal amplitudes: near a pole
    # the cos/sin parts of e1, e2 are huge and cancel, so the coefficient scales above can hide a miss
    # (from the coarse sampling of the admissibility check, whose last samples are at T^I and T^-)
    r1 = np.maximum(r1, np.abs(f1) / np.where(s1 > 0, s1, 1.0))
    r2 = np.maximum(r2, np.abs(f2) / np.where(s2 > 0, s2, 1.0))
    zero = (r1 < ZERO_TOL) & (r2 < ZERO_TOL)
    periodic = periodicity_error(orb) < PERIODIC_TOL
    why = np.where(~zero, NOT_A_ZERO, np.where(~periodic, NOT_PERIODIC,
                   np.where(ok, "", np.char.add("premature switch (", np.char.add(adm.reason.astype(str), ")")))))
    why = np.where(why == "premature switch (impact)", IMPACT_VELOCITY, why)
    return Evaluated(orb, adm, zero & periodic & ok, r1, r2, why)


def evaluate(prob: Problem, P: np.ndarray, progress: bool = False, desc: str = "checking points") -> Evaluated:
    """Everything about the points ``P`` (N, 2) on zero curves of ``G``.

    In chunks over threads (:func:`plbar.util.threads.map_chunks`); the sampling
    of the admissibility check is fixed for the whole batch, so the result does
    not depend on the chunks.  With ``progress``, a progress bar (``desc``)
    counts the chunks as they come in (the same chunks: the same bits).
    """
    ns = n_samples(prob, P.sum(axis=1)) if len(P) else 65
    m = prob.system.w1.size + prob.system.w2.size
    cap = max(16, int(SAMPLE_ELEMENTS // (ns * m)))        # memory: the dense sampling is (points, ns, modes)

    with progress_bar(len(P), progress and len(P) >= 2 * PAR_CHUNK, desc, "point") as bar:
        return Evaluated.concat(map_chunks(lambda a, b: _evaluate_chunk(prob, P[a:b], ns), len(P),
                                           min(PAR_CHUNK // 4, cap), cap, bar.update))
