"""``plbar sweep-loads`` (every load from one solve), ``plbar refine`` (a list of N), ``plbar figures``.

Handlers are thin calls into :mod:`plbar.studies`; they return exit codes
(errors become codes in :func:`plbar.cli.main.main`).
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np

from ..errors import OutputExistsError
from ..util.outputs import check_writable, clear_owned, require
from .common import case_args, case_from_args, hidden, output_args, progress, report

__all__ = ["register"]

SWEEP_OWNED = ("xi_positions.csv", "worst_load.csv", "worst_load_shapes.npz", "xi_along_mesh.vtu", "load_pairs.csv",
               "xi_T_s.png", "summary.json", "sweep.csv", "sweep_max.csv", "sweep_summary.json", "study.json",
               "tasks")


def _sweep_folder(a, case) -> Path:
    """The study folder, checked and cleared of an earlier sweep (another case's only with --overwrite)."""
    out = check_writable(a.out)
    old = out / "summary.json"
    if old.is_file() and not a.overwrite:
        try:
            prev = json.loads(old.read_text()).get("case")
        except (OSError, ValueError, AttributeError):
            prev = None
        if prev != json.loads(json.dumps(case.to_dict(), default=str)):
            raise OutputExistsError(f"study folder {str(out)!r} holds results of another case; "
                                    "choose another --out or pass --overwrite")
    clear_owned(out, SWEEP_OWNED)
    return out


def _cmd_sweep(a) -> int:
    from ..studies.loads import sweep_loads

    case, _ = case_from_args(a)
    out = _sweep_folder(a, case)
    plot = not a.no_plot and importlib.util.find_spec("matplotlib") is not None
    r = sweep_loads(case, out, positions=a.positions, per_element=a.per_element, pairs=not a.no_pairs,
                    progress=progress(a), plot=plot)
    s = r["summary"]
    lines = [f"plbar sweep-loads: {len(r['forms'])} path points from one solve ({s['times']['solve']:.3g} s), "
             f"{s['positions']} positions and the worst load in "
             f"{s['times']['load_study']:.3g} s"]
    for fam, e in s.get("families", {}).items():
        lines.append(f"  {fam:8s}: worst load xi_eq = {e['xi_worst_max']:.4f}, best single force "
                     f"{e['xi_best_single_max']:.4f} at s = {e['s_at_best_single']:.4g}")
    if s.get("no_path"):
        lines.append(f"  {len(s['no_path'])} load(s) have no path (h(q) = 0): see summary.json 'no_path'")
    lines.append("  wrote " + ", ".join(str(f) for f in r["files"].values()))
    report(a, {"summary": s, "files": {k: str(v) for k, v in r["files"].items()}}, "\n".join(lines))
    return 0


def _cmd_refine(a) -> int:
    from ..studies import get_executor, refine_study, refine_tables, run_study, write_refine_tables

    if a.case:
        from ..app import load_case

        case, _ = load_case(a.case)
        a.series = ["chain"] if case.model == "chain" else [f"fe-{case.element}-{case.mass}"]
        a.grid = case.grid
    st = refine_study(a.elements, a.series, a.frac, tuple(a.grid or (200, 200)),
                      tuple(a.T2_frac) if a.T2_frac else None)
    with get_executor("dask" if a.scheduler else a.executor, a.scheduler, a.workers) as ex:
        res = run_study(check_writable(a.out), st, ex, progress=progress(a), overwrite=a.overwrite)
    tb = refine_tables(st.tasks, res)
    files = write_refine_tables(a.out, tb)
    m = tb.maxima
    lines = [f"{m['series'][i]:18s} N = {m['n'][i]:3d}: T0_I = {m['T0_I'][i]:.4f}, T0_II = {m['T0_II'][i]:.4f}, "
             f"family T0_II/2: T in [{m['T_min'][i]:.4f}, {m['T_max'][i]:.4f}], max xi_eq = {m['xi_max'][i]:.4f}"
             for i in range(len(m["n"])) if m["family"][i] == "T0_II/2" and np.isfinite(m["T_min"][i])]
    lines += ["rates: " + json.dumps(tb.rates), "wrote " + ", ".join(str(f) for f in files.values())]
    report(a, {"rates": tb.rates, "files": {k: str(v) for k, v in files.items()}}, "\n".join(lines))
    return 0


def _cmd_figures(a) -> int:
    require("matplotlib", "plbar figures")
    from ..studies.figures import make_all

    files = make_all(check_writable(a.out), grid=tuple(a.grid or (200, 200)), which=a.only, progress=progress(a))
    report(a, {"files": [str(f) for f in files]}, f"wrote {len(files)} files into {a.out}")
    return 0


def _executor_args(p) -> None:
    g = p.add_argument_group("execution")
    g.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="dask scheduler address (tcp://host:8786) or scheduler file; implies --executor dask")
    g.add_argument("--executor", choices=("local", "serial", "dask"), default="local",
                   help="local process pool, serial, or dask (LocalCluster without --scheduler) [local]")
    g.add_argument("--workers", type=int, default=None, metavar="W", help="worker processes [all cores]")


def register(sub) -> None:
    """Add ``sweep-loads``, ``refine`` and ``figures`` to the ``plbar`` subparsers ``sub``."""
    s = sub.add_parser("sweep-loads", help="xi_eq for loads anywhere on the bar, from one solve (paper Sec. 4.2)",
                       description="Solve the case once (its load is the reference: any load with a contact "
                                   "response gives the same paths), then xi_eq and Delta_PL of a unit force at "
                                   "many positions, the node pairs (Fig. 9) and the worst load distribution at "
                                   "every path point.  Writes DIR/xi_positions.csv, worst_load.csv, "
                                   "worst_load_shapes.npz, load_pairs.csv, xi_along_mesh.vtu, xi_T_s.png, "
                                   "summary.json.")
    output_args(s, "plbar-sweep", "study folder")
    s.add_argument("--positions", "--at", type=float, nargs="+", default=None, metavar="S",
                   help="unit-force positions [--per-element steps over (0, L]]")
    s.add_argument("--per-element", type=int, default=50, metavar="K", help="default positions per element [50]")
    s.add_argument("--no-pairs", action="store_true", help="skip the node-pair table")
    s.add_argument("--pairs", action="store_true", help=hidden)
    s.add_argument("--no-plot", action="store_true", help="skip xi_T_s.png")
    case_args(s, "the reference load")
    s.set_defaults(func=_cmd_sweep)

    r = sub.add_parser("refine", help="the same case for a list of N: periods, path extent, xi_eq (Sec. 4.3)",
                       description="Mesh refinement: write DIR/refine.csv, DIR/refine_max.csv and "
                                   "DIR/refine_rates.json.  Resumable.")
    output_args(r, "plbar-refine", "study folder (resumable)")
    r.add_argument("--elements", "-N", "--n", type=int, nargs="+", default=[3, 4, 5, 6, 8, 12, 16], metavar="N",
                   help="masses / elements [3 4 5 6 8 12 16]")
    r.add_argument("--series", nargs="+", default=["chain"], metavar="S",
                   help="chain and/or fe-P1-lumped, fe-P1-consistent, fe-P2-lumped, fe-P2-consistent [chain]")
    r.add_argument("--frac", type=float, nargs="+", default=[0.5], metavar="F", help="load positions s/L [0.5]")
    r.add_argument("--case", default=None, metavar="FILE.toml",
                   help="take the series (model/element/mass) and the grid from a TOML case file")
    r.add_argument("--grid", type=int, nargs=2, default=None, metavar=("N1", "N2"), help="scan grid [200 200]")
    r.add_argument("--T2-frac", type=float, nargs=2, default=None, metavar=("LO", "HI"),
                   help="search T2 in [LO, HI] * T0_II/2 only (cheaper for large N)")
    _executor_args(r)
    r.set_defaults(func=_cmd_refine)

    f = sub.add_parser("figures", help="the paper's figures (2-9) for our numbers, PNG and PDF",
                       description="Draw the figure families of the paper's Sec. 4 into DIR (needs matplotlib).")
    output_args(f, "plbar-figures", "output folder")
    f.add_argument("--grid", type=int, nargs=2, default=None, metavar=("N1", "N2"), help="scan grid [200 200]")
    f.add_argument("--only", nargs="+", default=None, metavar="FIG",
                   help="some of: fig2 fig3 fig4 fig56 fig7 fig8 fig9 [all]")
    f.set_defaults(func=_cmd_figures)
