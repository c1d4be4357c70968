"""The tables of a refinement study: one row per family and mesh, observed rates, continuum limits.

``refine.csv``
    One row per series, family and N (:data:`REFINE_HEADER`): the fundamental
    periods and the anchor (divided by the length ``L``), the family's curve
    pieces, admissible stretches and points, the period range of its main
    stretch (the one holding the largest ``xi_eq``) and of all its admissible
    points, the largest ``xi_eq`` and
    the response there (``T``, ``T^I``, ``Delta_PL``, ``v_c``), the impact mass
    ``S`` and, with an end mass ``M_e``, ``Delta_PL / (M_e v_c^2 / 2)`` there (which
    equals ``S / M_e`` exactly), the status (seed, tracked, split, inadmissible,
    ended) and the notes.  A missing value is an empty field, never ``nan``.
``refine_rates.json``
    Per series and family, per quantity: the observed orders of successive
    triples, the Richardson limit and its error estimate (or ``why`` not), and
    where the continuum value is known in closed form (the fundamental periods
    of a uniform bar, ``S / M_e -> 1``) the orders against it; for ``xi_max`` also
    the better of a power law and ``a / (b + ln N)``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...util.files import write_csv, write_json
from .convergence import converge, known_limit
from .decay import decay_fit
from .anchors import family_label
from .track import admissible_runs_of

__all__ = ["REFINE_HEADER", "family_rows", "refine_rows", "convergence_of", "continuum_periods", "write_refine",
           "family_label"]

REFINE_HEADER = ["series", "family", "n", "h", "dofs", "status", "pieces", "stretches", "points", "admissible",
                 "T0_I_L", "T0_II_L", "A_L", "T_min_L", "T_max_L", "T_mid_T0I", "T_spread_T0I", "T_all_min_L",
                 "T_all_max_L", "xi_max", "T_at_max_L", "T1_at_max_L", "dPL_at_max", "v_c_at_max", "impact_mass",
                 "end_mass", "loss_ratio", "evaluations", "time", "notes"]
_STR = {"series", "family", "status", "notes"}
_INT = {"n", "dofs", "pieces", "stretches", "points", "admissible", "evaluations"}


def _cat(level: dict, key: str) -> np.ndarray:
    parts = [np.asarray(p[key], float) for p in level["pieces"]]
    return np.concatenate(parts) if parts else np.zeros(0)


def _main_stretch(level: dict):
    """Indices (into the concatenated points) of the admissible stretch holding the largest ``xi_eq``, and all runs."""
    best, off, runs = None, 0, 0
    for p in level["pieces"]:
        xi = np.asarray(p["xi"], float)
        for r in admissible_runs_of(p["good"]):
            runs += 1
            m = np.nanmax(xi[r])
            if best is None or m > best[0]:
                best = (m, r + off)
        off += len(p["T1"])
    return (best[1] if best else np.zeros(0, int)), runs


def level_row(level: dict) -> dict:
    """The table row of one level (floats; ``nan`` where a value does not exist).

    The family's *main stretch* is its admissible stretch that holds the largest
    ``xi_eq``: its period range is ``T_min_L, T_max_L`` (``T_mid_T0I``,
    ``T_spread_T0I``); ``T_all_min_L, T_all_max_L`` span every admissible point.
    """
    L, T0 = level["length"], level["T0_I"]
    good = _cat(level, "good") > 0
    T1, T2, xi = _cat(level, "T1"), _cat(level, "T2"), _cat(level, "xi")
    T = T1 + T2
    main, runs = _main_stretch(level)
    row = {k: level[k] for k in ("n", "h", "dofs", "length", "status", "impact_mass", "end_mass", "evaluations",
                                 "time")}
    row.update(pieces=len(level["pieces"]), stretches=runs, points=int(T.size), admissible=int(good.sum()),
               T0_I_L=T0 / L, T0_II_L=level["T0_II"] / L, A_L=level["A"] / L, notes="; ".join(level["notes"]))
    nan = float("nan")
    row.update(T_min_L=nan, T_max_L=nan, T_all_min_L=nan, T_all_max_L=nan, T_mid_T0I=nan, T_spread_T0I=nan,
               xi_max=nan, T_at_max_L=nan, T1_at_max_L=nan, dPL_at_max=nan, v_c_at_max=nan, loss_ratio=nan)
    if main.size:
        i = main[np.nanargmax(xi[main])]
        dpl, vc = _cat(level, "dPL")[i], _cat(level, "v_c")[i]
        lo, hi = T[main].min(), T[main].max()
        row.update(T_min_L=lo / L, T_max_L=hi / L, T_all_min_L=T[good].min() / L, T_all_max_L=T[good].max() / L,
                   T_mid_T0I=0.5 * (lo + hi) / T0, T_spread_T0I=(hi - lo) / T0, xi_max=xi[i], T_at_max_L=T[i] / L,
                   T1_at_max_L=T1[i] / L, dPL_at_max=dpl, v_c_at_max=vc)
        if level["end_mass"] > 0 and vc != 0:
            row["loss_ratio"] = dpl / (0.5 * level["end_mass"] * vc * vc)
    return row


def family_rows(series: str, family: str, chain: list[dict]) -> list[dict]:
    """The rows of one family, coarse to fine."""
    return [{"series": series, "family": family, **level_row(lv)} for lv in chain]


def refine_rows(results) -> list[dict]:
    """All rows of the task results of a refinement study (task order, then family, then N)."""
    rows = []
    for r in results:
        chains = r["chains"]
        for k, chain in enumerate(chains):
            rows += family_rows(r["series"], family_label(r["family"], k, len(chains)), chain)
    return rows


def continuum_periods(level: dict, base: dict) -> tuple[float | None, float | None]:
    """``T0^I / L`` and ``T0^II / L`` of the continuous uniform bar (None where the bar is not one).

    State I is the bar fixed at both ends: ``T0^I = 2 L / c``.  State II is the
    bar with the end mass ``M_e = mu rho A L`` free: ``T0^II = 2 pi L / (c x)`` with
    ``x tan x = 1 / mu`` (``4 L / c`` without an end mass).  ``c = sqrt(EA / rhoA)``
    (``sqrt(k / m)`` per unit spacing for the chain, whose own ``m / 2`` at the
    contact is a fraction ``1 / (2 N)`` of its mass and vanishes in the limit).
    """
    from scipy.optimize import brentq  # on use: importing scipy.optimize takes 0.13 s

    if base.get("model", "chain") == "chain":
        c = math.sqrt(base.get("k", 1.0) / base.get("m", 1.0))
        mu = level["end_mass"] / (level["length"] * base.get("m", 1.0))
    else:
        if base.get("point_masses"):
            return None, None
        c = math.sqrt(base.get("EA", 1.0) / base.get("rhoA", 1.0))
        mu = level["end_mass"] / (level["length"] * base.get("rhoA", 1.0))
    T0I = 2.0 / c
    if mu <= 1e-15:
        return T0I, 4.0 / c
    x = brentq(lambda v: v * math.tan(v) - 1.0 / mu, 1e-12, math.pi / 2 - 1e-15, xtol=1e-15, rtol=1e-15)
    return T0I, 2 * math.pi / (c * x)


def _expected(base: dict) -> float:
    return 4.0 if base.get("element") == "P2" else 2.0


def convergence_of(rows: list[dict], base: dict) -> dict:
    """Observed rates of one family's quantities (``rows`` coarse to fine): ``{quantity: Convergence}``.

    Against exact limits where the continuum gives one (and, for the periods and
    ``S / M_e``, also by Richardson from successive triples, whose limit must
    agree): the fundamental periods of a uniform bar, ``S / M_e -> 1``, the
    spread of the family's main stretch (``-> 0``, the paper's "could shrink to a
    single point") and ``xi_max -> 0`` (the denominator of Eq. (22) grows like
    ``ln N`` on the velocity jump an impact leaves in the bar); Richardson (limit
    unknown) for the rest.
    """
    n = np.array([r["n"] for r in rows], int)
    h = 1.0 / n
    col = {k: np.array([r[k] for r in rows], float) for k in ("T0_I_L", "T0_II_L", "T_min_L", "T_max_L",
                                                             "T_mid_T0I", "T_spread_T0I", "xi_max", "v_c_at_max",
                                                             "dPL_at_max")}
    out = {}
    for q, L in zip(("T0_I_L", "T0_II_L"), continuum_periods(rows[-1], base)):
        out[q] = known_limit(q, h, col[q], L, _expected(base), n=n) if L is not None else \
            converge(q, h, col[q], _expected(base), n=n)
        out[q + " (Richardson)"] = converge(q + " (Richardson)", h, col[q], _expected(base), n=n)
    me = np.array([r["end_mass"] for r in rows], float)
    if np.all(me > 0):
        S = np.array([r["impact_mass"] for r in rows], float) / me
        out["S/M_e"] = known_limit("S/M_e", h, S, 1.0, 1.0, n=n)
        out["S/M_e (Richardson)"] = converge("S/M_e (Richardson)", h, S, 1.0, n=n)
    out["T_spread_T0I"] = known_limit("T_spread_T0I", h, col["T_spread_T0I"], 0.0, n=n)
    out["xi_max"] = known_limit("xi_max", h, col["xi_max"], 0.0, n=n)
    for q in ("T_mid_T0I", "T_min_L", "T_max_L", "v_c_at_max", "dPL_at_max"):
        out[q] = converge(q, h, col[q], n=n)
    return out


def decay_of(rows: list[dict]) -> dict:
    """The better of ``xi ~ C h^p`` and ``xi ~ a / (b + ln N)`` for the family's largest ``xi_eq``."""
    n = np.array([r["n"] for r in rows], float)
    xi = np.array([r["xi_max"] for r in rows], float)
    ok = np.isfinite(xi) & (xi > 0)
    return decay_fit(1.0 / n[ok], xi[ok], name="xi_max").as_dict()


def _csv_columns(rows: list[dict]):
    cols, fmts = [], []
    for k in REFINE_HEADER:
        v = [r[k] for r in rows]
        if k in _STR:
            cols.append(np.array([str(x).replace(",", ";") for x in v], object))
            fmts.append("%s")
        elif k in _INT:
            cols.append(np.array(v, int))
            fmts.append("%d")
        else:
            cols.append(np.array(v, float))
            fmts.append("%.12g")
    return cols, fmts


def write_refine(folder, rows: list[dict], rates: dict) -> dict[str, Path]:
    """Write ``refine.csv`` and ``refine_rates.json`` into ``folder`` (atomically; no nan in either)."""
    folder = Path(folder)
    cols, fmts = _csv_columns(rows)
    return {"refine": write_csv(folder / "refine.csv", REFINE_HEADER, cols, fmts, allow_nan=True),
            "rates": write_json(folder / "refine_rates.json", rates)}
