"""``plbar run`` (all periodic paths of a case) and ``plbar mesh`` (the shipped mesh files)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

from ..app import check_output, cost_note, run_case_file, solve, write_results
from ..errors import InputError
from ..io import SHIPPED, write_shipped
from ..util.check import MIN_BRANCH_POINTS
from ..util.outputs import claim_folder, fingerprint
from ..util.progress import message, progress_bar
from ..visuals.style import PAPER_SIGNATURE, unit_note
from .common import (case_args, case_flags, case_from_args, note_no_contact_mass, output_args, plural, progress, report,
                     warn_damping_fit, yes_arg)

__all__ = ["register"]

TOP = 5     #: branches listed by default (stable ones first, then the largest xi_eq); --verbose lists all
#: the search options of ``plbar run`` that ``plbar survey`` does not take
SEARCH = ("grid", "T1", "T2", "method", "signatures")


def _line(b: dict, damped: bool = False) -> str:
    tot = (f", with Rayleigh in [{b['xi_total_range'][0]:.4g}, {b['xi_total_range'][1]:.4g}]" if damped else "")
    return (f"  branch {b['branch']:3d} {b['signature']:6s}: {plural(b['points'], 'point', width=4)}, T in "
            f"[{b['T_range'][0]:.5g}, "
            f"{b['T_range'][1]:.5g}], xi_eq in [{b['xi_range'][0]:.4g}, {b['xi_range'][1]:.4g}]{tot}, "
            f"{b['stable_points']} stable")


def _stable_lines(summary: dict, survey: str) -> list[str]:
    """What to look at first: the stable points (what a real bar can settle on), or, without any, the survey."""
    brs = summary["branches"]
    total, stable = sum(b["points"] for b in brs), sum(b["stable_points"] for b in brs)
    if not total:
        return []                                      # nothing found: said by solve's warning
    if not stable:
        return [f"  none of the {plural(total, 'point')} is stable: a real bar settles on none of these responses; to "
                f"see what it does, run plbar survey {survey}".rstrip()]
    on = sum(b["stable_points"] > 0 for b in brs)
    return [f"  {stable:,} of {total:,} points are stable, on {plural(on, 'branch')}: what a real bar can settle on "
            "(the unstable ones it leaves); listed first"]


def _window(summary: dict, survey: str, units: str = "") -> list[str]:
    """The units of the numbers, the forcing periods searched and how to search or simulate others."""
    (lo1, hi1), (lo2, hi2) = summary["domain"]["T1"], summary["domain"]["T2"]
    own = "" if summary["case"].get("T1") or summary["case"].get("T2") else " (the bar's own: T1 <= T0_I/2, " \
        "T2 <= T0_II/2)"
    return [f"  units: {units + '; ' if units else ''}any consistent system, times in its unit (s with N, kg/m, m: "
            "docs/cli.md 'Units')",
            f"  searched forcing periods T = T1 + T2 in ({lo1 + lo2:.4g}, {hi1 + hi2:.4g}]{own}; another window: "
            f"--T1 LO HI --T2 LO HI; the motion at your forcing period T: plbar survey {survey} --T-list T"
            .replace("  --", " --")]


def _human(summary: dict, files: dict, verbose: bool, survey: str = "", units: str = "") -> str:
    brs = summary["branches"]
    paper = [b for b in brs if b["signature"] == PAPER_SIGNATURE]
    e = summary["case"].get("restitution")
    lines = [f"plbar: {summary['bar']}; load {summary['load']}",
             f"  fundamental periods T0_I = {summary['T0_I']:.6g}, T0_II = {summary['T0_II']:.6g}",
             *_window(summary, survey, units),
             f"  {plural(summary['n_branches'], 'branch')}, {plural(summary['n_points'], 'admissible point')}; "
             f"the paper's class ({PAPER_SIGNATURE}): {plural(len(paper), 'branch')}, "
             f"{plural(sum(b['points'] for b in paper), 'point')}" if not e else
             f"  {plural(summary['n_branches'], 'branch')}, {plural(summary['n_points'], 'admissible point')}; the "
             f"paper's class: none (restitution e = {e:g}: it needs a plastic impact); every response has rebounds "
             "(R) or chatters (R...RP)", *_stable_lines(summary, survey)]
    if summary.get("rayleigh"):
        lines.insert(4, f"  Rayleigh damping alpha = {summary['rayleigh'][0]:.6g}, beta = {summary['rayleigh'][1]:.6g}")
    order = sorted(brs, key=lambda b: (b["stable_points"] == 0, -b["xi_range"][1]))
    shown = order if verbose else [b for b in order if b["points"] >= MIN_BRANCH_POINTS][:TOP]
    if shown and len(shown) < len(brs):
        first = "stable points first, then the largest xi_eq" if shown[0]["stable_points"] else "the largest xi_eq"
        lines.append(f"  {'the ' if len(shown) > 1 else ''}{plural(len(shown), 'branch')} with {first}, of at least "
                     f"{MIN_BRANCH_POINTS} points (--verbose lists all {len(brs)}):")
    lines += [_line(b, bool(summary.get("rayleigh"))) for b in shown]
    if not verbose and len(shown) < len(brs):
        rest = [b for b in brs if b not in shown]
        short = sum(b["points"] < MIN_BRANCH_POINTS for b in rest)
        lines.append(f"  ... {plural(len(rest), 'more branch')} with {plural(sum(b['points'] for b in rest), 'point')} "
                     f"(max xi_eq {max(b['xi_range'][1] for b in rest):.4g}; {short} with fewer than "
                     f"{MIN_BRANCH_POINTS} points): all in paths.csv and summary.json")
    if summary.get("signatures", "default") != "paper":
        by: dict = {}
        for b in brs:                  # chattering orbits (R...RP) by family: their count of rebounds varies
            by.setdefault(b.get("family", b["signature"]), []).append(b)
        lines.append(f"  by signature ({summary['signatures']}; found in {summary['paper_time']:.3g} s of scan and "
                     f"{summary['signatures_time']:.3g} s more):")
        for lab, bs in by.items():
            lo, hi = min(b["T_range"][0] for b in bs), max(b["T_range"][1] for b in bs)
            sigs = sorted({b["signature"] for b in bs}, key=lambda x: (len(x), x))
            what = f" ({', '.join(sigs) if len(sigs) <= 3 else sigs[0] + ' .. ' + sigs[-1]}: C a chatter)" \
                if "C" in lab else ""
            lines.append(f"    {lab:8s} {len(bs):3d} branch(es), T in [{lo:.5g}, {hi:.5g}], xi_eq up to "
                         f"{max(b['xi_range'][1] for b in bs):.4g}, {sum(b['stable_points'] for b in bs)} stable "
                         f"points{what}")
    else:
        lines.append("  (the paper's class only: without --signatures paper, plbar run adds zero-dwell impacts, "
                     "subharmonics and several impacts per period)")
    lines.append(f"  total {summary['run_time']:.3g} s")
    lines.append("  wrote " + ", ".join(str(p) for p in files.values() if not isinstance(p, (list, tuple))))
    return "\n".join(lines)


def _plots(res, out, a) -> dict:
    """The frequency-response view and the (T1, T2) map, if matplotlib is installed (else said once)."""
    if a.no_plot:
        return {}
    if importlib.util.find_spec("matplotlib") is None:
        if not (a.quiet or a.json):
            message('plbar: note: plots skipped: matplotlib is not installed (pip install "plbar[plot]")')
        return {}
    from ..visuals import frequency_response, paths_plane

    return {"frequency_response": frequency_response(res, out, xi=a.plot_xi), "paths_plane": paths_plane(res, out)}


def _number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _cmd_run(a) -> int:
    if a.case_pos and getattr(a, "elements", None) is not None and _number(a.case_pos):
        raise InputError(f"plbar run solves one size: -N {a.elements} (the {a.case_pos!r} after it would be read "
                         f"as a case file); for several sizes use plbar refine -N {a.elements} {a.case_pos} or "
                         f"plbar survey -N {a.elements} {a.case_pos}")
    if a.case_pos:
        if a.case and a.case != a.case_pos:
            raise InputError("give the case file once (positional or --case)")
        a.case = a.case_pos
    case, st = case_from_args(a)
    out = Path(a.out if st is None or a.out != "plbar-out" or st.dir is None else st.dir)
    overwrite = a.overwrite or (st is not None and st.overwrite)
    note = cost_note(case, yes=a.yes)                  # a costly solve is refused before anything is made
    with check_output(case, out, overwrite) as claim:   # before the solve: fail fast; undone if interrupted
        if note and not a.quiet:
            message(note)
        if st is not None:
            r = run_case_file(a.case, out, overwrite, progress=progress(a), loaded=(case, st))
            res, files = r["result"], r["files"]
        else:
            res = solve(case, progress=progress(a))
            claim.take()
            with progress_bar(1, progress(a), "writing paths.csv and summary.json", "step"):
                files = write_results(res, out, overwrite=overwrite)   # (every orbit's amplitude: seconds)
        with progress_bar(1, progress(a) and not a.no_plot, "plotting", "step"):
            files.update(_plots(res, out, a))        # still holding the folder's lock
    s = res.summary()
    warn_damping_fit(a, [t for b in s["branches"] for t in b["T_range"]])
    note_no_contact_mass(a, case)
    report(a, s, files, _human(s, files, a.verbose, case_flags(a, skip=SEARCH), unit_note(res.prob.bar)))
    return 0


def _cmd_mesh(a) -> int:
    """The shipped meshes: missing ones are written, existing ones kept (replaced with --overwrite)."""
    claim = claim_folder(a.out, "mesh", fingerprint(sorted(SHIPPED)), tuple(SHIPPED), a.overwrite)
    kept = [] if a.overwrite else [n for n in SHIPPED if (claim.folder / n).exists()]
    files = write_shipped(claim.folder, [n for n in SHIPPED if n not in kept])
    text = ("wrote " + ", ".join(str(f) for f in files)) if files else "wrote nothing"
    if kept:
        text += f"; kept {plural(len(kept), 'existing file')} (--overwrite replaces them)"
    report(a, {"written": len(files), "kept": len(kept)}, {"meshes": files, "kept": [claim.folder / n for n in kept]},
           text)
    return 0


def register(sub) -> None:
    """Add ``run`` and ``mesh`` to the ``plbar`` subparsers ``sub``."""
    r = sub.add_parser("run", help="find all periodic paths of a case, with Delta_PL and xi_eq",
                       description="Find all admissible periodic paths of a case and write DIR/paths.csv, "
                                   "DIR/summary.json and two plots.  Without options: the paper's chain N = 5, "
                                   "unit force on DOF 1.  With a case file, --out overrides its [output] dir; "
                                   "model, load and search options are refused (the file defines them).")
    r.add_argument("case_pos", nargs="?", default=None, metavar="CASE.toml", help="a TOML case file (= --case)")
    output_args(r, "plbar-out", "output folder (its earlier plbar results are replaced)")
    r.add_argument("--no-plot", action="store_true", help="skip the PNG plots")
    r.add_argument("--plot-xi", choices=("eq", "w"), default="eq",
                   help="the damping ratio drawn: xi_eq of Eq. (22), or xi_w (one frequency, the forcing's) [eq]")
    r.add_argument("--verbose", "-v", action="store_true",
                   help="list every branch (default: 5 of at least 3 points, stable ones first, then by xi_eq)")
    yes_arg(r)
    case_args(r)
    r.set_defaults(func=_cmd_run)
    m = sub.add_parser("mesh", help="regenerate the shipped mesh files",
                       description="Write the meshes shipped in meshes/ (gmsh 2.2 ASCII line meshes); existing "
                                   "files are kept unless --overwrite.")
    output_args(m, "meshes", "output folder")
    m.set_defaults(func=_cmd_mesh)
