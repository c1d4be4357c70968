"""Solve a case end to end and write its results (``plbar run``)."""

from __future__ import annotations

import contextlib

import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import CoarseGridWarning, InputError
from ..model import Problem, Structure
from ..paths import Domain, Paths, find_paths
from ..periodic import canonical, find_branches, from_paths, prepare
from ..util.check import MIN_BRANCH_POINTS, show
from ..util.check import grid as check_grid
from ..util.files import check_finite, write_csv, write_json
from ..util.outputs import Claim, check_folder, clear_owned, fingerprint
from ..util.progress import message
from ..util.version import __version__
from ..util.reprs import listing
from .case import Case
from .cost import search_note
from .signatures import M_MAX, Search, search_window

__all__ = ["Result", "solve", "write_results", "branch_rows", "branch_summary", "read_paths",
           "check_output", "case_fingerprint", "PATHS_COLUMNS",
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
    """A solved case: the branches of every signature (the paper's class first), the paper's scan, the times (s).

    ``solver_time`` is the whole solve; ``paper_time`` the paper's class (:func:`plbar.find_paths`: the scan of
    ``G`` and its continuation in ``(T^I, T^II)``); ``signatures_time`` what the other signatures added after it
    (their seeding simulation began beside the paper's class and is not counted twice).
    """

    case: Case
    paths: Paths
    branches: tuple
    solver_time: float
    paper_time: float = 0.0
    signatures_time: float = 0.0

    @property
    def prob(self) -> Problem:
        return self.paths.prob

    @property
    def domain(self) -> Domain:
        return self.paths.domain

    @property
    def stats(self) -> dict:
        """The paper's scan: grid, crossings, zeros, points traced, times."""
        return self.paths.stats

    @property
    def paper(self) -> tuple:
        """The branches of the paper's class (signature ``1P``)."""
        return tuple(b for b in self.branches if b.paper)

    def __repr__(self) -> str:
        n = sum(len(b) for b in self.branches)
        bar = self.prob.bar.describe() if self.prob.bar else f"structure of {self.prob.system.n} DOFs"
        lines = listing((b.describe() for b in self.branches), 5)
        return (f"Result({bar}; {len(self.branches)} branches ({len(self.paper)} of the paper's class), {n} points, "
                f"solved in {self.solver_time:.3g} s)\n  case: {self.case!r}" + "".join("\n  " + ln for ln in lines))

    def summary(self) -> dict:
        """The content of ``summary.json``."""
        s = self.prob.system
        T0I, T0II = s.T0
        stats = {k: (round(v, 6) if isinstance(v, float) else v) for k, v in self.stats.items()}
        return {
            "case": self.case.to_dict(),
            "bar": self.prob.bar.describe() if self.prob.bar else _structure_text(self.case),
            "load": self.prob.load.describe() if self.prob.load else "the structure's own (its vector q)",
            "dofs": int(s.n),
            "rayleigh": [float(s.alpha), float(s.beta)] if s.damped else None,
            "T0_I": float(T0I), "T0_II": float(T0II),
            "domain": {"T1": list(self.domain.T1), "T2": list(self.domain.T2)},
            "n_branches": len(self.branches),
            "n_paper_branches": len(self.paper),
            "n_points": int(sum(len(b) for b in self.branches)),
            "branches": branch_summary(self.branches),
            "signatures": self.case.signatures,
            "scan": stats,
            "run_time": round(self.solver_time, 6),
            "paper_time": round(self.paper_time, 6),
            "signatures_time": round(self.signatures_time, 6),
            "plbar_version": __version__,
        }


def _structure_text(case: Case) -> str:
    """What a structure given by its matrices is, in a line (its DOFs and where it came from)."""
    where = f" from {case.matrices}" if case.matrices else ""
    n = case.structure.n
    dofs = f"a structure of {n} DOF{'s' if n != 1 else ''}{where}"
    return f"{dofs} (contact row {case.structure.contact.tolist()})" if n <= 6 else dofs


#: the answer of :func:`solve` for a structure whose free state floats (:attr:`plbar.TwoStateSystem.floating`)
NO_PERIODIC_CONTACT = ("no periodic response with a contact exists: the free state moves as a rigid body that every "
                       "contact pushes away from the stop (a cracked bar's outer part, a free body), and no constant "
                       "load pushes it back, so over a period the contact's impulse must vanish (the rigid mode's "
                       "momentum balance, docs/crack.md); the motion from rest (plbar survey) leaves the stop for "
                       "good. Clamp the far end (supports = 'clamped-clamped', --supports clamped-clamped) for a "
                       "crack that keeps breathing")


#: the answer of :func:`solve` for a structure whose constant load pushes a rigid motion of the free state
RIGID_LOAD = ("the constant load (gravity, a prestress) pushes a rigid-body motion of the free state (a body dropped "
              "on the stop, a crack pressed shut): the periodic solvers do not take it yet; the motion from rest or "
              "from a given start is exact (plbar.simulate, plbar survey), and over any periodic motion the mean "
              "contact force equals the load on the rigid motion (docs/free_body.md)")


def solve(case: Case | Structure | None = None, progress: bool = False) -> Result:
    """Solve ``case`` (default: the paper's chain N = 5, unit force on DOF 1): every periodic response.

    ``case`` may be a :class:`plbar.Structure` (any matrices, any contact row): ``Case(structure=...)``.

    The paper's class comes from the paper's scan of ``G`` over the search domain and its continuation
    (:func:`plbar.find_paths`, made branches of the one record by :func:`plbar.periodic.from_paths`), the other
    signatures (``case.signatures`` ``"default"`` or ``"all"``) from the structure and a simulation from rest
    (:class:`plbar.app.signatures.Search`, begun beside the paper's class), followed in ``T`` by the periodic
    core (:func:`plbar.periodic.find_branches`).  Warns (:class:`plbar.errors.CoarseGridWarning`) when the scan grid
    has fewer than 20 points along an axis, a branch of the paper's class has fewer than 3 points, or nothing is
    found.
    """
    if case is None:
        case = Case()
    if isinstance(case, Structure):
        case = Case(structure=case)
    if not isinstance(case, Case):
        raise InputError(f"case = {show(case)} is not a plbar.Case ({type(case).__name__}); "
                         "build one with plbar.Case(...) or read a file with plbar.casefile.load_case")
    if (case.gap or case.gravity) and case.signatures == "paper":
        what = f"gap = {case.gap:g}" if case.gap else f"gravity = {case.gravity:g}"
        raise InputError(f"{what} with signatures = 'paper': the paper's scan of (T1, T2) is written for no gap and "
                         "no constant load; with either every response, the paper's class too, is found by the "
                         "signature search: signatures = 'default' or 'all'")
    if case.restitution and case.signatures == "paper":
        raise InputError(f"restitution = {case.restitution:g} with signatures = 'paper': the paper's class (one "
                         "plastic impact and a stuck phase per period, Eq. (10)) needs e = 0; with rebounds every "
                         "response is found by the signature search: signatures = 'default' or 'all'")
    check_grid(case.grid, stacklevel=3)
    t0 = time.perf_counter()
    prob = case.problem()
    if prob.statics.accel is not None:
        raise InputError(RIGID_LOAD)
    if prob.system.floating:
        raise InputError(NO_PERIODIC_CONTACT)
    domain = case.domain(prob)
    note = search_note(case) if progress and case.signatures != "paper" else None
    if note:
        message(note)
    with contextlib.ExitStack() as stack:        # the other signatures begin beside the paper's class
        search = None if case.signatures == "paper" else stack.enter_context(
            Search(prob, domain, case.signatures, progress))
        t_paper = time.perf_counter()
        paths = _no_paths(prob, domain, case) if case.restitution or prob.affine else \
            find_paths(prob, domain, case.grid, method=case.method, progress=progress)
        paper = from_paths(prob, paths.branches)
        t_search = time.perf_counter()
        if search is not None:
            prepare(prob, paper[0].orbits[0] if paper else None)
        seeds = [] if search is None else search.seeds()
        branches = tuple(find_branches(prob, search_window(prob, domain), paper, seeds, case.signatures,
                                       m_max=M_MAX[case.signatures],
                                       progress=None if search is None else search.curve))
        t_end = time.perf_counter()
    _warn_coarse(case, domain, branches, len(paper))
    return Result(case, paths, branches, time.perf_counter() - t0, t_search - t_paper, t_end - t_search)


def _warn_coarse(case: Case, domain: Domain, branches, n_paper: int) -> None:
    """The :class:`CoarseGridWarning` of a solve: short branches of the paper's class (the scan's: they come
    first), or nothing found."""
    short = [b.id for b in branches[:n_paper] if len(b) < MIN_BRANCH_POINTS]
    if short:
        ids = ", ".join(str(i) for i in short[:8]) + (f" and {len(short) - 8} more" if len(short) > 8 else "")
        many = len(short) != 1
        warnings.warn(f"{len(short)} branch{'es' if many else ''} ({ids}) of the paper's class "
                      f"{'have' if many else 'has'} fewer than {MIN_BRANCH_POINTS} points on grid = "
                      f"{case.grid}; refine the grid (or narrow T1/T2) to resolve them", CoarseGridWarning,
                      stacklevel=3)
    if not branches:
        warnings.warn(f"no admissible periodic response in T1 = {_interval(domain.T1)}, T2 = {_interval(domain.T2)} "
                      f"(forcing periods T in {_interval((domain.T1[0] + domain.T2[0], domain.T1[1] + domain.T2[1]))})"
                      f" on grid = {case.grid}; widen T1/T2 (default (0, T0/2] each) or refine the grid",
                      CoarseGridWarning, stacklevel=3)


def _no_paths(prob, domain, case: Case) -> Paths:
    """No scan of the paper's class: with restitution ``e > 0`` it does not exist (its impact is plastic), and
    every response with rebounds, chattering included (``R...RP``), comes from the signature search; with a gap the
    scan's equations do not hold, and the paper's class (``P1``) is found by the search too."""
    why = (f"none: restitution e = {case.restitution:g} (the paper's class needs a plastic impact)" if case.restitution
           else f"from the signature search: {prob.static_part} (the scan of (T1, T2) is written for neither)")
    return Paths(prob, domain, tuple(case.grid), (), {"paper_class": why})


def _interval(r) -> str:
    return f"[{r[0]:.6g}, {r[1]:.6g}]"


def branch_rows(branches) -> list[np.ndarray]:
    """The columns of ``paths.csv`` (:data:`CSV_HEADER` order), one row per orbit of every branch.

    ``T1`` and ``T2`` are the total stuck and free time over the orbit (``m`` periods), ``dPL`` the loss over the
    orbit, ``phi`` and ``durations`` those of its canonical rotation (:func:`plbar.periodic.canonical`); for the
    paper's class they are the paper's ``T^I, T^II, phi`` and ``Delta_PL``.
    """
    cols: dict = {k: [] for k in CSV_HEADER}
    for b in branches:
        graze, label = b.grazing, b.label
        for j, o in enumerate(b.orbits):
            _, d, phi = canonical(o)                 # the durations and phase of the canonical rotation
            row = {"branch": b.id, "T1": float(d[0::2].sum()), "T2": float(d[1::2].sum()), "phi": phi, "T": o.T,
                   "dPL": o.dPL, "xi": o.xi, "grazing": int(graze[j]), "stable": int(b.stable[j]),
                   "max_abs_multiplier": float(b.max_abs_multiplier[j]), "max_abs_xc": o.amplitude,
                   "omega": 2 * np.pi / o.T, "xi_w": o.xi_w, "viscous_loss": o.viscous,
                   "zeta_rayleigh": o.xi_total - o.xi, "xi_total": o.xi_total, "m": o.sig.m, "k": o.sig.k,
                   "signature": label, "loss_per_T": o.loss_per_T, "durations": ";".join(f"{x:.17g}" for x in d)}
            for k, v in row.items():
                cols[k].append(v)
    return [np.array(cols[k], dtype=object if k in TEXT_COLUMNS else None) if cols[k] else np.zeros(0)
            for k in CSV_HEADER]


def branch_summary(branches) -> list[dict]:
    """One entry per branch for ``summary.json``."""
    out = []
    for b in branches:
        out.append({"branch": b.id, "signature": b.label, "family": b.sig.family, "m": b.sig.m, "k": b.sig.k,
                    "points": len(b),
                    "T_range": [float(b.T.min()), float(b.T.max())],
                    "T1_range": [float(b.T1.min()), float(b.T1.max())],
                    "T2_range": [float(b.T2.min()), float(b.T2.max())],
                    "xi_range": [float(b.xi.min()), float(b.xi.max())],
                    "dPL_range": [float(b.dPL.min()), float(b.dPL.max())],
                    "loss_per_T_range": [float(b.loss_per_T.min()), float(b.loss_per_T.max())],
                    "viscous_loss_range": [float(b.viscous.min()), float(b.viscous.max())],
                    "xi_total_range": [float(b.xi_total.min()), float(b.xi_total.max())],
                    "grazing_points": int(b.grazing.sum()),
                    "stable_points": int(b.stable.sum()),
                    "ends": list(b.ends),
                    "events": [{"kind": e["kind"], "index": int(e["index"]), "T": float(e["T"])} for e in b.events]})
    return out


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
        rows = branch_rows(res.branches)
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
