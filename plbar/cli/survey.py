"""``plbar survey``: what the bar really does at every forcing period (simulated from rest, and sweeps).

A thin call into :func:`plbar.studies.survey.run_survey`; the same vocabulary
as every command (``--out``, ``--overwrite``, ``--quiet``, ``--json``, the model
and load options, ``--case``), the executor options of the studies.
"""

from __future__ import annotations

import importlib.util
from dataclasses import replace

import numpy as np

from ..errors import InputError
from ..util.outputs import check_creatable
from ..util.progress import message
from .common import (case_args, case_from_args, note_no_contact_mass, output_args, progress, refuse_contact_load,
                     report, warn_damping_fit, yes_arg)

__all__ = ["register"]

#: the search options of ``plbar run``: a survey simulates, it does not search
_SEARCH = ("grid", "T1", "T2", "method", "signatures")


def _periods(a, case) -> np.ndarray:
    from ..studies.survey import default_periods

    if a.T_list:                            # explicit periods: a range's options would be ignored, so refused
        given = [o for o, v in (("--T", a.T), ("--num", a.num)) if v is not None]
        if given:
            raise InputError(f"{' and '.join(given)} conflict{'s' if len(given) == 1 else ''} with --T-list (explicit "
                             f"forcing periods, surveyed in increasing order): give a range (--T LO HI --num K) or "
                             "the list, not both")
        return np.asarray(a.T_list, float)
    num = 161 if a.num is None else a.num
    if num < 2:
        raise InputError(f"--num {num} is not a range of forcing periods: give --num 2 or more, or one period with "
                         "--T-list T")
    if a.T is None:
        return default_periods(case, num)
    lo, hi = a.T
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 < lo <= hi):
        raise InputError(f"--T {lo:g} {hi:g} must be a range 0 < LO <= HI of forcing periods")
    return np.linspace(lo, hi, num)


def _cost(a, case, T) -> str:
    """Refuse a survey above the limits of :func:`plbar.app.cost.check_cost` (unless ``--yes``); say what a long
    one will cost: its motions x forcing periods, and the time from the measured cost of one period.

    A survey over meshes (``-N`` with two sizes or more) has the continuum as its N = infinity row; where that row
    alone is above the limits (a slow forcing: its cost grows steeply with ``T c / L``) it is left out, not the
    survey refused: the reason is returned (else ``""``)."""
    import os

    from ..app.cost import LIMIT_SECONDS, NOTE_SECONDS, check_cost, duration_range, survey_seconds
    from ..studies.survey.loads import DEFAULT_POSITIONS
    from ..studies.survey.refine import continuum_case

    motions = len(T) * (1 + len(set(a.cont or ())))
    if a.positions is not None or a.per_element is not None:
        motions *= len(a.positions) if a.positions is not None else max(DEFAULT_POSITIONS, a.per_element * case.n_eff)
    motions *= len(a.amplitudes or [None])
    sizes = sorted(set(a.sizes)) if a.sizes and len(a.sizes) > 1 else [None]
    cpu = sum(survey_seconds(case if n is None else _with_n(case, n), motions, a.periods) for n in sizes)
    workers = 1 if a.executor == "serial" and not a.scheduler else (a.workers or os.cpu_count() or 1)
    skip = ""
    if sizes != [None] and a.positions is None and a.per_element is None:
        cont, _ = continuum_case(case)
        if cont is not None:
            c = survey_seconds(cont, motions, a.periods, T)
            if c / min(workers, motions) > LIMIT_SECONDS and not a.yes:
                skip = (f"the continuum's survey would take {duration_range(c / min(workers, motions))} (its cost "
                        f"grows like periods^2 (T c/L)^3); left out: give --yes to run it, or fewer --periods")
            else:
                cpu += c
    wall = cpu / workers
    what = (f"this survey simulates {motions:,} motions x {a.periods:,} forcing periods"
            + (f" on {len(sizes)} meshes" if len(sizes) > 1 else "")
            + f": {duration_range(cpu)} of CPU, {duration_range(wall)} on {workers} worker{'s' if workers > 1 else ''}"
            " (idle to busy machine)")
    check_cost(wall, 0.0, what, "fewer periods (--num, --periods) or a coarser bar (-N)", a.yes)
    if wall > NOTE_SECONDS and not (a.quiet or a.json):
        message(f"plbar: note: {what}")
    if skip and not a.quiet:
        message(f"plbar: note: {skip}")
    return skip


def _lines(s, T, damped: bool = False, given: bool = False) -> list[str]:
    from ..motion import PERIODIC_TOL

    t = s.table
    lines = [f"plbar survey: {len(T)} forcing periods in [{T.min():.6g}, {T.max():.6g}], {s.summary['periods']} "
             f"periods each (last {s.summary['record']} recorded), {s.summary['seconds']:.1f} s"]
    for start, e in s.summary["by_start"].items():
        k = e["kinds"]
        by_m = ", ".join(f"m = {m}: {c}" for m, c in e["periodic_by_m"].items())
        sel = (t["start"] == start) & (t["kind"] == "periodic") & (t["distance"] > PERIODIC_TOL)
        settling = f"; {int(sel.sum())} still settling on their orbit" if sel.any() else ""
        name = "the case's start" if given and start == "rest" else f"{start:4s}"     # [start] of the case
        lines.append(f"  from {name}: {k['periodic']} periodic ({by_m or '-'}{settling}), {k['irregular']} "
                     "irregular" + (f", {k['failed']} failed" if k["failed"] else ""))
    if s.summary["record"] < 2:                 # periodic needs two repeats of the period in the window
        lines.append("  1 recorded period cannot show a motion repeat: every motion is irregular (give --record 2 "
                     "or more)")
    per = (t["kind"] == "periodic") & (t["start"] == "rest")
    if per.any():
        i = int(np.nanargmax(np.where(per, t["xi_eq"], -np.inf)))
        lines.append(f"  largest xi_eq of a periodic motion: {t['xi_eq'][i]:.4g} at T = {t['T'][i]:.6g} "
                     f"(m = {t['m'][i]}, loss per period {t['loss_per_T'][i]:.4g})")
    fin = np.isfinite(t["xi_eq"])
    if fin.any():
        lines.append(f"  xi_eq of every motion: {np.nanmin(t['xi_eq']):.4g} .. {np.nanmax(t['xi_eq']):.4g} "
                     f"(median {np.nanmedian(t['xi_eq']):.4g}); xi_w: {np.nanmin(t['xi_w']):.4g} .. "
                     f"{np.nanmax(t['xi_w']):.4g}")
    if damped and "xi_total" in t and np.isfinite(t["xi_total"]).any():   # Rayleigh's ratio at W + xi_eq
        tot = t["xi_total"]
        lines.append(f"  xi_total (Rayleigh's ratio at the forcing frequency + xi_eq): {np.nanmin(tot):.4g} .. "
                     f"{np.nanmax(tot):.4g} (median {np.nanmedian(tot):.4g})")
    drift = (t["steady"] == 0) & (t["kind"] != "failed")
    if drift.any():
        lines.append(f"  {int(drift.sum())} motion(s) drift over the recorded window (loss or int v^T M v changes by "
                     "more than 5 %, a significant trend): their xi_eq and xi_w are the window's, not steady values "
                     "(column steady = 0; drift_loss, drift_vMv)")
    if s.summary["energy_residual_max"] is not None:                 # None: every motion failed
        lines.append(f"  energy budget closes to {s.summary['energy_residual_max']:.1e} of the work")
    lines.append("  wrote " + ", ".join(str(f) for v in s.files.values() for f in (v if isinstance(v, list) else [v])))
    return lines


def _cmd_survey(a) -> int:
    from ..app import solve
    from ..studies import get_executor
    from ..studies.survey import run_survey

    if a.amplitude is not None and (a.positions is not None or a.per_element is not None):
        raise InputError("--amplitude does not apply with --positions/--per-element: a unit force acts at each "
                         "position (xi_eq does not depend on its amplitude); drop --amplitude")
    if a.amplitudes is not None and (a.positions is not None or a.per_element is not None):
        raise InputError("--amplitudes and --positions/--per-element are two studies: give one")
    case, _ = case_from_args(a)
    if a.sizes and len(a.sizes) == 1:
        case = _with_n(case, a.sizes[0])
    for n in a.sizes or [None]:           # a --load-node on the contact DOF of any size is refused
        refuse_contact_load(case if n is None else _with_n(case, n), tuple((k, 1.0) for k in a.load_node or ()))
    T = _periods(a, case)
    warn_damping_fit(a, T)
    no_continuum = _cost(a, case, T)
    note_no_contact_mass(a, case)
    out = check_creatable(a.out)              # made by the study's claim (removed again if it fails)
    if a.positions is not None or a.per_element is not None or a.amplitudes is not None:
        return _loads(a, case, T, out)
    if a.sizes and len(a.sizes) > 1:
        return _refine(a, case, T, out, no_continuum)
    plot = not a.no_plot and importlib.util.find_spec("matplotlib") is not None
    paths = None
    # the paper's class under it (plastic: with a restitution e > 0 it does not exist; the responses with rebounds
    # are plbar run --restitution E)
    if plot and not a.no_paths and not case.restitution and not case.gap and not case.gravity and \
            (a.paths or case.n_eff <= 12):
        paths = solve(replace(case, signatures="paper"), progress=False).paper
    kind = "dask" if a.scheduler else a.executor
    modes = ("rest",) + tuple(dict.fromkeys(a.cont or ()))
    with get_executor(kind, a.scheduler, a.workers) as ex:
        s = run_survey(case, T, a.periods, a.record, out, modes, a.chunks, paths, executor=ex, progress=progress(a),
                       overwrite=a.overwrite, plot=plot)
    given = case.start_x is not None or case.start_v is not None
    report(a, s.summary, s.files, "\n".join(_lines(s, T, case.rayleigh is not None, given)))
    return 0


def _loads(a, case, T, out) -> int:
    """The load study along positions (``--positions``, ``--per-element``) or amplitudes (``--amplitudes``)."""
    from ..studies import get_executor
    from ..studies.survey import AMPLITUDES, POSITIONS, run_survey_loads

    axis = POSITIONS if a.amplitudes is None else AMPLITUDES
    if a.cont:
        raise InputError("--continue sweeps T from one state: give it without --positions/--per-element/"
                         "--amplitudes")
    kind = "dask" if a.scheduler else a.executor
    sizes = sorted(set(a.sizes)) if a.sizes and len(a.sizes) > 1 else None
    values = a.positions if a.amplitudes is None else a.amplitudes
    with get_executor(kind, a.scheduler, a.workers) as ex:
        r = run_survey_loads(case, T, values, a.per_element, sizes, a.periods, a.record, out, axis=axis,
                             executor=ex, progress=progress(a), overwrite=a.overwrite,
                             plot=not a.no_plot and importlib.util.find_spec("matplotlib") is not None)
    w, col = axis.word, axis.column
    lines = [f"plbar survey over load {w}s: {r.values.size} {w}s x {r.T.size} forcing periods"
             + (f" x N = {', '.join(str(n) for n in r.sizes)}" if r.sizes.size > 1 else "")
             + f", {r.summary['periods']} periods each, {r.summary['seconds']:.1f} s"]
    for n, d in r.summary["by_N"].items():
        k = d["kinds"]
        mean = np.asarray(d[f"mean_xi_eq_per_{w}"])
        lines.append(f"  N = {n}: {k['periodic']} periodic, {k['irregular']} irregular"
                     + (f", {k['failed']} failed" if k["failed"] else "")
                     + f"; mean xi_eq over T by {w} {mean.min():.4g} .. {mean.max():.4g}, largest at {col} = "
                       f"{d[f'{w}_of_largest_mean_xi_eq']:g}")
    if r.summary["energy_residual_max"] is not None:                 # None: every motion failed
        lines.append(f"  energy budget closes to {r.summary['energy_residual_max']:.1e} of the work")
    lines.append("  wrote " + ", ".join(str(f) for v in r.files.values() for f in (v if isinstance(v, list) else [v])))
    report(a, r.summary, r.files, "\n".join(lines))
    return 0


def _with_n(case, n):
    from dataclasses import replace

    return replace(case, n=int(n))


def _refine(a, case, T, out, no_continuum: str = "") -> int:
    from ..studies import get_executor
    from ..studies.survey import run_survey_refine

    kind = "dask" if a.scheduler else a.executor
    with get_executor(kind, a.scheduler, a.workers) as ex:
        r = run_survey_refine(case, a.sizes, T, a.periods, a.record, out, no_continuum, executor=ex,
                              progress=progress(a), overwrite=a.overwrite,
                              plot=not a.no_plot and importlib.util.find_spec("matplotlib") is not None)
    text = "\n".join(_refine_lines(r.rates, a.sizes, 0 in r.surveys, r.files, case.bar().transit))
    report(a, r.summary, r.files, text, rates=r.rates)
    return 0


def _refine_lines(rates: dict, sizes, inf: bool, files: dict, tau: float = 1.0) -> list[str]:
    """The summary of a survey refinement: per forcing period (in the case's time unit, and in transit times
    ``T c / L`` for a bar whose waves cross it in ``tau = L / c``) and mean, the values and their limit (the
    continuum's where there is one), or why no limit is stated."""
    lines = [f"plbar survey over N = {', '.join(str(n) for n in sorted(set(sizes)))}"
             + (", infinity (the continuum, plbar.continuum)" if inf else "") + ":"]
    for d in rates.values():
        cont = d.get("continuum")
        lines.append(f"  T = {d['T']:.6g} (T c/L = {d['T'] / tau:.4g}): kinds {', '.join(d['kinds'])}"
                     + (f"; continuum {cont['kind']}" if isinstance(cont, dict) else f"; no continuum: {cont}"))
        for q in ("loss_per_T", "xi_eq", "xi_w"):
            c = d[q]
            vals = ", ".join(f"{v:.4g}" for v in c["values"])
            ac = c.get("against_continuum")
            if c.get("method") == "continuum":          # the limit is the continuum's value (the line below)
                rate = "-> the continuum (N = infinity, below)"
            elif c["rate"] is not None and c["limit"] is not None and not c.get("caution"):
                rate = f"-> {c['limit']:.4g}, rate {c['rate']:.2f} ({len(c['h'])} meshes)"
            elif c["rate"] is not None and c["limit"] is not None:
                rate = f"no limit stated: {c['caution']}"
            else:
                rate = f"no rate: {c['why']}"
            lines.append(f"    {q:10s} {vals}  {rate}")
            if ac and ac.get("continuum") is not None:
                z = ", ".join("-" if v is None else f"{v:+.1f}" for v in ac["z"])
                order = f"order {ac['order']:.2f}" if ac.get("order") is not None else f"no order: {ac['orders_why']}"
                lines.append(f"    {'':10s} continuum {ac['continuum']:.4g}" + (f" +- {ac['continuum_se']:.2g}"
                             if ac["continuum_se"] else "") + "; errors "
                             + ", ".join(f"{v:+.3g}" if v is not None else "-" for v in ac["error"])
                             + (f" (z {z})" if ac["continuum_se"] else "") + f"; {order}")
            elif ac:
                lines.append(f"    {'':10s} continuum: {ac['why']}")
    lines.append("  wrote " + ", ".join(str(f) for v in files.values() for f in (v if isinstance(v, list) else [v])))
    return lines


def register(sub) -> None:
    """Add ``survey`` to the ``plbar`` subparsers ``sub``."""
    s = sub.add_parser("survey", help="what the bar really does at every forcing period: simulated from rest, "
                                      "periodic or irregular, loss, xi_eq and xi_w of the motion",
                       description="Simulate the bar from rest (at the wall, load q cos(2 pi t / T)) at many forcing "
                                   "periods together (exact, event-driven), drop the transient and characterise the "
                                   "last --record periods: periodic with stroboscopic period m or irregular, impacts "
                                   "and impact loss per period (mean, spread), xi_eq of the motion (Eq. 22 over all "
                                   "its segments), xi_w (one frequency), contact amplitude, time stuck.  Writes "
                                   "DIR/survey.csv, DIR/summary.json and DIR/survey.png/.pdf (the frequency response "
                                   "of the real motion over the exact branches of 'plbar run').  Resumable.")
    output_args(s, "plbar-survey", "study folder (resumable)")
    g = s.add_argument_group("forcing periods")
    g.add_argument("--T", type=float, nargs=2, default=None, metavar=("LO", "HI"),
                   help="range of forcing periods [6 14 for the paper's case; 0.6-1.4 T0_I for a chain, "
                        "0.75 T0_I to the top of what 'plbar run' searches, (T0_I + T0_II)/2, for an FE bar]")
    g.add_argument("--num", type=int, default=None, metavar="K", help="forcing periods in the range [161]")
    g.add_argument("--T-list", dest="T_list", type=float, nargs="+", default=None, metavar="T",
                   help="explicit forcing periods (instead of --T/--num)")
    g.add_argument("--periods", type=int, default=1000, metavar="P", help="forcing periods simulated [1000]")
    g.add_argument("--record", type=int, default=None, metavar="R",
                   help="the last R periods characterise the motion (the rest is the transient) "
                        "[100, or P/10 when fewer]")
    g.add_argument("--continue", dest="cont", choices=("up", "down"), nargs="+", default=None,
                   help="also sweep T up and/or down, each period starting from the previous one's final state "
                        "(hysteresis, coexisting motions)")
    g.add_argument("--chunks", type=int, default=None, metavar="C",
                   help="tasks the from-rest runs are split into [max(2, K/96)]")
    g = s.add_argument_group("load positions (the survey at every one: survey_loads.csv and the (T, s) map)")
    g.add_argument("--positions", type=float, nargs="+", default=None, metavar="S",
                   help="unit-force positions 0 < S <= L, as in sweep-loads (the case's load is replaced)")
    g.add_argument("--per-element", type=int, default=None, metavar="K",
                   help="K positions per element (every node and points between) [enough for 20 in all]")
    g = s.add_argument_group("load amplitudes (the survey at every one: survey_amplitudes.csv and the (T, A) map)")
    g.add_argument("--amplitudes", type=float, nargs="+", default=None, metavar="A",
                   help="factors A > 0 on the case's load (with a gap or gravity the response depends on them; "
                        "without, xi_eq does not)")
    s.add_argument("--no-plot", action="store_true", help="skip survey.png/.pdf")
    s.add_argument("--no-paths", action="store_true", help="do not solve the exact branches under the figure")
    s.add_argument("--paths", action="store_true",
                   help="solve the exact branches under the figure even for a large model [only N <= 12]")
    yes_arg(s)
    case_args(s, "the load", sizes=())
    for act in list(s._actions):
        if act.dest in _SEARCH:
            act.help = "not used by a survey (it simulates; the branches under the figure use the defaults)"
    from .studies import _executor_args

    _executor_args(s)
    s.set_defaults(func=_cmd_survey, resumable=True)
