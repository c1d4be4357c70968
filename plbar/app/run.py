"""Solve a case end to end and write its results (``plbar run``)."""

from __future__ import annotations

import contextlib

import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import CoarseGridWarning, InputError
from ..paths import Paths, find_paths
from ..util.check import MIN_BRANCH_POINTS, show
from ..util.check import grid as check_grid
from ..util.files import check_finite, write_csv, write_json
from ..util.outputs import Claim, check_folder, clear_owned, fingerprint
from ..util.progress import message
from ..util.version import __version__
from ..visuals.plots import contact_amplitude
from .case import Case
from .cost import search_note
from .signatures import Search, hybrid_rows, hybrid_summary

__all__ = ["Result", "solve", "write_results", "read_paths", "check_output", "case_fingerprint", "PATHS_COLUMNS",
           "CSV_HEADER", "CSV_FORMATS", "TEXT_COLUMNS", "RUN_FILES"]

#: the columns of ``paths.csv`` (name, printf format): the one definition, for writers and readers
PATHS_COLUMNS = (("branch", "%d"), ("T1", "%.17g"), ("T2", "%.17g"), ("phi", "%.17g"), ("T", "%.17g"),
                 ("dPL", "%.17g"), ("xi", "%.17g"), ("grazing", "%d"), ("stable", "%d"),
                 ("max_abs_multiplier", "%.17g"), ("max_abs_xc", "%.17g"), ("omega", "%.17g"),
                 ("xi_w", "%.17g"),
                 ("viscous_loss", "%.17g"), ("zeta_rayleigh", "%.17g"), ("xi_total", "%.17g"),
                 ("m", "%d"), ("k", "%d"), ("signature", "%s"), ("loss_per_T", "%.17g"), ("durations", "%s"))
#: the text columns of ``paths.csv`` (read as strings)
TEXT_COLUMNS = ("signature", "durations")
CSV_HEADER = [c for c, _ in PATHS_COLUMNS]
#: what ``plbar run`` owns in its folder besides paths.csv and summary.json (cleared before new results)
RUN_OWNED = ("vtk", "render", "frequency_response.png", "frequency_response.pdf", "paths_T1_T2.png", "paths_T1_T2.pdf")
#: temporaries of a run killed while writing
RUN_TEMPS = (".paths.*.part.csv", ".summary.*.part.json")
#: everything ``plbar run`` owns in its folder (its owner marker lists these)
RUN_FILES = ("paths.csv", "summary.json") + RUN_OWNED + RUN_TEMPS
CSV_FORMATS = [f for _, f in PATHS_COLUMNS]


@dataclass(frozen=True)
class Result:
    """A solved case: the paths of the paper's class, the branches of other signatures, the times (s).

    ``solver_time`` is the whole solve; ``paper_time`` the paper's class (:func:`plbar.find_paths`);
    ``signatures_time`` what the signature search added after it (:meth:`Search.finish`: its seeding simulation
    began beside the paper's class and is not counted twice).
    """

    case: Case
    paths: Paths
    solver_time: float
    hybrid: tuple = ()
    paper_time: float = 0.0
    signatures_time: float = 0.0

    @property
    def branches(self):
        return self.paths.branches

    def __repr__(self) -> str:
        n = sum(len(b) for b in self.branches)
        return (f"Result({self.paths.prob.bar.describe() if self.paths.prob.bar else 'bar'}; "
                f"{len(self.branches)} branches, {n} path points, solved in {self.solver_time:.3g} s)\n"
                f"  case: {self.case!r}\n  paths: {self.paths!r}")

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
                "viscous_loss_range": [float(b.viscous.min()), float(b.viscous.max())],
                "xi_total_range": [float(b.xi_total.min()), float(b.xi_total.max())],
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
            "rayleigh": [float(s.alpha), float(s.beta)] if s.damped else None,
            "T0_I": float(T0I), "T0_II": float(T0II),
            "domain": {"T1": list(self.paths.domain.T1), "T2": list(self.paths.domain.T2)},
            "n_branches": len(self.branches),
            "n_points": int(sum(len(b) for b in self.branches)),
            "branches": br,
            "signatures": self.case.signatures,
            "other_signatures": hybrid_summary(self.hybrid, _first_hybrid_id(self)),
            "scan": stats,
            "run_time": round(self.solver_time, 6),
            "paper_time": round(self.paper_time, 6),
            "signatures_time": round(self.signatures_time, 6),
            "plbar_version": __version__,
        }


def solve(case: Case | None = None, progress: bool = False) -> Result:
    """Solve ``case`` (default: the paper's chain N = 5, unit force on DOF 1).

    Warns (:class:`plbar.errors.CoarseGridWarning`) when the scan grid has
    fewer than 20 points along an axis, a branch has fewer than 3 points, or nothing is found.
    """
    if case is None:
        case = Case()
    if not isinstance(case, Case):
        raise InputError(f"case = {show(case)} is not a plbar.Case ({type(case).__name__}); "
                         "build one with plbar.Case(...) or read a file with plbar.casefile.load_case")
    if case.restitution and case.signatures == "paper":
        raise InputError(f"restitution = {case.restitution:g} with signatures = 'paper': the paper's class (one "
                         "plastic impact and a stuck phase per period, Eq. (10)) needs e = 0; with rebounds every "
                         "response is found by the signature search: signatures = 'default' or 'all'")
    check_grid(case.grid, stacklevel=3)
    t0 = time.perf_counter()
    prob = case.problem()
    domain = case.domain(prob)
    note = search_note(case) if progress and case.signatures != "paper" else None
    if note:
        message(note)
    with contextlib.ExitStack() as stack:        # the other signatures begin beside the paper's class
        search = None if case.signatures == "paper" else stack.enter_context(
            Search(prob, domain, case.signatures, progress))
        t_paper = time.perf_counter()
        paths = _no_paths(prob, domain, case) if case.restitution else \
            find_paths(prob, domain, case.grid, method=case.method, progress=progress)
        t_search = time.perf_counter()
        hybrid = () if search is None else tuple(search.finish(paths))
        t_end = time.perf_counter()
    short = [b.id for b in paths.branches if len(b) < MIN_BRANCH_POINTS]
    if short:
        ids = ", ".join(str(i) for i in short[:8]) + (f" and {len(short) - 8} more" if len(short) > 8 else "")
        many = len(short) != 1
        warnings.warn(f"{len(short)} branch{'es' if many else ''} ({ids}) {'have' if many else 'has'} fewer than "
                      f"{MIN_BRANCH_POINTS} points on grid = "
                      f"{case.grid}; refine the grid (or narrow T1/T2) to resolve them", CoarseGridWarning,
                      stacklevel=2)
    if not paths.branches and not hybrid:
        warnings.warn(f"no admissible periodic response in T1 = {_interval(domain.T1)}, T2 = {_interval(domain.T2)} "
                      f"(forcing periods T in {_interval((domain.T1[0] + domain.T2[0], domain.T1[1] + domain.T2[1]))})"
                      f" on grid = {case.grid}; widen T1/T2 (default (0, T0/2] each) or refine the grid",
                      CoarseGridWarning, stacklevel=2)
    return Result(case, paths, time.perf_counter() - t0, hybrid, t_search - t_paper, t_end - t_search)


def _no_paths(prob, domain, case: Case) -> Paths:
    """The paper's class with restitution ``e > 0``: none (its impact is plastic); every response with rebounds,
    chattering included (``R...RP``), comes from the signature search."""
    return Paths(prob, domain, tuple(case.grid), (), {"paper_class": f"none: restitution e = {case.restitution:g} "
                                                                    "(the paper's class needs a plastic impact)"})


def _interval(r) -> str:
    return f"[{r[0]:.6g}, {r[1]:.6g}]"


def _first_hybrid_id(res: Result) -> int:
    return max((b.id for b in res.branches), default=-1) + 1


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
        cols["max_abs_xc"].append(contact_amplitude(b.orbits))          # the amplitude the plot shows
        cols["omega"].append(2 * np.pi / b.T)
        cols["xi_w"].append(b.xi_w)
        cols["viscous_loss"].append(b.viscous)
        cols["zeta_rayleigh"].append(b.damping.zeta_rayleigh)
        cols["xi_total"].append(b.xi_total)
        cols["m"].append(np.ones(len(b), int))
        cols["k"].append(np.ones(len(b), int))
        cols["signature"].append(np.full(len(b), "1P", dtype=object))
        cols["loss_per_T"].append(b.dPL)
        cols["durations"].append(np.array([f"{a:.17g};{c:.17g}" for a, c in zip(b.T1, b.T2)], dtype=object))
    for k, v in hybrid_rows(res.hybrid, _first_hybrid_id(res)).items():
        cols[k].append(np.array(v, dtype=object if k in TEXT_COLUMNS else None))
    return [np.concatenate(cols[k]) if cols[k] else np.zeros(0) for k in CSV_HEADER]


def read_paths(path) -> dict[str, np.ndarray]:
    """The columns of a ``paths.csv`` by name (see :data:`PATHS_COLUMNS`)."""
    path = Path(path)
    with open(path) as fh:
        header = fh.readline().strip().split(",")
    missing = [c for c in CSV_HEADER if c not in header]
    if missing:
        raise InputError(f"{str(path)!r} is not a plbar paths.csv (no column {missing[0]!r})")
    import csv

    with open(path, newline="") as fh:
        body = list(csv.reader(fh))[1:]
    cols = list(zip(*body)) if body else [()] * len(header)
    out = {}
    for c, vals in zip(header, cols):
        out[c] = np.array(vals, dtype=object) if c in TEXT_COLUMNS else \
            np.array([float(v) if v != "" else np.nan for v in vals], float)
    return out


def case_fingerprint(case: Case) -> str:
    """The identity of a case in an owner marker (:func:`plbar.util.outputs.fingerprint` of ``case.to_dict()``)."""
    return fingerprint(case.to_dict())


def check_output(case: Case, out, overwrite: bool = False) -> Claim:
    """Raise unless results of ``case`` may be written into ``out`` (the one ownership rule; nothing is written).

    Cheap: call it before a long solve so that a bad ``--out`` fails at once (the
    folder is created and a file written and removed there).  Returns the
    :class:`~plbar.util.outputs.Claim` (a context manager: a folder it created is
    removed again if the solve fails or is interrupted before anything is written).
    """
    out = Path(out)
    if (out / "summary.json").is_dir():
        raise InputError(f"output folder {str(out)!r} holds a folder named summary.json; choose another --out")
    return check_folder(out, "run", case_fingerprint(case), RUN_FILES, overwrite)


def write_results(res: Result, out, overwrite: bool = False) -> dict[str, Path]:
    """Write ``paths.csv`` and ``summary.json`` into ``out`` (atomically).

    Rerunning the same case into ``out`` replaces its results.  A folder that
    belongs to another command or case (its owner marker, ``.plbar-owner.json``,
    :func:`plbar.util.outputs.check_folder`) is kept and an
    :class:`OutputExistsError` raised unless ``overwrite`` (then what the old
    owner owned is removed).  What an earlier run left there (:data:`RUN_OWNED`: its ParaView
    export, renders and plots) is removed first, so no file of another case stays
    beside the new results.  Both tables are checked before either is written: a nan or
    inf raises :class:`plbar.errors.NonFiniteError` and writes nothing.  Each
    file appears under its name only when complete; ``summary.json`` is
    written last, so a run killed in between leaves a ``paths.csv`` without
    a summary, which the next run of the same case replaces.
    """
    if not isinstance(res, Result):
        raise InputError(f"res = {show(res)} is not a plbar.Result; get one from plbar.solve(case)")
    out = Path(out)
    with check_output(res.case, out, overwrite) as claim:     # undone on a failure; its lock released after
        rows = _rows(res)
        summary = res.summary()
        check_finite("paths.csv", dict(zip(CSV_HEADER, rows)))
        check_finite("summary.json", summary)
        claim.take()                                     # another owner's files go only now (with overwrite)
        clear_owned(out, RUN_OWNED + RUN_TEMPS)          # derived outputs of an earlier run: never stale
        files = {
            "paths": write_csv(out / "paths.csv", CSV_HEADER, rows, CSV_FORMATS, allow_nan=False),
        }
        files["summary"] = write_json(out / "summary.json", summary)
    return files
