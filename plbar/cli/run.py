"""``plbar run`` (all periodic paths of a case) and ``plbar mesh`` (the shipped mesh files)."""

from __future__ import annotations

import argparse
import importlib.util
import json
from pathlib import Path

from ..app import Case, check_output, load_case, run_case_file, solve, write_results
from ..io import write_shipped

__all__ = ["register", "case_args", "case_from_args"]


def case_args(p: argparse.ArgumentParser) -> None:
    """The model, load and search options shared by the commands that build a case."""
    g = p.add_argument_group("model")
    g.add_argument("--model", choices=("chain", "fe"), default="chain",
                   help="the paper's mass-spring chain (L = N) or a finite-element bar (L = 1) [chain]")
    g.add_argument("--elements", "-N", type=int, default=None, metavar="N",
                   help="masses of the chain / elements of the FE bar [5 / 8]")
    g.add_argument("--element", choices=("P1", "P2"), default="P1", help="FE element [P1]")
    g.add_argument("--mass", choices=("lumped", "consistent"), default="lumped", help="FE mass matrix [lumped]")
    g.add_argument("--mesh-file", default=None, help="meshio-readable 1D line mesh for --model fe")
    g.add_argument("--grading", type=float, default=1.0,
                   help="FE mesh grading: last/first element length [1 = uniform]")
    g.add_argument("--modes", type=int, default=None, metavar="M",
                   help="keep the lowest M modes of each state (modal truncation for fine meshes; "
                        "xi_eq converges slowly in M, see README) [all]")
    g = p.add_argument_group("load (unit amplitude; default: DOF 1)")
    g.add_argument("--load-node", type=int, action="append", default=None, metavar="K",
                   help="force on free DOF K (1-based from the clamp, as in the paper); repeatable")
    g.add_argument("--load-at", type=float, action="append", default=None, metavar="S",
                   help="point force at position S in (0, L] through the shape functions; repeatable")
    g = p.add_argument_group("search")
    g.add_argument("--grid", type=int, nargs=2, default=(200, 200), metavar=("N1", "N2"),
                   help="scan grid over (T1, T2) [200 200]")
    g.add_argument("--T1", type=float, nargs=2, default=None, metavar=("LO", "HI"),
                   help="T1 search range [(0, T0_I/2]]")
    g.add_argument("--T2", type=float, nargs=2, default=None, metavar=("LO", "HI"),
                   help="T2 search range [(0, T0_II/2]]")
    g.add_argument("--method", choices=("continuation", "grid"), default="continuation",
                   help="branches by pseudo-arclength continuation seeded by the scan, or by linking the "
                        "scan's crossings only (faster, may fragment) [continuation]")


def case_from_args(a) -> Case:
    """The :class:`Case` of the parsed model, load and search options."""
    nodes = tuple((k, 1.0) for k in (a.load_node or ()))
    points = tuple((s, 1.0) for s in (a.load_at or ()))
    return Case(model=a.model, n=a.elements, element=a.element, mass=a.mass, mesh_file=a.mesh_file,
                grading=a.grading, load_nodes=nodes, load_points=points, grid=tuple(a.grid),
                T1=tuple(a.T1) if a.T1 else None, T2=tuple(a.T2) if a.T2 else None, method=a.method,
                modes=a.modes)


def _human(summary: dict, files: dict) -> str:
    lines = [f"plbar: {summary['bar']}; load {summary['load']}",
             f"  fundamental periods T0_I = {summary['T0_I']:.6g}, T0_II = {summary['T0_II']:.6g}",
             f"  {summary['n_branches']} branch(es), {summary['n_points']} admissible path points "
             f"in {summary['run_time']:.3g} s"]
    for b in summary["branches"]:
        lines.append(f"  branch {b['branch']:2d}: {b['points']:4d} points, T in [{b['T_range'][0]:.5g}, "
                     f"{b['T_range'][1]:.5g}], xi_eq in [{b['xi_range'][0]:.4g}, {b['xi_range'][1]:.4g}], "
                     f"{b['stable_points']} stable")
    lines.append("  wrote " + ", ".join(str(p) for p in files.values() if not isinstance(p, (list, tuple))))
    return "\n".join(lines)


def _cmd_run(a) -> int:
    if a.case:
        out = None if a.out == "plbar-out" else a.out
        case, st = load_case(a.case)                         # fail fast on the file and the output folder
        check_output(case, out or st.dir or "plbar-out", a.overwrite or st.overwrite)
        r = run_case_file(a.case, out, a.overwrite, progress=not (a.quiet or a.json), loaded=(case, st))
        res, files = r["result"], r["files"]
        out = Path(files["summary"]).parent
    else:
        case = case_from_args(a)
        check_output(case, a.out, a.overwrite)
        res = solve(case, progress=not (a.quiet or a.json))
        files = write_results(res, a.out, overwrite=a.overwrite)
        out = a.out
    if not a.no_plot:
        files.update(_plots(res, out))
    s = res.summary()
    if a.json:
        print(json.dumps({"summary": s, "files": {k: str(v) for k, v in files.items()}}))
    elif not a.quiet:
        print(_human(s, files))
    return 0


def _plots(res, out) -> dict:
    """The frequency-response view and the (T1, T2) map, if matplotlib is installed."""
    if importlib.util.find_spec("matplotlib") is None:
        return {}
    from ..visuals import frequency_response, paths_plane

    return {"frequency_response": frequency_response(res, out), "paths_plane": paths_plane(res, out)}


def _cmd_mesh(a) -> int:
    files = write_shipped(a.out)
    if not a.quiet:
        print("wrote " + ", ".join(str(f) for f in files))
    return 0


def register(sub) -> None:
    """Add ``run`` and ``mesh`` to the ``plbar`` subparsers ``sub``."""
    r = sub.add_parser("run", help="find all periodic paths of a case, with Delta_PL and xi_eq",
                       description="Find all admissible periodic paths of a case and write DIR/paths.csv "
                                   "and DIR/summary.json.  Without options: the paper's chain N = 5, "
                                   "unit force on DOF 1.")
    r.add_argument("--out", default="plbar-out", metavar="DIR", help="output folder [plbar-out]")
    r.add_argument("--overwrite", action="store_true", help="replace results of another case in DIR")
    r.add_argument("--quiet", "-q", action="store_true", help="print nothing on success")
    r.add_argument("--json", action="store_true", help="print the summary as JSON")
    r.add_argument("--no-plot", action="store_true", help="skip the PNG plots")
    r.add_argument("case", nargs="?", default=None, metavar="CASE.toml",
                   help="a TOML case file (see examples/cases/); overrides the model/load/search options")
    case_args(r)
    r.set_defaults(func=_cmd_run)
    m = sub.add_parser("mesh", help="regenerate the shipped mesh files",
                       description="Write the meshes shipped in meshes/ (gmsh 2.2 ASCII line meshes).")
    m.add_argument("--out", default="meshes", metavar="DIR", help="output folder [meshes]")
    m.add_argument("--quiet", "-q", action="store_true")
    m.set_defaults(func=_cmd_mesh)
