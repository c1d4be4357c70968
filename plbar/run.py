"""Solve a case end to end and write its results (``plbar run``)."""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .case import Case
from .errors import OutputExistsError
from .io import write_csv, write_json
from .paths import Paths, find_paths

__all__ = ["Result", "solve", "write_results", "CSV_HEADER"]

CSV_HEADER = ["branch", "T1", "T2", "phi", "T", "dPL", "xi", "grazing", "stable", "max_abs_multiplier"]


@dataclass(frozen=True)
class Result:
    """A solved case: the paths and the solver time (s)."""

    case: Case
    paths: Paths
    solver_time: float

    @property
    def branches(self):
        return self.paths.branches

    def summary(self) -> dict:
        """The content of ``summary.json``."""
        s = self.paths.prob.system
        T0I, T0II = s.T0
        br = []
        for b in self.branches:
            br.append({
                "branch": b.id, "points": len(b),
                "T_range": [float(b.T.min()), float(b.T.max())],
                "T1_range": [float(b.T1.min()), float(b.T1.max())],
                "T2_range": [float(b.T2.min()), float(b.T2.max())],
                "xi_range": [float(b.xi.min()), float(b.xi.max())],
                "dPL_range": [float(b.dPL.min()), float(b.dPL.max())],
                "grazing_points": int(b.grazing.sum()),
                "resonant_points": int((~b.damping.closed_form).sum()),
                "stable_points": int(b.stable.sum()),
                "ends": list(b.ends),
                "events": list(b.events),
            })
        stats = {k: (round(v, 6) if isinstance(v, float) else v) for k, v in self.paths.stats.items()}
        return {
            "case": self.case.to_dict(),
            "bar": self.paths.prob.bar.describe() if self.paths.prob.bar else "",
            "load": self.paths.prob.load.describe() if self.paths.prob.load else "",
            "dofs": int(s.n),
            "T0_I": float(T0I), "T0_II": float(T0II),
            "domain": {"T1": list(self.paths.domain.T1), "T2": list(self.paths.domain.T2)},
            "n_branches": len(self.branches),
            "n_points": int(sum(len(b) for b in self.branches)),
            "branches": br,
            "scan": stats,
            "run_time": round(self.solver_time, 6),
        }


def solve(case: Case | None = None, progress: bool = False) -> Result:
    """Solve ``case`` (default: the paper's chain N = 5, unit force on DOF 1)."""
    case = case or Case()
    t0 = time.perf_counter()
    prob = case.problem()
    paths = find_paths(prob, case.domain(prob), case.grid, method=case.method, progress=progress)
    return Result(case, paths, time.perf_counter() - t0)


def _rows(res: Result):
    cols = {k: [] for k in CSV_HEADER}
    for b in res.branches:
        cols["branch"].append(np.full(len(b), b.id))
        cols["T1"].append(b.T1)
        cols["T2"].append(b.T2)
        cols["phi"].append(np.mod(b.phi, 2 * np.pi))
        cols["T"].append(b.T)
        cols["dPL"].append(b.dPL)
        cols["xi"].append(b.xi)
        cols["grazing"].append(b.grazing.astype(int))
        cols["stable"].append(b.stable.astype(int))
        cols["max_abs_multiplier"].append(b.max_abs_multiplier)
    return [np.concatenate(cols[k]) if cols[k] else np.zeros(0) for k in CSV_HEADER]


def write_results(res: Result, out, overwrite: bool = False) -> dict[str, Path]:
    """Write ``paths.csv`` and ``summary.json`` into ``out`` (atomically).

    An existing ``summary.json`` of a *different* case is kept and an
    :class:`OutputExistsError` raised unless ``overwrite``.
    """
    out = Path(out)
    old = out / "summary.json"
    if old.exists() and not overwrite:
        try:
            prev = json.loads(old.read_text()).get("case")
        except (OSError, ValueError):
            prev = None
        if prev != json.loads(json.dumps(res.case.to_dict())):
            raise OutputExistsError(f"output folder {str(out)!r} holds results of another case; "
                                    "choose another --out or pass --overwrite")
    files = {
        "paths": write_csv(out / "paths.csv", CSV_HEADER, _rows(res),
                           ["%d", "%.17g", "%.17g", "%.17g", "%.17g", "%.17g", "%.17g", "%d", "%d", "%.17g"]),
    }
    files["summary"] = write_json(out / "summary.json", res.summary())
    return files
