"""The periodic responses of every signature in a run: the search window, the extra seeds, the table rows, the summary.

:func:`hybrid_branches` is what :func:`plbar.solve` calls after the paper's class
(:func:`plbar.find_paths`), for ``Case.signatures`` ``"default"`` or ``"all"``
(:func:`plbar.hybrid.find_hybrid`): besides the seeds of the structure (the zero-dwell
class, period doublings, admissibility ends), the periodic motions of a simulation from
rest across the window (``"default"``: 81 forcing periods, 600 periods each, the last 60
recorded; ``"all"``: 161, 1,000 and 100, as ``plbar survey``, and orbits up to ``m = 8``)
are polished (:func:`plbar.hybrid.from_motion`) and followed.  Their rows
join the paper's in ``paths.csv`` with the columns ``m, k, signature,
loss_per_T, durations``; ``T1`` and ``T2`` are then the total stuck and free
time over the orbit (``m`` periods) and ``dPL`` the loss over the orbit.
"""

from __future__ import annotations

import numpy as np

from ..hybrid import NotConverged, canonical, find_hybrid, from_motion
from ..motion import COMPILE_NOTE, compiled, padded, run, steady
from ..paths import Paths
from ..util.progress import message, progress_bar

__all__ = ["hybrid_branches", "hybrid_window", "hybrid_rows", "hybrid_summary", "simulated_seeds", "SEED_PERIODS"]

#: forcing periods, periods simulated, periods recorded of the seeding simulation, per kind
SEED_PERIODS = {"default": (81, 600, 60), "all": (161, 1000, 100)}


def hybrid_window(paths: Paths) -> tuple[float, float]:
    """Forcing periods searched: from ``T0^I / 2`` to the top of the paper's search domain ``max T1 + max T2``."""
    T0I, _ = paths.prob.system.T0
    return 0.5 * T0I, float(paths.domain.T1[1] + paths.domain.T2[1])


def simulated_seeds(paths: Paths, window, kinds: str = "default", progress: bool = False) -> list:
    """Orbits polished from the periodic motions of a simulation from rest across the window."""
    prob = paths.prob
    num, periods, record = SEED_PERIODS[kinds]
    T = np.linspace(window[0], window[1], num)
    pad = padded(prob)
    if progress and not compiled(pad, accounts=False):
        message(f"plbar: {COMPILE_NOTE}")
    with progress_bar(periods, progress, f"signatures: simulating {num} forcing periods from rest", "period") as bar:
        r = run(pad, T, 0.0, periods, record, progress=bar.update, accounts=False)     # the switches only
    s = steady(r, tol=1e-4)
    out = []
    first = periods - record
    for b in np.flatnonzero(s.kind == 0):
        sel = r.events["traj"] == b
        te, ke = r.events["time"][sel], r.events["kind"][sel]
        after = te >= first * T[b]
        try:
            out.append(from_motion(prob, float(T[b]), int(s.m[b]), first * T[b], r.strobe_x[b, 0], r.strobe_v[b, 0],
                                   int(r.strobe_state[b, 0]), te[after], ke[after]))
        except (NotConverged, ValueError, np.linalg.LinAlgError):
            continue
    return out


def hybrid_branches(paths: Paths, kinds: str, progress: bool = False) -> list:
    """The branches of every signature but the paper's class (:func:`plbar.hybrid.find_hybrid`).

    With ``progress``, two phases on stderr: the seeding simulation (periods done) and the curves followed
    (their number grows as bifurcations seed new ones, so the bar counts them without a total).
    """
    if kinds == "paper":
        return []
    window = hybrid_window(paths)
    seeds = simulated_seeds(paths, window, kinds, progress)
    with progress_bar(None, progress, "signatures: following curves", "curve") as bar:
        return find_hybrid(paths.prob, window, paths.branches, seeds, kinds=kinds,
                           m_max=4 if kinds == "default" else 8, progress=lambda: bar.update(1))


def hybrid_rows(branches, first_id: int) -> dict:
    """The ``paths.csv`` columns of the hybrid branches (ids from ``first_id``)."""
    cols: dict = {}
    for j, b in enumerate(branches):
        for o in b.orbits:
            _, d, phi = canonical(o)                 # the durations and phase of the canonical rotation
            row = {"branch": first_id + j, "T1": float(d[0::2].sum()), "T2": float(d[1::2].sum()),
                   "phi": phi, "T": o.T, "dPL": o.dPL, "xi": o.xi, "grazing": 0, "omega": 2 * np.pi / o.T,
                   "xi_w": o.xi_w, "viscous_loss": o.viscous, "zeta_rayleigh": o.xi_total - o.xi, "xi_total": o.xi_total, "m": o.sig.m, "k": o.sig.k, "signature": b.label, "loss_per_T": o.loss_per_T,
                   "durations": ";".join(f"{x:.17g}" for x in d), "max_abs_xc": o.amplitude}
            for k, v in row.items():
                cols.setdefault(k, []).append(v)
        for k, v in (("stable", b.stable.astype(int)), ("max_abs_multiplier", b.max_abs_multiplier)):
            cols.setdefault(k, []).extend(v.tolist())
    return cols


def hybrid_summary(branches, first_id: int) -> list[dict]:
    """One entry per hybrid branch for ``summary.json``."""
    out = []
    for j, b in enumerate(branches):
        out.append({"branch": first_id + j, "signature": b.label, "m": b.sig.m, "k": b.sig.k, "points": len(b),
                    "T_range": [float(b.T.min()), float(b.T.max())],
                    "xi_range": [float(b.xi.min()), float(b.xi.max())],
                    "loss_per_T_range": [float(b.loss_per_T.min()), float(b.loss_per_T.max())],
                    "stable_points": int(b.stable.sum()),
                    "events": [{"kind": e["kind"], "index": int(e["index"]), "T": float(e["T"])} for e in b.events]})
    return out
