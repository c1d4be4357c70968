"""The survey under mesh refinement: does the dissipation of the real motion converge where the paper's class vanishes?

For a list of sizes ``N`` the same survey (same forcing periods; for the chain,
whose length is ``N``, the periods scale with ``N``) runs in ``DIR/N00016/``
(each resumable), and ``DIR/survey_refine.csv`` gathers, per forcing period and
``N``, the motion's kind, loss per period, ``xi_eq`` and ``xi_w`` with their
spread.  ``DIR/survey_refine.json`` holds observed rates and Richardson limits
of the three means (:func:`plbar.studies.refine.convergence.converge`, with the
standard error of each mean as its noise floor: an irregular motion's mean is a
statistic), or the reason where there is none.

The continuum is the N = infinity row (``N = 0, h = 0`` in the table, ``DIR/continuum/``): where the case has one
(an undamped uniform FE bar with a plastic contact and one point load, :func:`continuum_case`) the same survey runs on
:mod:`plbar.continuum`, and for every mean ``survey_refine.json`` gives each mesh's error against it, its z-score
(the error over the two means' standard errors, ``std / sqrt(record)``: periods taken as independent, so a screen)
and the observed orders between successive meshes (:func:`plbar.studies.refine.known_limit`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ...app import Case
from ...errors import InputError
from ...util.files import write_csv, write_json
from ...util.options import keywords
from ...util.outputs import claim_folder, fingerprint
from ...util.reprs import build
from ...util.version import __version__
from ..execution import run_options
from ..refine import MIN_MESHES, converge, known_limit
from .study import default_record, run_survey

__all__ = ["SurveyRefinement", "run_survey_refine", "continuum_case", "REFINED", "REFINE_COLUMNS", "MIN_MESHES"]

#: what a survey refinement owns in its folder (each size's survey is in its own folder, owned by ``survey``)
REFINE_OWNED = ("survey_refine.csv", "survey_refine.json", "survey_refine.png", "survey_refine.pdf", "N[0-9]*",
                "continuum", ".*.part.*")

#: the means whose convergence is measured (with their spread column)
REFINED = (("loss_per_T", "loss_std"), ("xi_eq", "xi_std"), ("xi_w", None))
REFINE_COLUMNS = ("N", "h", "T", "T_L", "kind", "m", "impacts_per_T", "loss_per_T", "loss_std", "xi_eq", "xi_std",
                  "xi_w", "amp_c", "stuck_fraction", "energy_residual")


@dataclass(frozen=True)
class SurveyRefinement:
    """Surveys of one case at several sizes N (:func:`run_survey_refine`) and the convergence of their means.

    Attributes
    ----------
    case : Case
    rows : list of dict
        ``survey_refine.csv``: one row per forcing period and N (:data:`REFINE_COLUMNS`).
    rates : dict
        ``survey_refine.json``: per ``T/L``, the kinds and, per mean, its values, observed rate and
        Richardson limit, or why there is none.
    surveys : dict
        N -> the :class:`Survey` of that size (each in its own folder ``DIR/N00016/``).
    summary : dict
        Sizes, forcing periods, periods simulated and recorded, run time.
    files : dict
        Written files, name -> Path.
    """

    case: Case
    rows: list = field(repr=False)
    rates: dict = field(repr=False)
    surveys: dict = field(repr=False)
    summary: dict = field(repr=False)
    files: dict = field(default_factory=dict, repr=False)

    def __repr__(self) -> str:
        return build("SurveyRefinement", {"N": self.summary["sizes"], "T/L": len(self.rates), "rows": len(self.rows),
                                          "seconds": round(self.summary["seconds"], 3), "files": len(self.files)})


def _case_at(case: Case, n: int) -> Case:
    if case.mesh_file:
        raise InputError("a mesh file fixes the mesh; a refinement builds its meshes from N (drop --mesh-file)")
    if case.model == "chain" and case.load_points:          # the chain's length is N: positions scale with it
        k = n / case.n_eff
        return replace(case, n=n, load_points=tuple((s * k, a) for s, a in case.load_points))
    return replace(case, n=n)


def continuum_case(case: Case, steps: int | None = None) -> tuple[Case | None, str]:
    """The continuum of an FE ``case`` (``model = "continuum"``, ``steps`` per ``L/c``; with its Rayleigh damping,
    solved by exact modes), or None and why not."""
    if case.model != "fe":
        return None, "the chain is not a discretised continuum here (model = 'fe' is)"
    if case.restitution:
        return None, "restitution > 0: the continuum solver has a plastic contact"
    if case.point_masses:
        return None, "point masses away from the end have no continuum counterpart here"
    try:
        bar = case.bar()
        return Case(model="continuum", n=steps, length=bar.length, EA=case.EA, rhoA=case.rhoA,
                    end_mass=case.end_mass, end_mass_absolute=case.end_mass_absolute,
                    load_points=case.load_points, rayleigh=case.rayleigh), ""
    except InputError as exc:
        return None, str(exc)


def run_survey_refine(case: Case, sizes, T, periods: int = 1000, record: int | None = None,
                      out="plbar-survey-refine", no_continuum: str = "", **options) -> SurveyRefinement:
    """Surveys of ``case`` at every size in ``sizes`` and the convergence of their means, with the continuum's
    survey as the N = infinity row where the case has a continuum (:func:`continuum_case`) and ``no_continuum``
    gives no reason to leave it out (the command line's: its cost).

    ``T`` are forcing periods of ``case`` (its own ``N``); for the chain they scale with ``N / N0``.  The keyword
    options ``executor, progress, overwrite, plot`` are the run options (:class:`plbar.studies.RunOptions`)
    of this study and of every survey it runs.
    """
    opts = run_options(options, "run_survey_refine")
    t0 = time.perf_counter()
    record = default_record(periods) if record is None else record
    sizes = sorted({int(n) for n in sizes})
    if len(sizes) < 2 or sizes[0] < 2:
        raise InputError(f"sizes = {sizes}: give at least two sizes >= 2 for a refinement")
    folder = Path(out)
    T = np.atleast_1d(np.asarray(T, float))
    what = {"case": {k: v for k, v in case.to_dict().items() if k != "n"}, "T": T.tolist(), "periods": periods,
            "record": record}                      # not the sizes: more sizes extend the same study
    claim_folder(folder, "survey-refine", fingerprint(what), REFINE_OWNED, opts.overwrite)
    tau0 = case.bar().transit                   # T_L, the T/L= keys: T c / L (plbar.model.Bar.transit)
    rows, surveys = [], {}
    for n in sizes:
        c = _case_at(case, n)
        scale = n / case.n_eff if case.model == "chain" else 1.0
        s = run_survey(c, T * scale, periods, record, folder / f"N{n:05d}", **keywords(opts))
        surveys[n] = s
        t = s.rows("rest")
        tau, L = c.bar().transit, c.bar().length
        for i in range(t["T"].size):
            rows.append({"N": n, "h": L / n if case.model == "fe" else 1.0 / n,     # the chain: L = N
                         "T": float(t["T"][i]), "T_L": float(t["T"][i] / tau),
                         **{k: (t[k][i].item() if hasattr(t[k][i], "item") else t[k][i])
                            for k in REFINE_COLUMNS[4:]}})
    cont, why = continuum_case(case) if not no_continuum else (None, no_continuum)
    if cont is not None:
        s = run_survey(cont, T, periods, record, folder / "continuum", **keywords(opts))
        surveys[0] = s
        t = s.rows("rest")
        for i in range(t["T"].size):
            rows.append({"N": 0, "h": 0.0, "T": float(t["T"][i]), "T_L": float(t["T"][i] / tau0),
                         **{k: (t[k][i].item() if hasattr(t[k][i], "item") else t[k][i])
                            for k in REFINE_COLUMNS[4:]}})
    rates = _rates(rows, T / tau0, record, why, tau0)
    files = _write(folder, rows, rates)
    if opts.plot:
        files["figure"] = _plot(folder, rates)
    summary = {**what, "sizes": sizes, "seconds": time.perf_counter() - t0, "plbar_version": __version__}
    return SurveyRefinement(case, rows, rates, surveys, summary, files)


def _against(sel: list[dict], c: dict, q: str, spread, record: int) -> dict:
    """Each mesh's error against the continuum's mean ``c[q]``, its z-score and the orders (``known_limit``)."""
    if c.get("kind") == "failed":
        return {"continuum": None, "why": "the continuum's march stopped: its switches accumulate (chatter)"}
    if not np.isfinite(c[q]):
        return {"continuum": None, "why": f"{q} is not defined for the continuum (plbar.studies.survey.continuum)"}
    se = lambda r: (r[spread] / np.sqrt(record)) if spread else 0.0  # noqa: E731
    vals = np.array([r[q] for r in sel], float)
    err = vals - c[q]
    sd = np.array([np.hypot(se(r), se(c)) for r in sel])
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(sd > 0, err / sd, np.nan)
    plain = lambda a: [float(x) if np.isfinite(x) else None for x in a]  # noqa: E731
    out = {"continuum": float(c[q]), "continuum_se": float(se(c)), "error": plain(err), "z": plain(z)}
    if len(sel) >= 2:
        k = known_limit(q, [r["h"] for r in sel], vals, float(c[q]), n=[r["N"] for r in sel],
                        noise=float(sd.max())).as_dict()
        why = k.get("why") or ""
        if sd.max() > 0:
            why = why.replace("(|q - limit| at round-off)", "(the error is within the standard errors)")
        out.update(orders=k.get("rates"), order=k.get("rate"), orders_why=why)
    return out


def _rates(rows: list[dict], TL, record: int, no_continuum: str = "", length: float = 1.0) -> dict:
    """Per forcing period (keyed ``T/L=...``, the period in transit times ``T c / L``; ``T``: the case's own, in its
    time unit, ``length`` the transit time :attr:`plbar.model.Bar.transit`), the convergence of the means."""
    out = {}
    for tl in TL:
        at = [r for r in rows if abs(r["T_L"] - tl) <= 1e-12 * tl]
        cont = next((r for r in at if r["N"] == 0), None)
        sel = sorted((r for r in at if r["N"] > 0), key=lambda r: r["N"])
        h = np.array([r["h"] for r in sel])
        n = [r["N"] for r in sel]
        key = f"T/L={tl:.6g}"
        out[key] = {"T": float(tl * length), "kinds": [r["kind"] for r in sel], "N": n}
        for q, spread in REFINED:
            vals = np.array([r[q] for r in sel], float)
            noise = float(max((r[spread] for r in sel), default=0.0)) / np.sqrt(record) if spread else 0.0
            c = converge(q, h, vals, n=n, noise=noise).as_dict()
            if noise > 0 and "round-off" in c.get("why", ""):
                c["why"] = c["why"].replace("differences at round-off", "differences below the standard error of "
                                            "the means: the motion is irregular")
            if len(sel) < MIN_MESHES:
                c.update(rate=None, limit=None, error=None, fitted=None,
                         why=f"{len(sel)} meshes: a rate needs at least {MIN_MESHES}")
            if c["limit"] is not None and not c["caution"] and _beyond(vals, c["limit"]):
                c["caution"] = (f"the Richardson limit {c['limit']:.4g} (rate {c['rate']:.2g}) lies further from the "
                                "finest mesh than the meshes span: the values do not converge at that rate yet")
            out[key][q] = {"values": vals.tolist(), "meshes": len(sel), **c}
            if cont is not None:
                ac = out[key][q]["against_continuum"] = _against(sel, cont, q, spread, record)
                if ac.get("continuum") is not None:            # the continuum is the limit, not an extrapolation
                    out[key][q].update(_continuum_limit(out[key][q], ac, h, vals, n))
        if cont is None:
            out[key]["continuum"] = no_continuum or "none"
        else:
            ipt = float(cont["impacts_per_T"])
            out[key]["continuum"] = {"kind": cont["kind"], **({"impacts_per_T": ipt} if np.isfinite(ipt) else {})}
    return out


def _beyond(vals, limit: float) -> bool:
    """The extrapolated ``limit`` is further from the finest value than the values span (a rate near 0 sends it
    far beyond them: ``1 / (r^p - 1)`` times the last difference)."""
    v = np.asarray(vals, float)
    v = v[np.isfinite(v)]
    return bool(v.size >= 2 and abs(limit - v[-1]) > np.ptp(v))


def _continuum_limit(d: dict, ac: dict, h, vals, n) -> dict:
    """The fields of a mean whose limit is the continuum's value: the orders against it (:func:`known_limit`,
    ``against_continuum``), the Richardson numbers kept aside (``richardson``)."""
    k = known_limit(d["name"], h, vals, ac["continuum"], n=n).as_dict() if len(h) >= 2 else {}
    return {"richardson": {f: d.get(f) for f in ("rate", "limit", "error", "fitted", "why", "caution")},
            "limit": ac["continuum"], "error": ac.get("continuum_se", 0.0), "rate": ac.get("order"),
            "fitted": k.get("fitted"), "method": "continuum", "why": ac.get("orders_why") or "",
            "caution": k.get("caution", "")}


def _write(folder: Path, rows: list[dict], rates: dict) -> dict:
    cols = list(REFINE_COLUMNS)
    fmts = ["%d", "%.17g", "%.17g", "%.17g", "%s", "%d"] + ["%.17g"] * (len(cols) - 6)
    return {"table": write_csv(folder / "survey_refine.csv", cols, [np.array([r[c] for r in rows], dtype=object
                                                                              if c == "kind" else None) for c in cols],
                               fmts),
            "rates": write_json(folder / "survey_refine.json", rates)}


def _plot(folder: Path, rates: dict):
    from ...visuals import convergence_plot

    class _Item:
        def __init__(self, name, d):
            self.name, self.h, self.q = name, d["h"], d["q"]
            self.limit, self.rate, self.fitted = d.get("limit"), d.get("rate"), d.get("fitted")
            self.caution = d.get("caution") or ""      # a limit not stated is not drawn as one

    items = [_Item(f"T = {d['T']:.6g} {q}", d[q]) for d in rates.values() for q, _ in REFINED]
    return convergence_plot(items, folder, "survey_refine", "the real motion under mesh refinement")
