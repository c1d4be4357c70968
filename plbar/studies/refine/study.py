"""Mesh-refinement study (paper Sec. 4.3): families followed through N, with the full model.

A *series* is a bar without its size: the paper's chain (``L = N``) or a
finite-element bar (``L`` fixed), with its element, mass, end mass and load.
For each series and each family anchor (:mod:`.anchors`) one task seeds the
family on the coarsest mesh and carries it through the finer ones
(:mod:`.track`); every level is checkpointed (``DIR/levels/<task>/N00064.json``,
written atomically), so a rerun resumes inside a task, and the tasks run on any
executor through :func:`plbar.studies.run_study`.  Tables, observed rates and
plots are assembled by :mod:`.tables`.
"""

from __future__ import annotations

import contextvars
import hashlib
import json
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

from ...app import Case
from ...app.applies import refuse_static_part
from ...errors import InputError
from ...model import ELEMENTS, MASSES
from ...util.check import show
from ...util.files import write_json
from ...util.outputs import claim_folder, fingerprint
from ...util.progress import progress_bar
from ...util.reprs import build
from ...util.version import __version__, code_hash
from .anchors import family_label, family_title, parse_anchor, slug
from .tables import convergence_of, decay_of, refine_rows, write_refine
from ..execution import SerialExecutor, Study, run_options, run_study
from .track import TrackSettings, carry_level, mark_merges, seed_levels

__all__ = ["RefineStudy", "parse_series", "series_name", "refine_study", "refine_task", "track_family", "run_refine",
           "case_at", "refine_fingerprint", "REFINE_OWNED", "PLOTTED"]

#: the quantities drawn in ``refine_convergence.png``
PLOTTED = ("T0_I_L", "T0_II_L", "S/M_e", "T_mid_T0I", "T_spread_T0I", "xi_max")

#: Case fields a series may set (everything but the size)
SERIES_FIELDS = ("model", "element", "mass", "length", "EA", "rhoA", "m", "k", "grading", "end_mass",
                 "end_mass_absolute", "load_nodes", "load_points", "rayleigh")


@dataclass(frozen=True)
class RefineStudy:
    """A refinement study (:func:`run_refine`): one row per series, family and N, the rates, the files.

    Attributes
    ----------
    rows : list of dict
        ``refine.csv``, one row per series, family and N (:data:`.tables.REFINE_HEADER`).
    rates : dict
        ``refine_rates.json``: per series and family, quantity -> :meth:`Convergence.as_dict`, and ``xi_decay``.
    summary : dict
        The study's sizes, families, series, rows and run time.
    files : dict
        Written files, name -> Path (a list for a figure in PNG and PDF).
    """

    rows: list = field(repr=False)
    rates: dict = field(repr=False)
    summary: dict = field(repr=False)
    files: dict = field(default_factory=dict, repr=False)

    @property
    def time(self) -> float:
        """Run time (s)."""
        return self.summary["seconds"]

    def family(self, series: str, family: str) -> list[dict]:
        """The rows of one family of one series, coarse to fine."""
        return [r for r in self.rows if r["series"] == series and r["family"] == family]

    def __repr__(self) -> str:
        s = self.summary
        return build("RefineStudy", {"series": s["series"], "families": s["families"], "N": s["ns"],
                                     "rows": len(self.rows), "seconds": round(s["seconds"], 3),
                                     "files": len(self.files)})


def parse_series(name: str) -> dict:
    """Case fields of a series name (``chain``, ``fe-P1-lumped``, ``fe-P2-consistent`` ...)."""
    if name == "chain":
        return {"model": "chain"}
    parts = name.split("-")
    if len(parts) != 3 or parts[0] != "fe" or parts[1] not in ELEMENTS or parts[2] not in MASSES:
        raise InputError(f"series = {name!r} must be 'chain' or 'fe-<{'|'.join(ELEMENTS)}>-<{'|'.join(MASSES)}>'")
    return {"model": "fe", "element": parts[1], "mass": parts[2]}


def series_name(base: dict) -> str:
    """A short label of a series (``fe-P1-lumped``, with ``+Me0.5`` for an end mass)."""
    name = "chain" if base.get("model", "chain") == "chain" else \
        f"fe-{base.get('element', 'P1')}-{base.get('mass', 'lumped')}"
    me = base.get("end_mass", 0.0)
    if me:
        name += f"+Me{me:g}" + ("abs" if base.get("end_mass_absolute") else "")
    if base.get("rayleigh"):                     # inherent damping (issue 21): the same (alpha, beta) at every N
        name += "+rayleigh{:g},{:g}".format(*base["rayleigh"])
    return name


def _series(case: Case) -> dict:
    """The series fields of a case (JSON-able; the load as given, positions in the model's length)."""
    d = case.to_dict()
    out = {k: d[k] for k in SERIES_FIELDS if k in d}
    for k in ("load_nodes", "load_points"):
        out[k] = [list(p) for p in out.get(k, ())]
    if out["model"] == "chain":
        for k in ("element", "mass", "length", "EA", "rhoA", "grading"):
            out.pop(k, None)
    return out


def _ns(ns) -> list[int]:
    try:
        out = sorted({int(n) for n in ns})
    except (TypeError, ValueError):
        raise InputError(f"N = {show(ns)} must be a list of integers (masses / elements)") from None
    if not out or out[0] < 2:
        raise InputError(f"N = {show(ns)}: give the sizes of the refinement, each >= 2 (rates need three)")
    return out


def refine_study(cases, ns, families=("T0_II/2",), settings: TrackSettings | None = None,
                 checkpoints=None) -> Study:
    """The tasks of a refinement study: one per (series, family).

    Parameters
    ----------
    cases : sequence of Case
        The series (the case's own ``n`` is ignored; a chain's load positions
        are scaled with ``N``: a load at ``s`` on the case's chain of ``N0`` masses
        sits at ``s N / N0`` on the chain of ``N``).
    ns : sequence of int
        Masses (chain) / elements (FE bar), coarse to fine.
    families : sequence of str
        Anchors (:func:`plbar.studies.refine.anchors.parse_anchor`).
    settings : TrackSettings
    checkpoints : path, optional
        Folder for the per-level checkpoints of the tasks.
    """
    st = settings or TrackSettings()
    ns = _ns(ns)
    fams = [str(parse_anchor(f)) for f in families]
    if not fams:
        raise InputError("give at least one family anchor (T0_I, T0_II/2, ...)")
    tasks = []
    for case in cases:
        _refinable(case)
        base = _series(case)
        base["n0"] = case.n_eff
        for fam in fams:
            t = {"series": series_name(base), "family": fam, "ns": ns, "base": base,
                 "settings": {**asdict(st), "grid": list(st.grid)}}
            if checkpoints is not None:
                t["checkpoints"] = str(Path(checkpoints).resolve())
            tasks.append(t)
    params = {"ns": ns, "families": fams, "series": [t["series"] for t in tasks[::len(fams)]]}
    return Study("refine", refine_task, tuple(tasks), params)


def _refinable(case: Case) -> None:
    """Refuse what a refinement cannot honour (one line each, saying what to do instead)."""
    refuse_static_part(case, "refine follows families of the paper's scan",
                       "the real motion on each mesh: plbar survey -N N1 N2 ...")
    if case.restitution:
        raise InputError(f"restitution = {case.restitution:g}: refine follows families of the paper's class (a "
                         "plastic impact) through N, which need e = 0; the real motion on each mesh with rebounds: "
                         "plbar survey -N N1 N2 ... --restitution E")
    if case.modes is not None:
        raise InputError(f"the case keeps {case.modes} modes; a refinement follows the full model (xi_eq needs all "
                         "modes: a truncated impact loses the energy outside the kept modes); drop modes / --modes")
    if case.mesh_file:
        raise InputError(f"mesh_file = {case.mesh_file!r} fixes the mesh; a refinement builds its meshes from N "
                         "(uniform, or --grading R); drop the mesh file")
    if case.T1 is not None or case.T2 is not None or case.method != "continuation":
        raise InputError("a refinement searches each family's period window (--family ANCHOR --window W) with "
                         "continuation; drop T1/T2 (--T1/--T2) and method (--method)")


def case_at(base: dict, n: int) -> Case:
    """The case of a series at size ``n``."""
    b = dict(base)
    n0 = b.pop("n0", n)
    if b.get("model") == "chain" and b.get("load_points"):     # the chain's length is N: scale positions
        b["load_points"] = [[s * n / n0, a] for s, a in b["load_points"]]
    for k in ("load_nodes", "load_points"):
        b[k] = tuple(tuple(p) for p in b.get(k, ()))
    return Case(n=int(n), **b)


def _level_key(task: dict, n: int) -> str:
    core = {k: task[k] for k in ("family", "base", "settings")}
    core["ns"] = [m for m in task["ns"] if m <= n]
    core["code"] = code_hash()                       # a level is reused only by the code that computed it
    return hashlib.sha256(json.dumps(core, sort_keys=True).encode()).hexdigest()[:16]


def _read_level(path: Path, key: str):
    try:
        d = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return d.get("levels") if isinstance(d, dict) and d.get("key") == key else None


def track_family(task: dict, progress: bool = False) -> list[list[dict]]:
    """The levels of the family (or families, with ``pick = "all"``) of a task, coarse to fine.

    Levels already checkpointed under ``task["checkpoints"]`` are read back
    (same task, same sizes so far); every new one is written there atomically.
    """
    st = TrackSettings(**{**task["settings"], "grid": tuple(task["settings"]["grid"])})
    anchor = parse_anchor(task["family"])
    folder = Path(task["checkpoints"]) / f"{slug(task['series'])}-{slug(task['family'])}" \
        if task.get("checkpoints") else None
    chains: list[list[dict]] = []
    label = f"{task['series']} {task['family']}"
    with progress_bar(len(task["ns"]), progress, label, "mesh") as bar:
        def tick(j, k):                        # within a mesh: the carried points, so that the progress moves
            bar.set_description(f"{label}, N = {n}: point {j}/{k}")
            bar.update(0)

        for n in task["ns"]:
            key = _level_key(task, n)
            path = folder / f"N{n:05d}.json" if folder else None
            got = _read_level(path, key) if path else None
            if got is None:
                case = case_at(task["base"], n)
                got = seed_levels(case, anchor, st) if not chains else \
                    [carry_level(ch[-1], case, anchor, st, tick) for ch in chains]
                got = mark_merges(got, [family_label(task["family"], k, len(got)) for k in range(len(got))], st)
                if path:
                    write_json(path, {"key": key, "n": n, "levels": got})
            chains = [[lv] for lv in got] if not chains else [ch + [lv] for ch, lv in zip(chains, got)]
            bar.set_description(label)
            bar.update(1)
    return chains


def refine_task(task: dict) -> dict:
    """The study task: ``{"series", "family", "chains": [[level, ...], ...]}`` (JSON-able)."""
    return {"series": task["series"], "family": task["family"], "chains": track_family(task, _SHOW.get())}


#: what a refinement study owns in its folder (cleared before another study is written there)
REFINE_OWNED = ("refine.csv", "refine_rates.json", "refine_max.csv", "refine_convergence.png",
                "refine_convergence.pdf", "refine_family.png", "refine_family.pdf", "study.json", "tasks", "levels",
                ".*.part.*")

#: finished work in a refinement folder (a failed study that has some is kept: a rerun resumes it)
FINISHED = ("levels/*/N*.json", "tasks/*.json")

_SHOW = contextvars.ContextVar("plbar_refine_progress", default=False)


def refine_fingerprint(study: Study) -> str:
    """The identity of a refinement study: its series and settings, not its sizes or families.

    A study with more sizes or other families is the same study extended: its finished meshes are reused
    (the checkpoints of :func:`track_family` are keyed by the sizes up to each mesh).
    """
    series = [t["base"] for t in study.tasks]
    return fingerprint({"series": [json.loads(x) for x in dict.fromkeys(json.dumps(b, sort_keys=True)
                                                                         for b in series)],
                        "settings": study.tasks[0]["settings"] if study.tasks else {}})


def run_refine(cases, ns, families=("T0_II/2",), settings: TrackSettings | None = None, out="plbar-refine",
               rates_always: bool = False, **options) -> RefineStudy:
    """Run (or resume, or extend with more sizes) a refinement study into ``out`` and write its tables and plots.

    The folder is claimed for ``refine`` (:func:`plbar.util.outputs.claim_folder`) with
    :func:`refine_fingerprint`: the same series and settings with other sizes or families extend the study
    (finished meshes are reused); another study or command is refused unless ``overwrite``.  A study that fails
    before any mesh is finished leaves nothing behind.  ``rates_always``: the plot states every rate, also
    those with a caution (:func:`plbar.studies.refine.convergence.caution`).  ``cases, ns, families, settings``
    as :func:`refine_study`; the keyword options ``executor, progress, overwrite, plot`` are the study's run options
    (:class:`plbar.studies.RunOptions`).

    Returns
    -------
    RefineStudy
        ``rows`` (one per series, family and N), ``rates`` (per series and family:
        quantity -> :meth:`Convergence.as_dict`, plus ``xi_decay``), ``summary``, ``files`` and ``time``.
    """
    opts = run_options(options, "run_refine")
    executor, progress = opts.executor, opts.progress
    t0 = time.perf_counter()
    folder = Path(out)
    study = refine_study(cases, ns, families, settings, checkpoints=folder / "levels")   # checks every input
    claim = claim_folder(folder, "refine", refine_fingerprint(study), REFINE_OWNED, opts.overwrite)
    token = _SHOW.set(progress and (executor is None or isinstance(executor, SerialExecutor)))
    try:
        results = run_study(folder, study, executor, progress=progress, overwrite=True)
    except BaseException as exc:
        claim.abandon(FINISHED, exc)           # nothing finished: leave nothing that blocks a corrected rerun
        raise
    finally:
        _SHOW.reset(token)
    rows = refine_rows(results)
    bases = {t["series"]: t["base"] for t in study.tasks}
    rates: dict = {}
    conv = {}
    for key in dict.fromkeys((r["series"], r["family"]) for r in rows):
        fam = [r for r in rows if (r["series"], r["family"]) == key]
        conv[key] = convergence_of(fam, bases[key[0]])
        rates.setdefault(key[0], {})[key[1]] = {**{q: c.as_dict() for q, c in conv[key].items()},
                                                "xi_decay": decay_of(fam)}
    files = write_refine(folder, rows, rates)
    if opts.plot:
        files.update(_plots(folder, results, conv, rates_always))
    summary = {**study.params, "rows": len(rows), "seconds": time.perf_counter() - t0, "plbar_version": __version__}
    return RefineStudy(rows, rates, summary, files)


#: what each plotted quantity is, for plot titles
TITLES = {"T0_I_L": "$T_0^I / L$", "T0_II_L": "$T_0^{II} / L$", "S/M_e": "impact mass $S / M_e$",
          "T_mid_T0I": "main stretch: mid period / $T_0^I$", "T_spread_T0I": "main stretch: width / $T_0^I$",
          "xi_max": r"largest $\xi_{eq}$"}


def _plots(folder: Path, results: list[dict], conv: dict, always: bool = False) -> dict:
    from ...visuals import convergence_plot, refine_family_plot

    items = []
    for (series, family), cs in conv.items():
        for q, c in cs.items():
            if q in PLOTTED:
                where = family_title(family) if len(conv) == 1 else f"{series}, {family_title(family)}"
                items.append(replace(c, name=f"{TITLES[q]} ({where})"))
    fams = [(f"{r['series']}, {family_title(family_label(r['family'], k, len(r['chains'])))}", ch)
            for r in results for k, ch in enumerate(r["chains"])]
    return {"convergence": convergence_plot(items, folder, "refine_convergence",
                                            "observed convergence against h = 1/N", always=always),
            "family": refine_family_plot(fams, folder, "refine_family")}
