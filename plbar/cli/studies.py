"""Command line for studies: ``plbar sweep-loads``, ``plbar refine``, ``plbar figures``.

:func:`register` adds the subcommands to the ``plbar`` parser
(``register(sub)`` in :func:`plbar.cli.main.build_parser`).  Handlers are thin
calls into :mod:`plbar.studies`; they
return exit codes (errors are turned into codes by :func:`plbar.cli.main.main`).
"""

from __future__ import annotations

import argparse
import json

__all__ = ["register"]


def _run_args(p: argparse.ArgumentParser, out: str) -> None:
    g = p.add_argument_group("execution")
    g.add_argument("--out", default=out, metavar="DIR", help=f"study folder (resumable) [{out}]")
    g.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="dask scheduler address (tcp://host:8786) or scheduler file; implies --executor dask")
    g.add_argument("--executor", choices=("local", "serial", "dask"), default="local",
                   help="local process pool, serial, or dask (LocalCluster without --scheduler) [local]")
    g.add_argument("--workers", type=int, default=None, metavar="W", help="worker processes [all cores]")
    g.add_argument("--grid", type=int, nargs=2, default=(200, 200), metavar=("N1", "N2"),
                   help="scan grid of every case [200 200]")
    g.add_argument("--overwrite", action="store_true", help="reuse a folder that holds another kind of study")
    g.add_argument("--quiet", "-q", action="store_true", help="no progress bar, print nothing on success")


def _execute(a, study):
    from ..studies import get_executor, run_study

    with get_executor("dask" if a.scheduler else a.executor, a.scheduler, a.workers) as ex:
        return run_study(a.out, study, ex, progress=not a.quiet, overwrite=a.overwrite)


def _from_case_file(a) -> None:
    """Take the bar and the grid of a TOML case file (``--case``) into the sweep arguments."""
    from ..app import load_case

    case, _ = load_case(a.case)
    a.model, a.elements, a.element, a.mass, a.grid = case.model, case.n_eff, case.element, case.mass, case.grid


def _cmd_sweep(a) -> int:
    from ..studies import (default_positions, load_sweep_study, node_pairs, sweep_tables, write_sweep_tables,
                           xi_along_mesh)

    if a.case:
        _from_case_file(a)
    n = a.elements or (5 if a.model == "chain" else 8)
    pos = a.at if a.at else default_positions(n, a.per_element, a.model)
    pairs = node_pairs(n, a.model) if a.pairs else ()
    st = load_sweep_study(n, a.model, pos, pairs, tuple(a.grid), a.element, a.mass, per_element=a.per_element)
    res = _execute(a, st)
    tb = sweep_tables(st.tasks, res)
    files = write_sweep_tables(a.out, tb)
    try:
        from ..app import Case
        from ..io import write_xi_along_mesh

        bar = Case(model=a.model, n=n, element=a.element if a.model == "fe" else "P1",
                   mass=a.mass if a.model == "fe" else "lumped").bar()
        pos, fields = xi_along_mesh(tb)
        files["xi_along_mesh"] = write_xi_along_mesh(bar, pos, fields, f"{a.out}/xi_along_mesh.vtu")
    except ImportError:       # meshio/pyvista missing: the tables are still complete
        pass
    if not a.quiet:
        for fam, e in tb.summary["best"].items():
            for kind, v in e.items():
                print(f"{fam:8s} {kind:6s}: max xi_eq = {v['xi_max']:.4f} for load {v['load']} "
                      f"at T = {v['T_at_max']:.4f} (geometry deviation over {v['cases']} loads: "
                      f"{v['max_geom_dev']:.2e})")
        print("wrote " + ", ".join(str(f) for f in files.values()))
    return 0


def _cmd_refine(a) -> int:
    from ..studies import refine_study, refine_tables, write_refine_tables

    if a.case:
        from ..app import load_case

        case, _ = load_case(a.case)
        a.series = ["chain"] if case.model == "chain" else [f"fe-{case.element}-{case.mass}"]
        a.grid = case.grid

    st = refine_study(a.n, a.series, a.frac, tuple(a.grid), tuple(a.T2_frac) if a.T2_frac else None)
    res = _execute(a, st)
    tb = refine_tables(st.tasks, res)
    files = write_refine_tables(a.out, tb)
    if not a.quiet:
        m = tb.maxima
        for i in range(len(m["n"])):
            if m["family"][i] == "T0_II/2":
                print(f"{m['series'][i]:18s} N = {m['n'][i]:3d}: T0_I = {m['T0_I'][i]:.4f}, "
                      f"T0_II = {m['T0_II'][i]:.4f}, family T0_II/2: T in [{m['T_min'][i]:.4f}, "
                      f"{m['T_max'][i]:.4f}], max xi_eq = {m['xi_max'][i]:.4f}")
        print("rates: " + json.dumps(tb.rates))
        print("wrote " + ", ".join(str(f) for f in files.values()))
    return 0


def _cmd_figures(a) -> int:
    from ..studies.figures import make_all

    files = make_all(a.out, grid=tuple(a.grid), which=a.only)
    if not a.quiet:
        print(f"wrote {len(files)} files into {a.out}")
    return 0


def register(sub) -> None:
    """Add ``sweep-loads``, ``refine`` and ``figures`` to the ``plbar`` subparsers ``sub``."""
    s = sub.add_parser("sweep-loads", help="xi_eq and Delta_PL for loads along the bar (paper Sec. 4.2)",
                       description="Solve the case for a unit point load at many positions s (and two-point "
                                   "combinations), group branches into families and write DIR/sweep.csv, "
                                   "DIR/sweep_max.csv, DIR/sweep_summary.json.  Resumable: rerun to continue.")
    s.add_argument("--model", choices=("chain", "fe"), default="chain", help="bar model [chain]")
    s.add_argument("--elements", "-N", type=int, default=None, metavar="N", help="masses / elements [5 / 8]")
    s.add_argument("--element", choices=("P1", "P2"), default="P1")
    s.add_argument("--mass", choices=("lumped", "consistent"), default="lumped")
    s.add_argument("--at", type=float, action="append", default=None, metavar="S",
                   help="load position (repeatable) [per-element steps inside (0, L)]")
    s.add_argument("--per-element", type=int, default=10, metavar="K",
                   help="default positions: K per element, nodes included [10]")
    s.add_argument("--pairs", action="store_true", help="also every pair of nodes, amplitude 0.5 each")
    s.add_argument("--case", default=None, metavar="FILE.toml",
                   help="take the bar (model, N, element, mass) and the grid from a TOML case file")
    _run_args(s, "plbar-sweep")
    s.set_defaults(func=_cmd_sweep)

    r = sub.add_parser("refine", help="the same case for a list of N: periods, path extent, xi_eq (Sec. 4.3)",
                       description="Mesh refinement: write DIR/refine.csv, DIR/refine_max.csv and "
                                   "DIR/refine_rates.json.  Resumable.")
    r.add_argument("--n", type=int, nargs="+", default=[3, 4, 5, 6, 8, 12, 16], metavar="N",
                   help="masses / elements [3 4 5 6 8 12 16]")
    r.add_argument("--series", nargs="+", default=["chain"], metavar="S",
                   help="chain and/or fe-P1-lumped, fe-P1-consistent, fe-P2-lumped, fe-P2-consistent [chain]")
    r.add_argument("--frac", type=float, nargs="+", default=[0.5], metavar="F",
                   help="load positions s/L [0.5]")
    r.add_argument("--case", default=None, metavar="FILE.toml",
                   help="take the series (model/element/mass), N and the grid from a TOML case file")
    r.add_argument("--T2-frac", type=float, nargs=2, default=None, metavar=("LO", "HI"),
                   help="search T2 in [LO, HI] * T0_II/2 only (cheaper for large N)")
    _run_args(r, "plbar-refine")
    r.set_defaults(func=_cmd_refine)

    f = sub.add_parser("figures", help="the paper's figures (2-9) for our numbers, PNG and PDF",
                       description="Draw the figure families of the paper's Sec. 4 into DIR (needs matplotlib).")
    f.add_argument("--out", default="plbar-figures", metavar="DIR", help="output folder [plbar-figures]")
    f.add_argument("--grid", type=int, nargs=2, default=(200, 200), metavar=("N1", "N2"))
    f.add_argument("--only", nargs="+", default=None, metavar="FIG",
                   help="some of: fig2 fig3 fig4 fig56 fig7 fig8 fig9 [all]")
    f.add_argument("--quiet", "-q", action="store_true")
    f.set_defaults(func=_cmd_figures)
