"""``plbar sweep-loads`` (every load from one solve), ``plbar refine`` (a list of N), ``plbar figures``.

Handlers are thin calls into :mod:`plbar.studies`; they return exit codes
(errors become codes in :func:`plbar.cli.main.main`).
"""

from __future__ import annotations

import importlib.util
from dataclasses import replace

import numpy as np

from ..errors import InputError
from ..util.outputs import claim_folder, fingerprint, require
from ..util.progress import message
from .common import (CASE_OPTIONS, case_args, case_from_args, hidden, output_args, plural, progress, report,
                     yes_arg)

__all__ = ["register"]

#: what ``plbar figures`` owns in its folder
FIGURES_OWNED = ("fig[0-9]*.png", "fig[0-9]*.pdf", ".*.part.*")

def _cmd_sweep(a) -> int:
    from ..app import cost_note
    from ..studies.loads import sweep_loads

    if a.amplitude is not None:
        raise InputError("--amplitude does not apply to sweep-loads: it reports a unit force at every position (its "
                         "xi_eq is that of any amplitude Q, its Delta_PL is Q^2 times the unit force's); drop "
                         "--amplitude")
    case, _ = case_from_args(a)
    note = cost_note(case, yes=a.yes)
    if note and not a.quiet:
        message(note)
    plot = not a.no_plot and importlib.util.find_spec("matplotlib") is not None
    r = sweep_loads(case, a.out, positions=a.positions, per_element=a.per_element, pairs=not a.no_pairs,
                    progress=progress(a), plot=plot, positions_csv=a.positions_csv, overwrite=a.overwrite)
    s = r.summary
    lines = [f"plbar sweep-loads: {plural(len(r), 'path point')} from one solve "
             f"({s['times']['solve']:.3g} s), {plural(s['positions'], 'position')} and the load of the largest "
             f"xi_eq in {s['times']['load_study']:.3g} s"]
    for fam, e in s.get("families", {}).items():
        lines.append(f"  {fam:8s}: largest xi_eq of any load = {e['xi_worst_max']:.4g}, best single force "
                     f"{e['xi_best_single_max']:.4g} at s = {e['s_at_best_single']:.4g}")
    if s.get("no_path"):
        lines.append(f"  {plural(len(s['no_path']), 'load')} with no path (h(q) = 0): see summary.json 'no_path'")
    lines.append("  wrote " + ", ".join(str(f) for f in r.files.values()))
    report(a, s, r.files, "\n".join(lines))
    return 0


def _refine_cases(a) -> list:
    """The series of ``plbar refine``: the model options (or a case file), or the old ``--series`` names."""
    from ..app import Case
    from ..studies.refine import parse_series

    if a.T2_frac:
        raise InputError("--T2-frac is no longer used: refine follows each family inside its period window "
                         "(--family ANCHOR --window W)")
    if a.series:
        given = [f for d, f in CASE_OPTIONS.items() if d != "grid" and getattr(a, d, None) is not None]
        if given or a.case:
            raise InputError(f"--series conflicts with {given[0] if given else '--case'}; give the model with "
                             "--model/--element/--mass (one series) or --series names, not both")
        cases = [Case(**parse_series(s)) for s in a.series]
    else:
        cases = [case_from_args(a)[0]]
    if a.frac:                                       # old spelling: loads at fractions of the length
        cases = [replace(c, load_nodes=(), load_points=((f * c.bar().length, 1.0),)) for c in cases for f in a.frac]
    return cases


def _rate_line(q: str, c: dict, always: bool) -> str:
    """One quantity of the refine table: its limit and rate with the meshes they rest on, or why none is stated."""
    n = len(c["h"])
    on = f"{n} mesh{'' if n == 1 else 'es'}"
    if c["rate"] is None:
        return f"    {q:13s} no rate: {c['why']}"
    if c.get("caution") and not always:
        return f"    {q:13s} no rate stated: {c['caution']} (--rates-always prints it)"
    fit = f", fitted over all N: {c['fitted']:.3f}" if c.get("fitted") is not None else ""
    lim = f"-> {c['limit']:.6g}: " if c.get("limit") is not None else ""
    warn = f" [{c['caution']}]" if c.get("caution") else ""
    return f"    {q:13s} {lim}rate {c['rate']:.3f} ({on}{fit}){warn}"


def _refine_lines(r, always: bool = False) -> list[str]:
    from ..studies.refine import MIN_MESHES, PLOTTED

    lines = []
    for key in dict.fromkeys((row["series"], row["family"]) for row in r.rows):
        fam = r.family(*key)
        # the periods in the case's time unit where the bar is one (FE: the same L on every mesh); the chain's L = N
        # changes with N, so its invariant T/L
        L = {row["length"] for row in fam}
        scale, tl = (L.pop(), "T  ") if len(L) == 1 else (1.0, "T/L")
        lines.append(f"{key[0]}, family {key[1]}:")
        lines.append(f"      N  status        adm.  main stretch {tl}       largest xi_eq  at {tl}     S/M_e")
        for row in fam:
            rng = (f"[{scale * row['T_min_L']:.5g}, {scale * row['T_max_L']:.5g}]"
                   if np.isfinite(row["T_min_L"]) else "-").ljust(22)
            # xi_max and S/M_e in significant digits (a small end mass makes both small: 0.00000 says nothing)
            xi = (f"{row['xi_max']:<13.5g}  {scale * row['T_at_max_L']:<8.5g}" if np.isfinite(row["xi_max"])
                  else "-".ljust(22))
            sm = f"{row['impact_mass'] / row['end_mass']:.5g}" if row["end_mass"] > 0 else "-"
            lines.append(f"  {row['n']:5d}  {row['status']:12s} {row['admissible']:5d}  {rng} {xi}  {sm}")
        rates = r.rates[key[0]][key[1]]
        lines += [_rate_line(q, rates[q], always) for q in PLOTTED if q in rates]
        # one verdict for xi_max: its decay law only where the line above states a rate (its limit, 0, is
        # approached), never after "no rate": values that wander or grow do not decay like anything
        d, x = rates["xi_decay"], rates.get("xi_max", {})
        stated = x.get("rate") is not None and not x.get("caution")
        if d.get("model") and (always or (stated and len(d["h"]) >= MIN_MESHES)):
            tag = "" if stated else " [not a verdict: xi_max has no rate stated]"
            lines.append(f"    xi_max decays like {d['formula']} ({d['model']} law fits best, {len(d['h'])} "
                         f"meshes){tag}")
    return lines


def _cmd_refine(a) -> int:
    from ..studies import get_executor
    from ..studies.refine import TrackSettings, run_refine

    cases = _refine_cases(a)
    grid = tuple(a.grid) if a.grid else (cases[0].grid if a.case else (200, 200))
    st = TrackSettings(width=a.window, grid=grid, pick=a.pick, step=a.step)
    kind = "dask" if a.scheduler else a.executor
    if kind == "local" and len(cases) * len(a.family or ["T0_II/2"]) == 1:
        kind = "serial"          # one task: in this process, with its progress per mesh and the thread pool
    with get_executor(kind, a.scheduler, a.workers) as ex:
        r = run_refine(cases, a.sizes, a.family or ["T0_II/2"], st, a.out, a.rates_always, executor=ex,
                       progress=progress(a), overwrite=a.overwrite,
                       plot=not a.no_plot and importlib.util.find_spec("matplotlib") is not None)
    note = _no_continuum_row(cases[0])
    lines = _refine_lines(r, a.rates_always) + ([note] if note else []) + [
        f"done in {r.time:.1f} s; wrote " + ", ".join(
            str(f) for v in r.files.values() for f in (v if isinstance(v, list) else [v]))]
    rows = [{k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in row.items()}
            for row in r.rows]
    report(a, r.summary, r.files, "\n".join(lines), rates=r.rates, rows=rows)
    return 0


def _no_continuum_row(case) -> str:
    """Why ``refine`` (the paper's class, a periodic response) has no N = infinity row (docs/continuum.md)."""
    if case.model != "fe":
        return ""
    if case.rayleigh is not None:
        return ("N = infinity: none computed: the damped continuum (a Kelvin-Voigt bar, plbar.continuum."
                "simulate_modal) is simulated, but no periodic orbit of it is polished; the Richardson limits above "
                "are the estimate; the real motion's continuum row: plbar survey -N ...")
    if case.end_mass_value == 0:
        return ("N = infinity: without an end mass the continuum's plastic impact costs nothing (the bare end stops "
                "without inertia), so Delta_PL and xi_eq tend to 0 under refinement")
    return ("N = infinity: the undamped continuum has no periodic response with an impact loss (each plastic impact "
            "sends a velocity jump that the bar carries forever: docs/continuum.md), so the limits above are the "
            "meshes' orbits', not the continuum's; the real motion's continuum row: plbar survey -N ...")


def _cmd_figures(a) -> int:
    require("matplotlib", "plbar figures")
    from ..studies.paper import FIGURES, make_all

    bad = [w for w in a.only or () if w not in FIGURES]
    if bad:
        raise InputError(f"--only {bad[0]} is not a figure; choose from {', '.join(FIGURES)}")
    grid = tuple(a.grid or (200, 200))
    with claim_folder(a.out, "figures", fingerprint({"grid": list(grid)}), FIGURES_OWNED, a.overwrite) as claim:
        files = make_all(claim.folder, grid=grid, which=a.only, progress=progress(a))
    report(a, {"figures": len(files), "grid": list(grid)}, {"figures": files},
           f"wrote {plural(len(files), 'file')} into {a.out}")
    return 0


def _executor_args(p) -> None:
    g = p.add_argument_group("execution")
    g.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="dask scheduler address (tcp://host:8786) or scheduler file; implies --executor dask")
    g.add_argument("--executor", choices=("local", "serial", "dask"), default="local",
                   help="local process pool, serial, or dask (LocalCluster without --scheduler); a refinement "
                        "with one task runs in this process [local]")
    g.add_argument("--workers", type=int, default=None, metavar="W", help="worker processes [all cores]")


def register(sub) -> None:
    """Add ``sweep-loads``, ``refine`` and ``figures`` to the ``plbar`` subparsers ``sub``."""
    s = sub.add_parser("sweep-loads", help="xi_eq for loads anywhere on the bar, from one solve (paper Sec. 4.2)",
                       description="Solve the case once (its load is the reference: any load with a contact "
                                   "response gives the same paths), then xi_eq and Delta_PL of a unit force at "
                                   "many positions, the node pairs (Fig. 9) and the load distribution of the largest "
                                   "xi_eq at every path point.  Writes DIR/xi_positions.npz, worst_load.csv, "
                                   "worst_load_shapes.npz, load_pairs.csv, xi_along_mesh.vtu, xi_T_s.png, "
                                   "summary.json.")
    output_args(s, "plbar-sweep", "study folder")
    s.add_argument("--positions", "--at", type=float, nargs="+", default=None, metavar="S",
                   help="unit-force positions [--per-element steps over (0, L]]")
    s.add_argument("--per-element", type=int, default=50, metavar="K", help="default positions per element [50]")
    s.add_argument("--positions-csv", action="store_true",
                   help="also write the positions table as CSV (xi_positions.csv: one row per path point and "
                        "position; large: about 85 bytes a row)")
    s.add_argument("--no-pairs", action="store_true", help="skip the node-pair table")
    s.add_argument("--pairs", action="store_true", help=hidden)
    s.add_argument("--no-plot", action="store_true", help="skip xi_T_s.png")
    yes_arg(s)
    case_args(s, "the reference load", at=False)     # --at: the old spelling of --positions
    s.set_defaults(func=_cmd_sweep)

    r = sub.add_parser("refine", help="families followed through a list of N, full model (Sec. 4.3)",
                       description="Mesh refinement: seed each family (--family anchor, --window) on the coarsest "
                                   "mesh by the scan, then follow its curve to every finer mesh with the full model. "
                                   "Writes DIR/refine.csv (one row per family and N), DIR/refine_rates.json "
                                   "(observed rates, Richardson limits, continuum limits), DIR/refine_convergence.png "
                                   "and DIR/refine_family.png (with matplotlib).  Resumable (per mesh).")
    output_args(r, "plbar-refine", "study folder (resumable)")
    case_args(r, "the load, at the same place on every mesh", sizes=(3, 4, 5, 6, 8, 12, 16),
              refused=("mesh_file", "modes", "T1", "T2", "method"))
    r.add_argument("--family", action="append", default=None, metavar="ANCHOR",
                   help="family anchor: T0_I, T0_II/2, k*T0_I, a*T0_II/b or a period; repeatable [T0_II/2]")
    r.add_argument("--window", type=float, default=0.15, metavar="W",
                   help="relative half-width of the family's period window [0.15]")
    r.add_argument("--pick", choices=("longest", "xi", "nearest", "all"), default="longest",
                   help="the seed branch in the window: most points, largest xi_eq, nearest the anchor, or all "
                        "[longest]")
    r.add_argument("--step", type=float, default=1 / 200, metavar="H",
                   help="largest continuation step, as a fraction of the window [0.005]")
    r.add_argument("--no-plot", action="store_true", help="skip the plots")
    r.add_argument("--rates-always", action="store_true",
                   help="state every rate and limit, also those resting on fewer than 4 meshes or on values whose "
                        "successive differences change sign (marked)")
    r.add_argument("--series", nargs="+", default=None, help=hidden)
    r.add_argument("--frac", type=float, nargs="+", default=None, help=hidden)
    r.add_argument("--T2-frac", type=float, nargs=2, default=None, help=hidden)
    _executor_args(r)
    r.set_defaults(func=_cmd_refine, resumable=True)

    f = sub.add_parser("figures", help="the paper's figures (2-9) for our numbers, PNG and PDF",
                       description="Draw the figure families of the paper's Sec. 4 into DIR (needs matplotlib).")
    output_args(f, "plbar-figures", "output folder")
    f.add_argument("--grid", type=int, nargs=2, default=None, metavar=("N1", "N2"), help="scan grid [200 200]")
    f.add_argument("--only", nargs="+", default=None, metavar="FIG",
                   help="some of: fig2 fig3 fig4 fig56 fig7 fig8 fig9 [all]")
    f.set_defaults(func=_cmd_figures)
