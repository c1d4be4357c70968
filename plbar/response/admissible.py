"""Admissibility of periodic responses: no premature switch (paper Sec. 2.3).

A response found from the switch residuals is physical only if

* the contact stays in compression on ``(0, T^I)``: ``-R(t) >= 0`` (Eq. (4));
* the gap stays open on ``(T^I, T)``: ``x_c(t) <= 0`` (Eq. (5));
* the contact node comes back to the wall: ``v_c(T^-) > 0``.

The closed-form response is sampled densely (relative to the highest modal
frequency), every sampled local extremum that comes near the bound is
refined with a bounded scalar minimiser, so the check is exact up to a
tolerance relative to the response amplitude.  Orbits that touch a bound
(impact velocity or margin within the tolerance band) are flagged grazing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..util.batch import Batch
from ..util.reprs import build, count

from .orbit import Orbits

__all__ = ["Admissibility", "check", "TOL", "GRAZE", "GRAZE_V"]

TOL = 1e-9      #: violation tolerance, relative to the response amplitude
GRAZE = 1e-6    #: grazing band of the margins, relative to the response amplitude
GRAZE_V = 1e-3  #: grazing band of the impact velocity, relative to max |v_c|


@dataclass(frozen=True)
class Admissibility(Batch):
    """Result of :func:`check`, arrays of shape ``(P,)``.

    Attributes
    ----------
    ok : bool
        No premature switch and the impact velocity is towards the wall.
    grazing : bool
        An admissible orbit touching a bound (impact velocity or a margin
        within ``GRAZE`` of zero, relative).
    v_impact : float
        Contact velocity just before the impact, ``v_c(T^-)``.
    min_reaction, max_gap : float
        Smallest ``-R`` on ``(0, T^I)`` and largest ``x_c`` on ``(T^I, T)``,
        both relative to their segment's amplitude.
    reason : str
        ``"ok"``, ``"reaction"``, ``"gap"`` or ``"impact"``.
    """

    ok: np.ndarray
    grazing: np.ndarray
    v_impact: np.ndarray
    min_reaction: np.ndarray
    max_gap: np.ndarray
    reason: np.ndarray

    def __repr__(self) -> str:
        why, k = np.unique(np.asarray(self.reason, str), return_counts=True)
        return build("Admissibility", {"P": np.size(self.ok), "ok": count(self.ok), "grazing": count(self.grazing),
                                       "reasons": "{" + ", ".join(f"{w}: {int(c)}" for w, c in zip(why, k)) + "}"})


def n_samples(prob, T) -> int:
    """Samples per segment that resolve every response with periods ``T`` (array): 8 per half period."""
    T = np.asarray(T, float)
    fmax = max(float(prob.system.w2.max()), float((2 * np.pi / T).max()))
    return int(np.clip(np.ceil(8 * fmax * float(np.max(T)) / np.pi) + 33, 65, 6000))


def _refined_min(fun, tau, g, scale, rounds: int = 5, m: int = 17):
    """Minimum of ``fun`` near every sampled local minimum of ``g`` that comes close to 0.

    All candidates are refined together: each round samples ``m`` points on
    the bracket around the current minimum and shrinks the bracket to the
    neighbours of the best one (``rounds`` rounds shrink it by ``(2/(m-1))^rounds``).
    ``fun(p, t)`` evaluates rows ``p`` (C,) at times ``t`` (C, m).
    """
    P, K = g.shape
    out = g.min(axis=1)
    near = g < 0.05 * scale[:, None]
    loc = np.zeros_like(near)
    loc[:, 1:-1] = (g[:, 1:-1] <= g[:, :-2]) & (g[:, 1:-1] <= g[:, 2:])
    loc[:, 0] = g[:, 0] <= g[:, 1]
    loc[:, -1] = g[:, -1] <= g[:, -2]
    p, k = np.nonzero(near & loc)
    if p.size == 0:
        return out
    lo = tau[p, np.maximum(k - 1, 0)]
    hi = tau[p, np.minimum(k + 1, K - 1)]
    u = np.linspace(0.0, 1.0, m)
    best = g[p, k]
    for _ in range(rounds):
        t = lo[:, None] + (hi - lo)[:, None] * u
        v = fun(p, t)
        j = np.argmin(v, axis=1)
        best = np.minimum(best, v[np.arange(p.size), j])
        step = (hi - lo) / (m - 1)
        c = t[np.arange(p.size), j]
        lo, hi = np.maximum(c - step, lo), np.minimum(c + step, hi)
    np.minimum.at(out, p, best)
    return out


def _margins(orb: Orbits, u):
    tI = orb.T1[:, None] * u
    tII = orb.T2[:, None] * u
    xc, vc = orb.gap_signals(tII)
    return tI, tII, orb.reaction_margin(tI), -xc, vc


def check(orb: Orbits, tol: float = TOL, graze: float = GRAZE) -> Admissibility:
    """Admissibility of every orbit (exact up to ``tol`` relative to its amplitude)."""
    return check_both(orb, tol, graze, both=False)[0]


COARSE = np.linspace(0.0, 1.0, 65)   #: the coarse sampling of each segment (fractions of T^I, T^II)


def coarse(orb: Orbits):
    """Margins on the coarse sampling :data:`COARSE`: ``-R`` on state I, ``-x_c`` and ``v_c`` on state II.

    Each of shape ``(P, 65)``; the last column is at the switch (``T^I``, ``T^-``).
    """
    return _margins(orb, COARSE)[2:]


def check_both(orb: Orbits, tol: float = TOL, graze: float = GRAZE, both: bool = True, samples: int | None = None,
               coarse_margins=None):
    """Admissibility of every orbit and (if ``both``) of its negation (``phi + pi``).

    The response at ``phi + pi`` is the negated response, so its margins are
    the negated margins: one evaluation serves both.  A coarse sampling first
    rejects the orbits that violate a bound grossly; the dense sampling and
    the refinement run only on the rest.

    ``samples`` (per segment, default :func:`n_samples` of the batch) is
    given by callers that split one batch into chunks, so that the result
    does not depend on the chunking; ``coarse_margins`` (:func:`coarse`) by
    callers that use them too.

    Returns
    -------
    list of Admissibility
        For ``orb`` and, if ``both``, for the negated orbits.
    """
    signs = (1.0, -1.0) if both else (1.0,)
    margins = coarse(orb) if coarse_margins is None else coarse_margins
    out, alive = _coarse_verdicts(margins, signs)
    cand = np.flatnonzero(np.any(alive, axis=0))
    if cand.size:
        _dense_verdicts(orb.take(cand), cand, alive, signs, out, tol, graze, samples)
    return [Admissibility(**{f: np.asarray(d[f]) for f in d}) for d in out]


def _coarse_verdicts(margins, signs):
    """Rough verdicts from the coarse sampling, and which orbits need the dense check, per sign."""
    mI0, gII0, vc0 = margins
    P = mI0.shape[0]
    s0I = np.maximum(np.abs(mI0).max(axis=1), 1e-300)[:, None]
    s0II = np.maximum(np.abs(gII0).max(axis=1), 1e-300)[:, None]
    out, alive = [], []
    for sg in signs:
        rough_I = (sg * mI0 / s0I).min(axis=1)
        rough_II = (sg * gII0 / s0II).min(axis=1)
        alive.append((rough_I > -1e-3) & (rough_II > -1e-3) & (sg * vc0[:, -1] > 0))
        out.append(dict(ok=np.zeros(P, bool), grazing=np.zeros(P, bool), v_impact=sg * vc0[:, -1],
                        min_reaction=rough_I, max_gap=-rough_II,
                        reason=np.where(rough_I <= -1e-3, "reaction",
                                        np.where(rough_II <= -1e-3, "gap", "impact")).astype(object)))
    return out, np.array(alive)


def _dense_verdicts(sub: Orbits, cand, alive, signs, out, tol, graze, samples) -> None:
    """Exact verdicts (dense sampling, refined minima) for the candidate orbits ``sub``; fills ``out``."""
    u = np.linspace(0.0, 1.0, samples or n_samples(sub.prob, sub.T))
    tI, tII, mI, gII, vc = _margins(sub, u)
    sI = np.maximum(np.abs(mI).max(axis=1), 1e-300)
    sII = np.maximum(np.abs(gII).max(axis=1), 1e-300)
    vs = np.maximum(np.abs(vc).max(axis=1), 1e-300)
    mid = (u > 0.02) & (u < 0.98)
    for k, sg in enumerate(signs):
        idx = np.flatnonzero(alive[k][cand])
        if not idx.size:
            continue
        sb = sub.take(idx)

        def fI(p, t, sb=sb, sg=sg):
            return sg * sb.take(p).reaction_margin(t)

        def fII(p, t, sb=sb, sg=sg):
            return -sg * sb.take(p).gap(t)

        minI = _refined_min(fI, tI[idx], sg * mI[idx], sI[idx]) / sI[idx]
        minII = _refined_min(fII, tII[idx], sg * gII[idx], sII[idx]) / sII[idx]
        v_imp = sg * vc[idx, -1]
        okI, okII, okV = minI >= -tol, minII >= -tol, v_imp > tol * vs[idx]
        ok = okI & okII & okV
        touchI = ((sg * mI[idx] / sI[idx, None] < graze) & mid).any(axis=1)
        touchII = ((sg * gII[idx] / sII[idx, None] < graze) & mid).any(axis=1)
        j, d = cand[idx], out[k]
        d["ok"][j] = ok
        d["grazing"][j] = ok & ((v_imp < GRAZE_V * vs[idx]) | touchI | touchII)
        d["v_impact"][j] = v_imp
        d["min_reaction"][j] = minI
        d["max_gap"][j] = -minII
        d["reason"][j] = np.where(~okI, "reaction", np.where(~okII, "gap", np.where(~okV, "impact", "ok")))
