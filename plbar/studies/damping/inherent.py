"""The impact's equivalent damping on top of inherent Rayleigh damping (issue 21).

One case solved for several Rayleigh ratios ``zeta`` (each ``(alpha, beta)`` from
:func:`plbar.rayleigh_from_ratio` at two periods): ``xi_eq`` of the impact (Eq. (22) on the
damped velocities), the Rayleigh ratio at the forcing frequency and their sum, per branch.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...app import Case, Result, solve
from ...errors import InputError
from ...model import rayleigh_from_ratio

__all__ = ["RATIOS", "DampedRun", "with_rayleigh", "ratio_table"]

RATIOS = (0.0, 0.01, 0.02, 0.05)   #: the Rayleigh ratios of the README figure


@dataclass(frozen=True)
class DampedRun:
    """One case solved with the Rayleigh ratio ``ratio`` at the periods ``at`` (``rayleigh = (alpha, beta)``)."""

    ratio: float
    at: tuple[float, float]
    rayleigh: tuple[float, float]
    result: Result

    @property
    def branches(self):
        """The paper's class (:attr:`plbar.Result.paper`)."""
        return self.result.paper

    def points(self) -> dict[str, np.ndarray]:
        """Every path point: ``T, xi, xi_total, zeta_rayleigh, dPL, viscous, stable`` (concatenated branches)."""
        br = self.branches
        cat = (lambda f: np.concatenate([f(b) for b in br])) if br else (lambda f: np.zeros(0))
        return {"T": cat(lambda b: b.T), "xi": cat(lambda b: b.xi), "xi_total": cat(lambda b: b.xi_total),
                "zeta_rayleigh": cat(lambda b: b.orbits[0].prob.system.rayleigh_ratio(2 * np.pi / b.T)),
                "dPL": cat(lambda b: b.dPL),
                "viscous": cat(lambda b: b.viscous), "stable": cat(lambda b: b.stable)}


def with_rayleigh(case: Case | None = None, ratios=RATIOS, at=None, progress: bool = False) -> list[DampedRun]:
    """Solve ``case`` once per Rayleigh ratio (0: undamped, the paper).

    Parameters
    ----------
    case : Case, optional
        The bar and load (default: the paper's chain); its own ``rayleigh`` is replaced.
    ratios : sequence of float
        Damping ratios in ``[0, 1)`` (0.02 for 2 %).
    at : (float, float), optional
        The two periods where each ratio holds; default ``(0.8 T0^I, 0.55 T0^II)``
        (8.1 and 12.1 for the default chain, bracketing its paths).
    """
    case = Case() if case is None else case
    if not isinstance(case, Case):
        raise InputError(f"case must be a plbar.Case, got {type(case).__name__}")
    if case.restitution:
        raise InputError(f"restitution = {case.restitution:g}: this study compares the paper's class (a plastic "
                         "impact, e = 0) with inherent damping; with rebounds: plbar survey --restitution E "
                         "--damping-ratio Z")
    if at is None:
        T0I, T0II = replace(case, rayleigh=None).problem().system.T0
        at = (0.8 * T0I, 0.55 * T0II)
    at = (float(at[0]), float(at[1]))
    runs = []
    for z in ratios:
        ab = rayleigh_from_ratio(z, *at)
        runs.append(DampedRun(float(z), at, ab, solve(replace(case, rayleigh=ab, signatures="paper"),
                                                      progress=progress)))
    return runs


def ratio_table(runs: list[DampedRun], stable_only: bool = False) -> list[dict]:
    """Per ratio: points, the largest ``xi_eq`` and its period, the mean ``xi_eq`` and ``xi_total`` there."""
    rows = []
    for r in runs:
        p = r.points()
        m = p["stable"] if stable_only else np.ones(p["T"].size, bool)
        if not m.any():
            rows.append({"ratio": r.ratio, "points": 0})
            continue
        i = np.flatnonzero(m)[int(np.argmax(p["xi"][m]))]
        rows.append({"ratio": r.ratio, "points": int(m.sum()), "branches": len(r.branches),
                     "xi_max": float(p["xi"][i]), "T_at_max": float(p["T"][i]),
                     "xi_total_at_max": float(p["xi_total"][i]), "xi_mean": float(p["xi"][m].mean()),
                     "T_range": [float(p["T"][m].min()), float(p["T"][m].max())]})
    return rows
