"""``plbar export`` (one response for ParaView) and ``plbar render`` (pictures of it, headless).

Where the response comes from: ``--from DIR`` (a previous ``plbar run``: the
case is read from ``DIR/summary.json`` and the orbit rebuilt from its row of
``DIR/paths.csv``, no re-scan), or ``--case FILE.toml`` (solved first, results
written to the file's ``[output] dir`` or ``--from``).  ``--from SURVEY --T T``
(a ``plbar survey`` folder): the motion the survey simulated at that forcing
period (from rest, or ``--start up|down`` of its sweeps), its last
``--periods`` periods, irregular or not (:mod:`plbar.studies.survey.motion`).  Where it goes: ``--out``
(default ``DIR/vtk`` or ``DIR/render``); what an earlier export or render left
there is cleared first.  ``--dest`` is the old spelling of ``--out``.
"""

from __future__ import annotations

from pathlib import Path

from ..app import (OutputSettings, case_of_run, check_output, cost_note, files_of, from_run, load_case,
                   render_response, select, solve, write_response, write_response_data, write_results)
from ..errors import InputError
from ..io import CELL_FIELDS, POINT_FIELDS, response_data
from ..util.outputs import check_creatable, require
from ..util.progress import message
from .common import hidden, progress, report, yes_arg

__all__ = ["register"]


def _source_args(p, kind: str) -> None:
    p.add_argument("--from", dest="src", default=None, metavar="DIR",
                   help="folder of a previous 'plbar run' [plbar-out], or of a 'plbar survey' (with --T)")
    p.add_argument("--T", type=float, default=None, metavar="T",
                   help="with --from SURVEY: the forcing period whose simulated motion to show (the surveyed one "
                        "within 1e-3 of it)")
    p.add_argument("--start", choices=("rest", "up", "down"), default=None,
                   help="with --from SURVEY: the motion from rest, or of the survey's sweep up or down [rest]")
    p.add_argument("--case", default=None, metavar="FILE.toml", help="a TOML case file: solve it first")
    p.add_argument("--out", default=None, metavar="DIR", help=f"where to write [DIR/{kind}]")
    p.add_argument("--dest", dest="out", default=None, help=hidden)
    p.add_argument("--branch", type=int, default=None, help="branch id [the branch with the largest xi_eq]")
    p.add_argument("--index", type=int, default=None,
                   help="point along the branch, 0 = its first; negative counts from its end (-1: its last point) "
                        "[the largest xi_eq]")
    p.add_argument("--steps", type=int, default=None, help="time steps per period [40]")
    p.add_argument("--overwrite", action="store_true",
                   help="replace what another command or case owns in the output folder (and, with --case, in the "
                        "run folder)")
    p.add_argument("--quiet", "-q", action="store_true", help="print nothing on success")
    p.add_argument("--json", action="store_true", help="print the written files as JSON")
    yes_arg(p)


def _pick(arg, setting):
    return setting if arg is None else arg


def _check_options(a) -> None:
    """Refuse bad --steps, --snapshots, --field, --branch before anything is solved, read or created."""
    if a.steps is not None and a.steps < 4:
        raise InputError(f"--steps {a.steps} is not allowed; it must be >= 4 (time steps per period)")
    if a.branch is not None and a.branch < 0:
        raise InputError(f"--branch {a.branch} is not allowed; branch ids are >= 0 (see the run's summary.json)")
    if getattr(a, "snapshots", None) is not None and a.snapshots < 1:
        raise InputError(f"--snapshots {a.snapshots} is not allowed; it must be >= 1")
    field = getattr(a, "field", None)
    names = [f for f in POINT_FIELDS + CELL_FIELDS if not f.endswith("_vec")]
    if field is not None and field not in names:
        raise InputError(f"--field {field} is not a field of a response; choose one of {', '.join(names)}")


def _survey_source(a):
    """The motion data of ``--from SURVEY --T T`` (None when ``--from`` is not a survey folder)."""
    if a.src is None or a.case is not None:
        return None
    from ..io import motion_data
    from ..studies.survey import is_survey, survey_motion

    if not is_survey(a.src):
        if a.T is not None or a.start is not None:
            raise InputError(f"--T and --start pick a motion of a survey; {a.src!r} is not a 'plbar survey' folder")
        return None
    if a.T is None:
        raise InputError(f"{a.src!r} is a survey: give --T, the forcing period of the motion to show")
    if a.branch is not None or a.index is not None:
        raise InputError("--branch and --index pick a periodic response of a run; a survey's motion is picked by "
                         "--T (and --start)")
    _check_options(a)
    sm = survey_motion(a.src, a.T, 10 if a.periods is None else a.periods, a.start or "rest")
    if sm.T != a.T and not (a.quiet or a.json):    # the JSON summary has T_forcing
        message(f"plbar: --T {a.T:.10g} is taken as the survey's forcing period T = {sm.T:.10g}")
    return sm.case, motion_data(sm.series, 40 if a.steps is None else a.steps, sm.info)


def _source(a, kind: str):
    """``(settings, run folder, case file's Case or None)``; the old ``--out DIR`` (a run folder as input) works."""
    _check_options(a)
    if a.src is None and a.case is None and a.out is not None and (Path(a.out) / "summary.json").is_file():
        message(f"plbar: warning: --out {a.out} as the input folder is the old spelling; use --from {a.out} "
                f"(writing into {a.out}/{kind})")
        a.src, a.out = a.out, None
    if a.case:
        case, st = load_case(a.case)
        return st, Path(a.src or st.dir or "plbar-out"), case
    run = Path(a.src or "plbar-out")
    if not (run / "summary.json").is_file():
        raise InputError(f"{str(run / 'summary.json')!r} does not exist; give --from DIR of a previous "
                         "'plbar run' or a --case file")
    return OutputSettings(), run, None


def _solved(a, st, run: Path, case):
    """Solve a case file and write its results into ``run`` (checked before the solve), as ``plbar run`` does; a bad
    ``--branch``/``--index`` of the solve is refused before its results are written."""
    note = cost_note(case, yes=a.yes)              # a costly solve is refused before anything is made
    if note and not (a.quiet or a.json):
        message(note)
    with check_output(case, run, a.overwrite or st.overwrite) as claim:
        res = solve(case, progress=progress(a))
        select(res, _pick(a.branch, st.branch), _pick(a.index, st.index))
        claim.take()
        write_results(res, run, overwrite=a.overwrite or st.overwrite)
    return res


def _cmd_export(a) -> int:
    motion = _survey_source(a)
    if motion is not None:
        case, data = motion
        fmt = a.format or "pvd"
        dest = Path(a.out) if a.out else Path(a.src) / "vtk"
        _report(a, write_response_data(data, dest, format=fmt, case=case, overwrite=a.overwrite), "export")
        return 0
    if a.periods is not None and a.periods not in (1, 2):
        raise InputError(f"--periods {a.periods} is not allowed for a periodic response; choose 1 or 2")
    st, run, case = _source(a, "vtk")
    fmt = _pick(a.format, st.format)
    if fmt in ("pvd", "both"):
        require("pyvista", "plbar export")
    if fmt in ("xdmf", "both"):
        require("h5py", "plbar export --format xdmf")
    dest = Path(a.out) if a.out else run / "vtk"
    check_creatable(dest)                            # an unusable destination is refused before the solve
    if case is not None:
        res = _solved(a, st, run, case)
        f = write_response(res, dest, branch=_pick(a.branch, st.branch), index=_pick(a.index, st.index),
                           periods=_pick(a.periods, st.periods), steps=_pick(a.steps, st.steps), format=fmt,
                           overwrite=a.overwrite)
    else:
        case, orb, info = from_run(run, a.branch, a.index)           # a bad --branch/--index: nothing created
        data = response_data(orb, info, _pick(a.periods, st.periods), _pick(a.steps, st.steps))
        f = write_response_data(data, dest, format=fmt, case=case, overwrite=a.overwrite)
    _report(a, f, "export")
    return 0


def _cmd_render(a) -> int:
    require("pyvista", "plbar render")
    require("PIL", "plbar render")
    motion = _survey_source(a)
    if motion is not None:
        case, data = motion
        dest = Path(a.out) if a.out else Path(a.src) / "render"
        f = render_response(data, dest, field=a.field or "displacement", snapshots=a.snapshots or 4,
                            gif=not a.no_gif, case=case, overwrite=a.overwrite)
        _report(a, f, "render")
        return 0
    if a.periods is not None:
        raise InputError("--periods is for a survey's motion (--from SURVEY --T T); a periodic response renders one "
                         "period")
    st, run, case = _source(a, "render")
    dest = Path(a.out) if a.out else run / "render"
    check_creatable(dest)
    if case is not None:
        source = _solved(a, st, run, case)
    else:
        pvd = run / "vtk" / "response.pvd"
        source = pvd if pvd.is_file() and a.branch is None and a.index is None and a.steps is None else run
        case = case_of_run(run)
    f = render_response(source, dest, field=_pick(a.field, st.field), snapshots=_pick(a.snapshots, st.snapshots),
                        gif=st.gif and not a.no_gif, branch=_pick(a.branch, st.branch),
                        index=_pick(a.index, st.index), steps=_pick(a.steps, st.steps), case=case,
                        overwrite=a.overwrite)
    _report(a, f, "render")
    return 0


def _report(a, f, what: str) -> None:
    files = files_of(f)
    main = [v for v in files.values() if not isinstance(v, list)]
    n = sum(len(v) for v in files.values() if isinstance(v, list))
    summary = f.info if what == "export" else {"field": f.field, "snapshots": len(f.snapshots)}
    report(a, summary, files,
           f"plbar {what}: wrote " + ", ".join(main) + (f" and {n} more files" if n else ""))


def register(subparsers) -> None:
    """Add ``export`` and ``render`` to ``plbar``'s subparsers."""
    e = subparsers.add_parser(
        "export", help="write one periodic response, or a survey's simulated motion, for ParaView (.pvd + .vtu, "
                       "or .xdmf + .h5)",
        description="Write one periodic response (default: the largest xi_eq), or with --from SURVEY --T T the "
                    "motion a survey simulated (its last --periods periods, impacts marked), as a time series on "
                    "the bar mesh: displacement, velocity, energy densities, strain, stress, contact state and "
                    "reaction.  Open OUT/response.pvd (or response.xdmf) in ParaView.")
    _source_args(e, "vtk")
    e.add_argument("--periods", type=int, default=None,
                   help="periods to write: 1 or 2 of a periodic response [1]; the last P of a survey's motion [10]")
    e.add_argument("--format", choices=("pvd", "xdmf", "both"), default=None, help="file format [pvd]")
    e.set_defaults(func=_cmd_export)
    r = subparsers.add_parser(
        "render", help="PNG snapshots, a space-time map and a GIF of one periodic response (headless)",
        description="Render one periodic response off-screen with pyvista: OUT/snapshot_NN.png, "
                    "snapshots.png, spacetime.png and response.gif.  Uses DIR/vtk/response.pvd when "
                    "present (and no --branch/--index/--steps is given), else rebuilds the response.")
    _source_args(r, "render")
    r.add_argument("--field", default=None, help="field to colour by [displacement]; e.g. velocity, stress, "
                                                 "strain, kinetic_energy_density")
    r.add_argument("--snapshots", type=int, default=None, help="snapshots over the period [4]")
    r.add_argument("--periods", type=int, default=None,
                   help="with --from SURVEY: the last P periods of its motion, drawn as one window [10]")
    r.add_argument("--no-gif", action="store_true", help="skip the animated GIF")
    r.set_defaults(func=_cmd_render)
