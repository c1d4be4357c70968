"""The files of a load study (:func:`.sweep.sweep_loads`): tables, the worst loads, the mesh, the figure."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ...errors import LargeOutputWarning
from ...util.files import atomic_path, write_csv, write_json
from .families import FAMILIES, OTHER

__all__ = ["POSITIONS_HEADER", "WORST_HEADER", "PAIRS_HEADER", "WARN_BYTES", "tidy_positions", "write_all"]

POSITIONS_HEADER = ["branch", "point", "T", "s", "xi", "dPL"]
WORST_HEADER = ["branch", "point", "T1", "T2", "phi", "T", "xi_worst", "xi_best_single", "s_best_single"]
PAIRS_HEADER = ["load", "s1", "a1", "s2", "a2", "family", "points", "T_min", "T_max", "xi_min", "xi_max",
                "T_at_max", "T1_at_max", "T2_at_max", "phi_at_max", "dPL_at_max", "no_path_points"]
G17 = "%.17g"
WARN_BYTES = 50e6       #: a positions table larger than this is announced (a warning that names the switches)
CSV_ROW_BYTES = 85      #: about the size of one row of the tidy xi_positions.csv (measured: 81)


def tidy_positions(pos: dict) -> dict:
    """The positions table as tidy columns ``branch, point, T, s, xi, dPL``, one row per path point and position."""
    P, S = pos["xi"].shape
    return {"branch": np.repeat(pos["branch"], S), "point": np.repeat(pos["point"], S), "T": np.repeat(pos["T"], S),
            "s": np.tile(pos["s"], P), "xi": pos["xi"].ravel(), "dPL": pos["dPL"].ravel()}


def _blank(col):
    return ["" if (isinstance(v, float) and np.isnan(v)) else repr(float(v)) for v in col]


def _table_bytes(pos: dict, csv: bool) -> float:
    return pos["xi"].size * (CSV_ROW_BYTES if csv else 16)


def _write_positions(out: Path, pos: dict, csv: bool) -> dict:
    """``xi_positions.npz`` (and the tidy ``xi_positions.csv`` if asked), announced above :data:`WARN_BYTES`."""
    size = _table_bytes(pos, csv)
    if size > WARN_BYTES:
        P, S = pos["xi"].shape
        warnings.warn(f"the positions table holds {P} path points x {S} positions = {P * S} values (about "
                      f"{size / 1e6:.0f} MB{' of CSV' if csv else ''}); fewer positions: --per-element K or "
                      "--positions S ...", LargeOutputWarning, stacklevel=3)
    files = {}
    with atomic_path(out / "xi_positions.npz") as tmp:
        np.savez(tmp, **{k: pos[k] for k in ("branch", "point", "T", "s", "xi", "dPL")})
    files["xi_positions"] = out / "xi_positions.npz"
    if csv:
        t = tidy_positions(pos)
        files["xi_positions_csv"] = write_csv(out / "xi_positions.csv", POSITIONS_HEADER,
                                              [t[k] for k in POSITIONS_HEADER], ["%d", "%d", G17, G17, G17, G17],
                                              allow_nan=False)
    return files


def _write_tables(out: Path, pos, wcols, w, fam, pairs_rows, lf, csv: bool = False) -> dict:
    files = _write_positions(out, pos, csv)
    files["worst_load"] = write_csv(out / "worst_load.csv", WORST_HEADER, [wcols[k] for k in WORST_HEADER],
                                    ["%d", "%d"] + [G17] * 7, allow_nan=False)
    cols = [(_blank(pairs_rows[k]) if k in ("s2", "a2") else pairs_rows[k]) for k in PAIRS_HEADER]
    fm = ["%s", G17, G17, "%s", "%s", "%s", "%d"] + [G17] * 9 + ["%d"]
    files["load_pairs"] = write_csv(out / "load_pairs.csv", PAIRS_HEADER, cols, fm)
    with atomic_path(out / "worst_load_shapes.npz") as tmp:
        np.savez(tmp, q_star=w.q, x=lf.x, branch=lf.branch, point=lf.point, T1=lf.T1, T2=lf.T2,
                 phi=np.mod(lf.phi, 2 * np.pi), xi_worst=w.xi, rank=w.rank, family=fam.astype(str))
    files["worst_load_shapes"] = out / "worst_load_shapes.npz"
    return files


def _write_mesh(out: Path, pos: dict, fam) -> Path:
    """``xi_along_mesh.vtu``: a polyline through the evaluated load positions (``xi_positions.npz``'s ``s``), each
    with the largest ``xi_eq`` (over all path points and per family) and ``Delta_PL`` of a unit force there."""
    from ...io import write_xi_along_mesh

    s, k = np.unique(np.asarray(pos["s"], float), return_index=True)
    xi, dpl = np.asarray(pos["xi"])[:, k], np.asarray(pos["dPL"])[:, k]
    fields = {"xi_eq_max": xi.max(axis=0), "dPL_max": dpl.max(axis=0)}
    for f in FAMILIES:
        m = fam == f
        fields[f"xi_eq_max_{f.replace('/', '_')}"] = xi[m].max(axis=0) if m.any() else np.zeros(s.size)
    line = s if s.size > 1 else np.r_[0.0, s]           # one position: a line from the clamp (no value there)
    return write_xi_along_mesh(line, s, fields, out / "xi_along_mesh.vtu")


def _plot(out: Path, lf, fam, pos, wcols, units: str) -> Path:
    from ...visuals import xi_load_map

    return xi_load_map(out / "xi_T_s.png", lf.T, lf.branch, fam, pos["s"], pos["xi"], wcols["xi_worst"],
                       wcols["xi_best_single"], [f for f in FAMILIES + (OTHER,) if np.any(fam == f)], units)


def write_all(out: Path, r: dict, res, plot: bool, csv: bool) -> dict:
    lf, fam = r["forms"], r["families"]
    files = _write_tables(out, r["positions"], r["worst_load"], r["worst"], fam, r["pairs"], lf, csv)
    files["xi_along_mesh"] = _write_mesh(out, r["positions"], fam)
    if plot:
        from ...visuals.style import unit_note

        files["plot"] = _plot(out, lf, fam, r["positions"], r["worst_load"], unit_note(res.paths.prob.bar))
    files["summary"] = write_json(out / "summary.json", r["summary"])
    return files
