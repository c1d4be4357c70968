"""Command line: ``plbar export`` and ``plbar render`` (ParaView output, pictures).

``register(subparsers)`` adds both subcommands to ``plbar``'s parser.  Each
handler is a thin call into :mod:`plbar.app.export` and
returns an exit code; errors are :class:`PlbarError` and become exit code 2
in :func:`plbar.cli.main.main`.

Sources of the response:

* ``--out DIR`` of a previous ``plbar run``: the case is read from
  ``DIR/summary.json`` and the orbit rebuilt from its row of ``DIR/paths.csv``
  (no re-scan);
* ``--case FILE.toml``: the case is solved first (results written to the
  case's ``[output] dir`` or ``--out``).
"""

from __future__ import annotations

import json
from pathlib import Path

from ..app import (OutputSettings, files_of, from_run, load_case, render_response, solve, write_response,
                   write_results)
from ..errors import InputError
from ..io import response_data, write_data

__all__ = ["register"]


def _source_args(p) -> None:
    p.add_argument("--out", default=None, metavar="DIR",
                   help="folder of a previous 'plbar run' (or where --case writes its results) [plbar-out]")
    p.add_argument("--case", default=None, metavar="FILE", help="a TOML case file: solve it first")
    p.add_argument("--dest", default=None, metavar="DIR", help="where to write [DIR/vtk or DIR/render]")
    p.add_argument("--branch", type=int, default=None, help="branch id [the branch with the largest xi_eq]")
    p.add_argument("--index", type=int, default=None, help="point along the branch [the largest xi_eq]")
    p.add_argument("--steps", type=int, default=None, help="time steps per period [40]")
    p.add_argument("--overwrite", action="store_true", help="with --case: replace results of another case")
    p.add_argument("--quiet", "-q", action="store_true", help="print nothing on success")
    p.add_argument("--json", action="store_true", help="print the written files as JSON")


def register(subparsers) -> None:
    """Add ``export`` and ``render`` to ``plbar``'s subparsers."""
    e = subparsers.add_parser(
        "export", help="write one periodic response for ParaView (.pvd + .vtu, or .xdmf + .h5)",
        description="Write one periodic response (default: the largest xi_eq) as a time series on the bar "
                    "mesh: displacement, velocity, energy densities, strain, stress, contact state and "
                    "reaction.  Open DEST/response.pvd (or response.xdmf) in ParaView.")
    _source_args(e)
    e.add_argument("--periods", type=int, choices=(1, 2), default=None, help="periods to write [1]")
    e.add_argument("--format", choices=("pvd", "xdmf", "both"), default=None, help="file format [pvd]")
    e.set_defaults(func=_cmd_export)
    r = subparsers.add_parser(
        "render", help="PNG snapshots, a space-time map and a GIF of one periodic response (headless)",
        description="Render one periodic response off-screen with pyvista: DEST/snapshot_NN.png, "
                    "snapshots.png, spacetime.png and response.gif.  Uses DIR/vtk/response.pvd when "
                    "present (and no --branch/--index is given), else rebuilds the response.")
    _source_args(r)
    r.add_argument("--field", default=None, help="field to colour by [displacement]; e.g. velocity, stress, "
                                                 "strain, kinetic_energy_density")
    r.add_argument("--snapshots", type=int, default=None, help="snapshots over the period [4]")
    r.add_argument("--no-gif", action="store_true", help="skip the animated GIF")
    r.set_defaults(func=_cmd_render)


def _pick(arg, setting):
    return setting if arg is None else arg


def _solve_case(a):
    """(Result, OutputSettings, out folder) of ``--case``; results written."""
    case, settings = load_case(a.case)
    out = Path(a.out or settings.dir or "plbar-out")
    res = solve(case)
    write_results(res, out, overwrite=a.overwrite or settings.overwrite)
    return res, settings, out


def _export(a):
    if a.case:
        res, st, out = _solve_case(a)
        return write_response(res, Path(a.dest) if a.dest else out / "vtk",
                              branch=_pick(a.branch, st.branch), index=_pick(a.index, st.index),
                              periods=_pick(a.periods, st.periods), steps=_pick(a.steps, st.steps),
                              format=_pick(a.format, st.format))
    st = OutputSettings()
    out = Path(a.out or "plbar-out")
    _, orb, info = from_run(out, a.branch, a.index)
    data = response_data(orb, info, _pick(a.periods, st.periods), _pick(a.steps, st.steps))
    return write_data(data, Path(a.dest) if a.dest else out / "vtk", format=_pick(a.format, st.format))


def _report(a, f, what: str) -> None:
    files = files_of(f)
    if a.json:
        print(json.dumps({"files": files, "info": getattr(f, "info", None)}))
    elif not a.quiet:
        main = [v for k, v in files.items() if not isinstance(v, list)]
        n = sum(len(v) for v in files.values() if isinstance(v, list))
        print(f"plbar {what}: wrote " + ", ".join(main) + (f" and {n} more files" if n else ""))


def _cmd_export(a) -> int:
    _report(a, _export(a), "export")
    return 0


def _cmd_render(a) -> int:
    st = OutputSettings()
    if a.case:
        res, st, out = _solve_case(a)
        source = res
    else:
        out = Path(a.out or "plbar-out")
        pvd = out / "vtk" / "response.pvd"
        source = pvd if pvd.is_file() and a.branch is None and a.index is None and a.steps is None else out
        if source == out and not (out / "summary.json").is_file():
            raise InputError(f"{str(out / 'summary.json')!r} does not exist; give the --out folder of a "
                             "previous 'plbar run' or a --case file")
    f = render_response(source, Path(a.dest) if a.dest else out / "render", field=_pick(a.field, st.field),
               snapshots=_pick(a.snapshots, st.snapshots), gif=st.gif and not a.no_gif,
               branch=_pick(a.branch, st.branch), index=_pick(a.index, st.index), steps=_pick(a.steps, st.steps))
    _report(a, f, "render")
    return 0
