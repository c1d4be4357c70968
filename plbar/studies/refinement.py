"""Mesh-refinement study (paper Sec. 4.3, Fig. 9): the same case for a list of N.

One task per (series, N, load position).  A *series* is a bar family:
``"chain"`` (the paper's mass-spring chain, ``L = N``) or
``"fe-<P1|P2>-<lumped|consistent>"`` (uniform FE bar, ``L = 1``).  Loads are
unit point forces at fixed fractions ``s / L`` of the bar, so the same
physical load is compared across N.

Tables written by :func:`write_refine_tables`:

``refine.csv``
    Per series, N, load fraction and family (:mod:`plbar.families`, plus
    ``"all"`` = every branch with at least ``min_points`` points): the
    fundamental periods, the family's period range, and the range and maximum
    of ``xi_eq``.  Periods are also given divided by ``L``.
``refine_max.csv``
    Per series, N and family: the maximum over the load fractions.
``refine_rates.json``
    Observed convergence rates: for each series, family and quantity
    ``q(N)`` in ``T0_I/L, T0_II/L, Tmin/L, Tmax/L, xi_max``, the slope of
    ``log |q(N) - q(N_fin)|`` against ``log N`` over ``N <= N_fin / 2``
    (``N_fin`` the finest N), as ``{"rate": p, "why": ""}``, or
    ``{"rate": null, "why": reason}`` where it cannot be computed (fewer than 3
    such sizes, a family missing at some N, no monotone decrease).  Missing
    values are empty fields in the CSV files (never ``nan``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .families import FAMILIES, assign_families
from ..errors import InputError
from ..util.files import write_csv, write_json
from .study import Study
from .tasks import branch_arrays, solve_task

__all__ = ["refine_study", "parse_series", "RefineTables", "refine_tables", "write_refine_tables",
           "observed_rate", "REFINE_HEADER"]

REFINE_HEADER = ["series", "n", "frac", "family", "T0_I", "T0_II", "L", "branches", "points", "T_min", "T_max",
                 "xi_min", "xi_max", "T_at_max", "T0_I_L", "T0_II_L", "T_min_L", "T_max_L"]
MAX_HEADER = ["series", "n", "family", "T0_I", "T0_II", "L", "T_min", "T_max", "xi_max", "frac_at_max",
              "T_at_max"]


def parse_series(name: str) -> dict:
    """Case fields of a series name (``chain``, ``fe-P1-lumped``, ``fe-P2-consistent`` ...)."""
    if name == "chain":
        return {"model": "chain"}
    parts = name.split("-")
    if len(parts) != 3 or parts[0] != "fe" or parts[1] not in ("P1", "P2") or parts[2] not in ("lumped",
                                                                                               "consistent"):
        raise InputError(f"series = {name!r} must be 'chain' or 'fe-<P1|P2>-<lumped|consistent>'")
    return {"model": "fe", "element": parts[1], "mass": parts[2]}


def refine_study(ns, series=("chain",), fracs=(0.5,), grid=(200, 200), T2_frac=None) -> Study:
    """The tasks of a refinement study.

    Parameters
    ----------
    ns : sequence of int
        Masses (chain) / elements (FE bar).
    series : sequence of str
        See :func:`parse_series`.
    fracs : sequence of float
        Load positions ``s / L`` in ``(0, 1)`` (one task each).
    grid : (int, int) or dict
        Scan grid, or a mapping ``N -> (n1, n2)`` (coarser grids for large N).
    T2_frac : (float, float), optional
        Restrict the ``T^II`` search to ``[lo, hi] * T0^II / 2``.
    """
    tasks = []
    for ser in series:
        base = parse_series(ser)
        for n in ns:
            g = grid.get(n, grid.get(int(n))) if isinstance(grid, dict) else grid
            L = float(n) if base["model"] == "chain" else 1.0
            for fr in fracs:
                t = {"series": ser, "frac": float(fr),
                     "case": {**base, "n": int(n), "grid": [int(v) for v in g],
                              "load_points": [[float(fr) * L, 1.0]]}}
                if T2_frac:
                    t["T2_frac"] = [float(v) for v in T2_frac]
                tasks.append(t)
    params = {"ns": [int(n) for n in ns], "series": list(series), "fracs": [float(f) for f in fracs],
              "T2_frac": list(T2_frac) if T2_frac else None}
    return Study("refine", solve_task, tuple(tasks), params)


def observed_rate(ns, q) -> dict:
    """Observed convergence rate of ``q(N)`` against the finest N: ``{"rate": p or None, "why": reason}``.

    The slope of ``log |q(N) - q(N_fin)|`` against ``log N`` over ``N <= N_fin / 2``;
    where it cannot be computed, ``rate`` is None and ``why`` says why.
    """
    ns = np.asarray(ns, float)
    q = np.asarray(q, float)
    ok = np.isfinite(q)
    if ok.sum() < ns.size:
        miss = ", ".join(f"{int(n)}" for n in ns[~ok])
        if ok.sum() < 4:
            return {"rate": None, "why": f"the quantity is missing at N = {miss} (no branch of the family there); "
                                         "a rate needs it at >= 4 sizes"}
    ns, q = ns[ok], q[ok]
    if ns.size < 4:
        return {"rate": None, "why": f"only {ns.size} size(s); a rate needs >= 4 (3 against the finest)"}
    o = np.argsort(ns)
    ns, q = ns[o], q[o]
    sel = ns <= ns[-1] / 2
    err = np.abs(q[sel] - q[-1])
    if sel.sum() < 3:
        return {"rate": None, "why": f"only {int(sel.sum())} size(s) at most half the finest N = {int(ns[-1])}; "
                                     "a rate needs 3"}
    if np.any(err <= 0):
        return {"rate": None, "why": "the value equals the finest one at a coarser N (no error to fit)"}
    if np.any(np.diff(err) >= 0):
        return {"rate": None, "why": "the differences to the finest N do not decrease monotonically "
                                     "(not in the asymptotic range)"}
    return {"rate": float(-np.polyfit(np.log(ns[sel]), np.log(err), 1)[0]), "why": ""}


@dataclass(frozen=True)
class RefineTables:
    rows: dict
    maxima: dict
    rates: dict


def refine_tables(tasks, results, tol: float = 0.1, min_points: int = 4) -> RefineTables:
    """Assemble the refinement tables from task results (in task order)."""
    rows = {k: [] for k in REFINE_HEADER}
    for task, res in zip(tasks, results):
        brs = [branch_arrays(b) for b in res["branches"]]
        labels = assign_families([(b["T"].min(), b["T"].max()) for b in brs], [b["T"].size for b in brs],
                                 res["T0_I"], res["T0_II"], tol, min_points)
        L = res["length"]
        for fam in FAMILIES + ("all",):
            sel = [b for b, f in zip(brs, labels) if (f == fam if fam != "all" else b["T"].size >= min_points)]
            if sel:
                T = np.concatenate([b["T"] for b in sel])
                xi = np.concatenate([b["xi"] for b in sel])
                i = int(np.argmax(xi))
                v = dict(branches=len(sel), points=T.size, T_min=T.min(), T_max=T.max(), xi_min=xi.min(),
                         xi_max=xi[i], T_at_max=T[i])
            else:
                v = dict(branches=0, points=0, T_min=np.nan, T_max=np.nan, xi_min=np.nan, xi_max=np.nan,
                         T_at_max=np.nan)
            v.update(series=task["series"], n=task["case"]["n"], frac=task["frac"], family=fam,
                     T0_I=res["T0_I"], T0_II=res["T0_II"], L=L, T0_I_L=res["T0_I"] / L, T0_II_L=res["T0_II"] / L,
                     T_min_L=v["T_min"] / L, T_max_L=v["T_max"] / L)
            for k in REFINE_HEADER:
                rows[k].append(v[k])
    maxima = _maxima(rows)
    return RefineTables(rows, maxima, _rates(maxima))


def _maxima(rows: dict) -> dict:
    out = {k: [] for k in MAX_HEADER}
    keys = []
    for s, n, f in zip(rows["series"], rows["n"], rows["family"]):
        if (s, n, f) not in keys:
            keys.append((s, n, f))
    for s, n, f in keys:
        idx = [i for i, k in enumerate(zip(rows["series"], rows["n"], rows["family"])) if k == (s, n, f)]
        xs = np.array([rows["xi_max"][i] for i in idx], float)
        j = idx[int(np.nanargmax(xs))] if np.isfinite(xs).any() else idx[0]
        v = {"series": s, "n": n, "family": f, "T0_I": rows["T0_I"][j], "T0_II": rows["T0_II"][j],
             "L": rows["L"][j], "T_min": np.nanmin([rows["T_min"][i] for i in idx]) if np.isfinite(xs).any()
             else np.nan, "T_max": np.nanmax([rows["T_max"][i] for i in idx]) if np.isfinite(xs).any() else np.nan,
             "xi_max": rows["xi_max"][j], "frac_at_max": rows["frac"][j], "T_at_max": rows["T_at_max"][j]}
        for k in MAX_HEADER:
            out[k].append(v[k])
    return out


def _rates(mx: dict) -> dict:
    out: dict = {}
    for s in dict.fromkeys(mx["series"]):
        for f in dict.fromkeys(mx["family"]):
            idx = [i for i, (a, b) in enumerate(zip(mx["series"], mx["family"])) if (a, b) == (s, f)]
            ns = [mx["n"][i] for i in idx]
            L = np.array([mx["L"][i] for i in idx], float)
            q = {"T0_I/L": np.array([mx["T0_I"][i] for i in idx]) / L,
                 "T0_II/L": np.array([mx["T0_II"][i] for i in idx]) / L,
                 "T_min/L": np.array([mx["T_min"][i] for i in idx], float) / L,
                 "T_max/L": np.array([mx["T_max"][i] for i in idx], float) / L,
                 "xi_max": np.array([mx["xi_max"][i] for i in idx], float)}
            out.setdefault(s, {})[f] = {k: observed_rate(ns, v) for k, v in q.items()}
    return out


def write_refine_tables(folder, tables: RefineTables) -> dict[str, Path]:
    """Write ``refine.csv``, ``refine_max.csv`` and ``refine_rates.json`` (atomically)."""
    folder = Path(folder)
    g = "%.17g"
    fr = ["%s", "%d", g, "%s", g, g, g, "%d", "%d"] + [g] * 9
    fm = ["%s", "%d", "%s"] + [g] * 8
    return {
        "refine": write_csv(folder / "refine.csv", REFINE_HEADER, [tables.rows[k] for k in REFINE_HEADER], fr),
        "max": write_csv(folder / "refine_max.csv", MAX_HEADER, [tables.maxima[k] for k in MAX_HEADER], fm),
        "rates": write_json(folder / "refine_rates.json", tables.rates),
    }
