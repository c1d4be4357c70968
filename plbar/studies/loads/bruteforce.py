"""Load-position sweep (paper Sec. 4.2, Figs. 7-9).

One task per load case: a unit point force at ``s`` (any ``s`` in ``(0, L)``,
through the shape functions, so a force between two chain masses is the
paper's linear split) or a two-point combination ``((s1, a1), (s2, a2))``.
Branches are grouped into families (:mod:`.families`) so that "path 2"
of one load case is compared with "path 2" of another.

Tables written by :func:`write_sweep_tables`:

``sweep.csv``
    Tidy: one row per load case x path point, with its family.
``sweep_max.csv``
    Per load case and family: the period range, the maximum ``xi_eq`` (the
    paper's "upper limit for a time-history analysis") and where it occurs,
    and ``geom_dev`` / ``phi_dev``: the largest distance of the family's
    ``(T1, T2)`` points (and of ``phi`` mod ``pi``) from those of the
    reference load case (the first task) -- the check of the paper's
    observation that the path geometry does not depend on the load position.
``sweep_summary.json``
    Per family: the single-point load with the largest ``xi_eq`` and the
    combination with the largest ``xi_eq``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .families import FAMILIES, OTHER, assign_families
from ...util.files import write_csv, write_json
from ..execution import Study, branch_arrays, solve_task

__all__ = ["load_sweep_study", "default_positions", "node_pairs", "SweepTables", "sweep_tables",
           "write_sweep_tables", "xi_along_mesh", "SWEEP_HEADER", "MAX_HEADER"]

SWEEP_HEADER = ["case", "load", "s1", "a1", "s2", "a2", "family", "branch", "point",
                "T1", "T2", "phi", "T", "dPL", "xi", "grazing"]
MAX_HEADER = ["case", "load", "s1", "a1", "s2", "a2", "family", "branches", "points", "T_min", "T_max",
              "xi_min", "xi_max", "T_at_max", "T1_at_max", "T2_at_max", "phi_at_max", "dPL_at_max",
              "geom_dev", "phi_dev"]


def _bar_length(model: str, n: int, length: float) -> float:
    return float(n) if model == "chain" else float(length)


def default_positions(n: int, per_element: int = 10, model: str = "chain", length: float = 1.0) -> list[float]:
    """Positions ``k h / per_element`` strictly inside ``(0, L)`` (the nodes included)."""
    L = _bar_length(model, n, length)
    return [float(v) for v in np.linspace(0.0, L, per_element * n + 1)[1:-1]]


def node_pairs(n: int, model: str = "chain", length: float = 1.0, amplitude: float = 0.5):
    """All two-point combinations of the free non-contact nodes, ``amplitude`` each."""
    L = _bar_length(model, n, length)
    x = np.linspace(0.0, L, n + 1)[1:-1]
    return [((float(x[i]), amplitude), (float(x[j]), amplitude)) for i in range(len(x)) for j in range(i + 1, len(x))]


def load_sweep_study(n: int = 5, model: str = "chain", positions=None, pairs=(), grid=(200, 200),
                     element: str = "P1", mass: str = "lumped", length: float = 1.0,
                     per_element: int = 10) -> Study:
    """The tasks of a load-position sweep.

    Parameters
    ----------
    n, model, element, mass, length : Case fields
        The bar (default: the paper's chain ``N = 5``).
    positions : sequence of float, optional
        Unit point loads; default :func:`default_positions`.
    pairs : sequence of ((s1, a1), (s2, a2))
        Two-point combinations (e.g. :func:`node_pairs`).
    grid : (int, int)
        Scan grid of every case.

    Returns
    -------
    Study
        Tasks in the order: single positions, then pairs.
    """
    if positions is None:
        positions = default_positions(n, per_element, model, length)
    base = {"model": model, "n": int(n), "grid": [int(g) for g in grid]}
    if model == "fe":
        base.update(element=element, mass=mass, length=float(length))
    tasks = []
    for s in positions:
        tasks.append({"case": {**base, "load_points": [[float(s), 1.0]]}})
    for (s1, a1), (s2, a2) in pairs:
        tasks.append({"case": {**base, "load_points": [[float(s1), float(a1)], [float(s2), float(a2)]]}})
    params = {"n": int(n), "model": model, "grid": list(base["grid"]), "positions": len(positions),
              "pairs": len(pairs)}
    return Study("load-sweep", solve_task, tuple(tasks), params)


@dataclass(frozen=True)
class SweepTables:
    """Assembled sweep tables (columns as numpy arrays or lists)."""

    rows: dict
    maxima: dict
    summary: dict


def _load_cols(task: dict):
    pts = task["case"]["load_points"]
    s1, a1 = pts[0]
    s2, a2 = pts[1] if len(pts) > 1 else (np.nan, np.nan)
    label = "+".join(f"{a:g}@{s:g}" for s, a in pts)
    return label, float(s1), float(a1), float(s2), float(a2)


def _family_points(res: dict, labels, fam: str):
    brs = [branch_arrays(b) for b, f in zip(res["branches"], labels) if f == fam]
    if not brs:
        return None
    return {k: np.concatenate([b[k] for b in brs]) for k in brs[0]}, len(brs)


def _nearest_dev(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Distance from each row of P to the nearest row of Q, and that row's index."""
    d = np.sqrt(((P[:, None, :] - Q[None, :, :]) ** 2).sum(-1))
    j = d.argmin(1)
    return d[np.arange(len(P)), j], j


def sweep_tables(tasks, results, tol: float = 0.1, min_points: int = 4) -> SweepTables:
    """Tidy rows, per-case family maxima and the summary from task results (in task order)."""
    rows = {k: [] for k in SWEEP_HEADER}
    mx = {k: [] for k in MAX_HEADER}
    ref: dict[str, dict] = {}
    labels_all = []
    for res in results:
        rng = [(min(np.add(b["T1"], b["T2"])), max(np.add(b["T1"], b["T2"]))) for b in res["branches"]]
        labels_all.append(assign_families(rng, [len(b["T1"]) for b in res["branches"]], res["T0_I"],
                                          res["T0_II"], tol, min_points))
    for ci, (task, res, labels) in enumerate(zip(tasks, results, labels_all)):
        load, s1, a1, s2, a2 = _load_cols(task)
        for b, fam in zip(res["branches"], labels):
            a = branch_arrays(b)
            m = a["T"].size
            for k, v in (("case", ci), ("load", load), ("s1", s1), ("a1", a1), ("s2", s2), ("a2", a2),
                         ("family", fam), ("branch", b["id"])):
                rows[k].append([v] * m)
            rows["point"].append(list(range(m)))
            for k in ("T1", "T2", "phi", "T", "dPL", "xi", "grazing"):
                rows[k].append(list(a[k]))
        for fam in FAMILIES:
            got = _family_points(res, labels, fam)
            if got is None:
                continue
            p, nb = got
            if fam not in ref:
                ref[fam] = p
            r = ref[fam]
            dev, j = _nearest_dev(np.c_[p["T1"], p["T2"]], np.c_[r["T1"], r["T2"]])
            dphi = np.abs(np.angle(np.exp(2j * (p["phi"] - r["phi"][j])))) / 2   # mod pi
            i = int(np.argmax(p["xi"]))
            vals = {"case": ci, "load": load, "s1": s1, "a1": a1, "s2": s2, "a2": a2, "family": fam,
                    "branches": nb, "points": p["T"].size, "T_min": p["T"].min(), "T_max": p["T"].max(),
                    "xi_min": p["xi"].min(), "xi_max": p["xi"][i], "T_at_max": p["T"][i],
                    "T1_at_max": p["T1"][i], "T2_at_max": p["T2"][i], "phi_at_max": p["phi"][i],
                    "dPL_at_max": p["dPL"][i], "geom_dev": dev.max(), "phi_dev": dphi.max()}
            for k in MAX_HEADER:
                mx[k].append(vals[k])
    rows = {k: [x for part in v for x in part] for k, v in rows.items()}
    return SweepTables(rows, mx, _summary(mx))


def _summary(mx: dict) -> dict:
    out = {"families": list(FAMILIES), "other": OTHER, "best": {}}
    a2 = np.asarray(mx["a2"], float)
    for fam in FAMILIES:
        sel = [i for i, f in enumerate(mx["family"]) if f == fam]
        entry = {}
        for kind, keep in (("single", lambda i: np.isnan(a2[i])), ("pair", lambda i: not np.isnan(a2[i]))):
            idx = [i for i in sel if keep(i)]
            if not idx:
                continue
            i = max(idx, key=lambda k: (mx["xi_max"][k], -k))
            entry[kind] = {k: mx[k][i] for k in ("case", "load", "s1", "a1", "s2", "a2", "xi_max", "T_at_max",
                                                  "T1_at_max", "T2_at_max", "phi_at_max", "dPL_at_max")}
            entry[kind]["s2"] = None if np.isnan(entry[kind]["s2"]) else entry[kind]["s2"]
            entry[kind]["a2"] = None if np.isnan(entry[kind]["a2"]) else entry[kind]["a2"]
            entry[kind]["cases"] = len(idx)
            entry[kind]["max_geom_dev"] = float(max(mx["geom_dev"][k] for k in idx))
        out["best"][fam] = entry
    return out


def _blank_nan(col):
    """Column values for CSV with nan written as an empty field (single loads have no s2, a2)."""
    return ["" if (isinstance(v, float) and np.isnan(v)) else repr(float(v)) for v in col]


def write_sweep_tables(folder, tables: SweepTables) -> dict[str, Path]:
    """Write ``sweep.csv``, ``sweep_max.csv`` and ``sweep_summary.json`` (atomically).

    A single load has no second position: its ``s2, a2`` fields are empty
    (no ``nan`` is ever written).
    """
    folder = Path(folder)
    g = "%.17g"
    f_rows = ["%d", "%s", g, g, "%s", "%s", "%s", "%d", "%d", g, g, g, g, g, g, "%d"]
    f_max = ["%d", "%s", g, g, "%s", "%s", "%s", "%d", "%d"] + [g] * 11
    rows = [(_blank_nan(tables.rows[k]) if k in ("s2", "a2") else tables.rows[k]) for k in SWEEP_HEADER]
    maxi = [(_blank_nan(tables.maxima[k]) if k in ("s2", "a2") else tables.maxima[k]) for k in MAX_HEADER]
    return {
        "sweep": write_csv(folder / "sweep.csv", SWEEP_HEADER, rows, f_rows),
        "max": write_csv(folder / "sweep_max.csv", MAX_HEADER, maxi, f_max),
        "summary": write_json(folder / "sweep_summary.json", tables.summary),
    }


def xi_along_mesh(tables: SweepTables) -> tuple[np.ndarray, dict]:
    """Per single-load position: max ``xi_eq`` over all branches and per family, and the max ``Delta_PL``.

    Returns the sorted positions (with the clamp ``s = 0`` added, where a
    load does nothing: every value 0) and a dict of point fields for
    :func:`plbar.export.write_xi_along_mesh`.
    """
    r = tables.rows
    a2 = np.asarray(r["a2"], float)
    s1 = np.asarray(r["s1"], float)
    single = np.isnan(a2)
    pos = np.unique(s1[single])
    xi = np.asarray(r["xi"], float)
    dpl = np.asarray(r["dPL"], float)
    fam = np.asarray(r["family"], dtype=object)
    fields = {"xi_eq_max": np.zeros(pos.size), "dPL_max": np.zeros(pos.size)}
    for f in FAMILIES:
        fields[f"xi_eq_max_{f.replace('/', '_')}"] = np.zeros(pos.size)
    for i, s in enumerate(pos):
        m = single & (s1 == s)
        if not m.any():
            continue
        fields["xi_eq_max"][i] = xi[m].max()
        fields["dPL_max"][i] = dpl[m].max()
        for f in FAMILIES:
            mf = m & (fam == f)
            if mf.any():
                fields[f"xi_eq_max_{f.replace('/', '_')}"][i] = xi[mf].max()
    pos = np.r_[0.0, pos]
    return pos, {k: np.r_[0.0, v] for k, v in fields.items()}
