"""The one vocabulary of the command line: options every command shares, and how they become a Case.

* ``--out DIR`` is where a command writes; ``--from DIR`` is a previous run it reads;
* ``--overwrite`` lets a command replace what another command or case owns in its ``--out``
  (:func:`plbar.util.outputs.claim_folder`, never silently);
* ``--quiet`` prints nothing on success, ``--json`` prints the result as JSON (both without progress bars); the
  JSON is one shape for every command: ``{"summary": {...}, "files": ...}`` (:func:`report`);
* ``--yes`` starts a job estimated above an hour or half the machine's memory (else refused with the estimate and
  what to do instead: :func:`plbar.app.cost.check_cost`);
* the model is ``--model``, ``-N/--elements``, ``--element``, ``--mass``, ``--end-mass``, the FE bar's
  ``--length``, ``--EA``, ``--rhoA`` (any consistent units: docs/cli.md "Units"); the inherent damping
  ``--rayleigh A B`` or ``--damping-ratio XI --at T_A T_B`` (``--damping-at``); the load ``--load-node`` /
  ``--load-at`` and ``--amplitude``; a TOML file is ``--case FILE`` (``plbar run FILE`` too) and then no model,
  load or search option may be given.
"""

from __future__ import annotations

import argparse
import json
import math
import warnings
from dataclasses import replace

import numpy as np

from ..app import Case, load_case
from ..errors import InputError, PlbarWarning
from ..model import MASSES, rayleigh_from_ratio
from ..model.damping import outside_fit
from ..util.progress import message

__all__ = ["output_args", "yes_arg", "case_args", "case_from_args", "case_flags", "progress", "report", "hidden",
           "plural"]

hidden = argparse.SUPPRESS

#: the model, load and search options (dest names); with a case file none of them may be given
CASE_OPTIONS = {"model": "--model", "elements": "-N/--elements", "element": "--element", "mass": "--mass",
                "mesh_file": "--mesh-file", "grading": "--grading", "end_mass": "--end-mass",
                "end_mass_absolute": "--end-mass-absolute", "modes": "--modes", "load_node": "--load-node",
                "load_at": "--load-at", "grid": "--grid", "T1": "--T1", "T2": "--T2", "method": "--method",
                "signatures": "--signatures", "rayleigh": "--rayleigh", "damping_ratio": "--damping-ratio",
                "damping_at": "--damping-at", "restitution": "--restitution", "gap": "--gap", "gravity": "--gravity",
                "length": "--length",
                "EA": "--EA", "rhoA": "--rhoA", "amplitude": "--amplitude", "matrices": "--matrices",
                "base": "--base", "EI": "--EI", "supports": "--supports", "contact_at": "--contact-at",
                "crack_at": "--crack-at"}


def output_args(p: argparse.ArgumentParser, default_out: str, what: str) -> None:
    """``--out``, ``--overwrite``, ``--quiet``, ``--json``."""
    g = p.add_argument_group("output")
    g.add_argument("--out", default=default_out, metavar="DIR", help=f"{what} [{default_out}]")
    g.add_argument("--overwrite", action="store_true",
                   help="replace what another command or case owns in DIR (its owner marker .plbar-owner.json)")
    g.add_argument("--quiet", "-q", action="store_true", help="print nothing on success (no progress bars)")
    g.add_argument("--json", action="store_true", help="print the result as JSON (no progress bars)")


def yes_arg(p: argparse.ArgumentParser) -> None:
    """``--yes``: start a costly job that is otherwise refused (:func:`plbar.app.cost.check_cost`)."""
    p.add_argument("--yes", "-y", action="store_true",
                   help="start a job estimated above an hour or half of this machine's memory (else refused, with "
                        "the estimate and a cheaper command)")


def case_args(p: argparse.ArgumentParser, load_help: str = "the case's load", sizes=None, at: bool = True,
              refused=()) -> None:
    """The model, damping, load and search options (all default to None: given ones are known) and ``--case``.

    ``sizes`` (a default list) makes ``-N/--elements`` a list of sizes (``a.sizes``; ``plbar refine``);
    ``at=False`` leaves ``--at`` to the command (the damping periods are then ``--damping-at`` only).
    ``refused`` (dest names): options the command refuses (with a line saying what to do); left out of its help.
    """
    g = p.add_argument_group("model")
    g.add_argument("--case", default=None, metavar="FILE.toml",
                   help="a TOML case file (examples/cases/); then no model, load or search option may be given")
    g.add_argument("--model", choices=("chain", "fe", "continuum", "beam", "matrices"), default=None,
                   help="the paper's chain (L = N), a finite-element bar (L = 1, or --length), the exact uniform "
                        "bar by characteristics (survey, export, render; -N: its steps per L/c [32]), an "
                        "Euler-Bernoulli beam against a stop (--EI, --supports, --contact-at; run and survey), or "
                        "another FE program's structure (--matrices FILE.npz; run and survey) [chain]")
    g.add_argument("--matrices", default=None, metavar="FILE.npz", help="--model matrices: a .npz of M, K, the "
                   "contact (r, or a DOF contact), the load q; optional C (Rayleigh) or rayleigh, restitution, x")
    if sizes is None:
        g.add_argument("--elements", "-N", type=int, default=None, metavar="N",
                       help="masses of the chain / elements of the FE bar [5 / 8]")
    else:
        g.add_argument("--elements", "-N", "--n", dest="sizes", type=int, nargs="+", default=list(sizes),
                       metavar="N", help="masses of the chain / elements of the FE bar, coarse to fine "
                                         f"[{' '.join(str(n) for n in sizes) or 'the case: 5 / 8'}]")
    _section_args(g)
    g.add_argument("--element", choices=("P1", "P2"), default=None, help="FE element [P1]")
    g.add_argument("--mass", choices=MASSES, default=None,
                   help="FE mass matrix; redistributed needs --end-mass > 0 [lumped]")
    g.add_argument("--mesh-file", default=None, help="meshio-readable 1D line mesh for --model fe")
    g.add_argument("--grading", type=float, default=None,
                   help="FE mesh grading: last/first element length [1 = uniform]")
    g.add_argument("--end-mass", type=float, default=None, metavar="M",
                   help="a rigid point mass on the contact node, as a fraction of the bar's mass (N m for the "
                        "chain) [0]")
    g.add_argument("--end-mass-absolute", action="store_true", default=None,
                   help="take --end-mass as an absolute mass")
    g.add_argument("--modes", type=int, default=None, metavar="M",
                   help="keep the lowest M modes of each state (modal truncation: never for xi_eq, see README) [all]")
    _contact_args(g)
    _damping_args(p, at)
    _load_args(p, load_help)
    g = p.add_argument_group("search")
    g.add_argument("--grid", type=int, nargs=2, default=None, metavar=("N1", "N2"),
                   help="scan grid over (T1, T2) [200 200]")
    g.add_argument("--T1", type=float, nargs=2, default=None, metavar=("LO", "HI"), help="T1 range [(0, T0_I/2]]")
    g.add_argument("--T2", type=float, nargs=2, default=None, metavar=("LO", "HI"), help="T2 range [(0, T0_II/2]]")
    g.add_argument("--signatures", choices=("default", "paper", "all"), default=None,
                   help="which periodic responses: the paper's class and every signature found without the user: "
                        "the zero-dwell class, period doublings, the neighbours where a branch stops being "
                        "admissible and what a simulation from rest settles on (default); the paper's class only "
                        "(paper: the fastest); the default with the survey's simulation and orbits up to m = 8 "
                        "(all) [default]")
    g.add_argument("--method", choices=("continuation", "grid"), default=None,
                   help="branches by pseudo-arclength continuation seeded by the scan, or by linking the "
                        "scan's crossings only (faster, may fragment) [continuation]")
    for act in p._actions:                   # refused options: still parsed (to say why), not offered
        if act.dest in refused:
            act.help = hidden


def _contact_args(g) -> None:
    """``--restitution``, ``--gap`` and ``--gravity``: the contact's impact law, the stop's position and the
    constant load that presses the bar on it (or pulls it away)."""
    g.add_argument("--restitution", type=float, default=None, metavar="E",
                   help="coefficient of restitution of the contact, 0 <= E <= 1 (Newton's impact law; run's "
                        "responses then rebound: R in their signatures; sweep-loads and refine need E = 0) [0]")
    g.add_argument("--gap", type=float, default=None, metavar="D",
                   help="the stop's distance from the contact at rest: D > 0 a clearance, D < 0 an interference "
                        "(held by the stop); with a gap the response depends on --amplitude over D [0]")
    g.add_argument("--gravity", type=float, default=None, metavar="G",
                   help="a uniform acceleration along the bar, G > 0 towards the stop: the weight of the bar's "
                        "masses under G, beside the harmonic load; the bar starts in its static equilibrium [0]")


def _section_args(g) -> None:
    """``--length``, ``--EA``, ``--rhoA``: the FE (or continuum) bar's length and section, in any consistent units."""
    g.add_argument("--length", type=float, default=None, metavar="L",
                   help="bar length (FE or continuum; the chain's is N), in any consistent units (docs/cli.md "
                        "'Units') [1]")
    g.add_argument("--EA", type=float, default=None, metavar="EA",
                   help="axial stiffness E A (a force: N in SI; FE or continuum) [1]")
    g.add_argument("--rhoA", type=float, default=None, metavar="RHOA",
                   help="mass per length rho A (kg/m in SI; FE, continuum or beam); the wave speed is "
                        "c = sqrt(EA/rhoA) [1]")
    g.add_argument("--EI", type=float, default=None, metavar="EI",
                   help="the beam's bending stiffness E I (--model beam) [1]")
    g.add_argument("--supports", choices=("clamped-free", "pinned-pinned", "clamped-clamped", "free-free"),
                   default=None,
                   help="the beam's supports (--model beam), a cracked FE bar's (clamped-free, clamped-clamped; "
                        "with --crack-at), or free-free: an FE bar with no support, a free body (dropped on the "
                        "stop with --gravity) [clamped-free: a cantilever]")
    g.add_argument("--contact-at", type=float, default=None, metavar="S",
                   help="the stop's position on the beam (--model beam) [the tip of a cantilever, else mid-span]")
    g.add_argument("--crack-at", type=float, default=None, metavar="S",
                   help="a breathing crack at the FE bar's vertex S: the contact is the crack's faces (open in "
                        "tension), the end x = L is free (--model fe) [none: the stop at x = L]")


def _load_args(p: argparse.ArgumentParser, load_help: str) -> None:
    """``--load-node``, ``--load-at`` (repeatable) and ``--amplitude`` (of every force)."""
    g = p.add_argument_group(f"load ({load_help}; default: a unit force on DOF 1 of the chain, at s = L/2 of an FE "
                             "bar)")
    g.add_argument("--load-node", type=int, action="append", default=None, metavar="K",
                   help="force on free DOF K (1-based from the clamp, as in the paper); repeatable")
    g.add_argument("--load-at", type=float, action="append", default=None, metavar="S",
                   help="point force at position S in (0, L] through the shape functions; repeatable")
    g.add_argument("--amplitude", type=float, default=None, metavar="Q",
                   help="the amplitude of every force (a force: N in SI; the response is linear in it, xi_eq "
                        "does not depend on it) [1]")
    g.add_argument("--base", type=float, default=None, metavar="A",
                   help="shake the support: its acceleration amplitude A along the bar (> 0 towards the stop), the "
                        "load -M t A cos(W t); responses relative to the support (with no force given, this alone)")


def _damping_args(p: argparse.ArgumentParser, at: bool) -> None:
    """``--rayleigh A B`` or ``--damping-ratio XI --at T_A T_B`` (``--damping-at`` if ``at`` is False)."""
    g = p.add_argument_group("inherent damping (Rayleigh, C = alpha M + beta K on the whole bar; default none)")
    g.add_argument("--rayleigh", type=float, nargs=2, default=None, metavar=("ALPHA", "BETA"),
                   help="Rayleigh coefficients alpha (mass) and beta (stiffness), both >= 0")
    g.add_argument("--damping-ratio", type=float, default=None, metavar="XI",
                   help="the Rayleigh damping with ratio XI (0.02 for 2 %%) at the two periods of --damping-at (--at)")
    g.add_argument("--damping-at", *(["--at"] if at else []), dest="damping_at", type=float, nargs=2, default=None,
                   metavar=("T_A", "T_B"),
                   help="the two periods where --damping-ratio holds (e.g. bracketing the periods of interest)")


def _rayleigh(a):
    """``(alpha, beta)`` from ``--rayleigh`` or ``--damping-ratio`` with ``--at``, or None."""
    ratio, at, ab = getattr(a, "damping_ratio", None), getattr(a, "damping_at", None), getattr(a, "rayleigh", None)
    if ratio is None and at is None:
        return None if ab is None else tuple(ab)
    if ab is not None:
        raise InputError("give --rayleigh A B or --damping-ratio XI --at T_A T_B, not both")
    if ratio is None or at is None:
        raise InputError("--damping-ratio XI needs --at T_A T_B (the two periods where the ratio holds), and "
                         "the other way round")
    return rayleigh_from_ratio(ratio, *at)


#: the one note of ``run`` and ``survey`` on an FE bar without a mass on its contact node (issue 44)
NO_CONTACT_MASS = ("plbar: note: this FE bar has no mass of its own at the contact (no --end-mass): its xi_eq is "
                   "a mesh artefact, the loss of the contact node's share of the element mass, and it vanishes "
                   "under refinement (the continuum bar without an end mass has no impact loss: docs/continuum.md); "
                   "give --end-mass M for a physical contact mass")


#: its form for a cracked bar, whose faces never carry a mass of their own (docs/crack.md)
CRACK_NO_MASS = ("plbar: note: a crack's faces have no mass of their own: its xi_eq is a mesh artefact, the loss of "
                 "the faces' shares of their elements' mass, and it vanishes under refinement (as h: docs/crack.md)")
#: the note of a survey whose free state floats (plbar.TwoStateSystem.floating)
FLOATING = ("plbar: note: the free state moves as a rigid body that every contact pushes away (a cracked bar's outer "
            "part): no periodic motion has a contact (docs/crack.md), so each motion from rest leaves the stop for "
            "good; its long run is a free flight, counted as irregular")


def note_no_contact_mass(a, case) -> None:
    """Print :data:`NO_CONTACT_MASS` once for an FE case with no point mass on its contact node (unless quiet); for a
    cracked bar :data:`CRACK_NO_MASS`, and :data:`FLOATING` where its outer part floats."""
    if case.model != "fe" or getattr(a, "quiet", False) or getattr(a, "json", False):
        return
    bar = case.bar()
    if bar.crack_at is not None:
        message(CRACK_NO_MASS)
        prob = case.problem()
        if prob.system.floating and prob.statics.accel is None:
            message(FLOATING)
        return
    x = np.asarray(bar.nodes, float)
    if not any(int(np.argmin(np.abs(x - xp))) == x.size - 1 and mp > 0 for xp, mp in bar.point_masses):
        message(NO_CONTACT_MASS)


def warn_damping_fit(a, T) -> None:
    """One :class:`~plbar.errors.PlbarWarning` when ``--damping-ratio XI --at T_A T_B`` is evaluated at forcing
    periods ``T`` far outside ``[T_A, T_B]`` (:func:`plbar.model.damping.outside_fit`), where the ratio is not XI."""
    ratio, at = getattr(a, "damping_ratio", None), getattr(a, "damping_at", None)
    text = outside_fit(ratio, at, T) if ratio and at is not None and len(T) else None
    if text:
        warnings.warn(text, PlbarWarning, stacklevel=2)


def case_from_args(a):
    """``(Case, OutputSettings or None)`` of the parsed options (a case file, or the model/load/search options)."""
    if a.case:
        given = [flag for dest, flag in CASE_OPTIONS.items() if getattr(a, dest, None) is not None]
        if given:
            raise InputError(f"{given[0]} conflicts with the case file {a.case!r}, which defines the model, load "
                             "and search; edit the file or drop the option")
        return load_case(a.case)
    amp = _amplitude(getattr(a, "amplitude", None))
    nodes = tuple((k, amp) for k in (a.load_node or ()))
    points = tuple((s, amp) for s in (a.load_at or ()))
    kw = dict(model=a.model, n=getattr(a, "elements", None), element=a.element, mass=a.mass, mesh_file=a.mesh_file,
              matrices=getattr(a, "matrices", None),
              load_scale=amp if getattr(a, "matrices", None) is not None else None,
              length=getattr(a, "length", None), EA=getattr(a, "EA", None), rhoA=getattr(a, "rhoA", None),
              grading=a.grading, grid=tuple(a.grid) if a.grid else None, T1=tuple(a.T1) if a.T1 else None,
              T2=tuple(a.T2) if a.T2 else None, method=a.method,
              signatures=getattr(a, "signatures", None), modes=a.modes, end_mass=a.end_mass,
              end_mass_absolute=a.end_mass_absolute, rayleigh=_rayleigh(a),
              restitution=getattr(a, "restitution", None), gap=getattr(a, "gap", None),
              gravity=getattr(a, "gravity", None), base=getattr(a, "base", None), EI=getattr(a, "EI", None),
              supports=getattr(a, "supports", None), contact_at=getattr(a, "contact_at", None),
              crack_at=getattr(a, "crack_at", None))
    case = Case(load_nodes=nodes, load_points=points, **{k: v for k, v in kw.items() if v is not None})
    if not hasattr(a, "sizes") and case.structure is None:   # sizes (-N): each size's case is checked where made
        refuse_contact_load(case, nodes)
    if nodes or points or amp == 1.0 or case.structure is not None:
        return case, None
    return replace(case, load_nodes=tuple((k, amp * q) for k, q in case.load_nodes),   # the default load, scaled
                   load_points=tuple((s, amp * q) for s, q in case.load_points)), None


def _amplitude(amp) -> float:
    """``--amplitude`` (default 1): a finite force > 0 (the response is linear in it)."""
    if amp is None:
        return 1.0
    if not (math.isfinite(amp) and amp > 0):
        raise InputError(f"--amplitude {amp:g} is not allowed; it must be a finite force > 0 (the amplitude of every "
                         "force of the load; a negative one is the same load half a period later)")
    return float(amp)


def refuse_contact_load(case, nodes) -> None:
    """Refuse a ``--load-node`` (``nodes``) on the contact DOF of ``case``: the paper loads the bar away from its
    contact (the last DOF, at the wall), where a force goes straight into the reaction.  A structure given by its
    matrices holds its own load (the case refuses ``--load-node``)."""
    if case.structure is not None:
        return
    n = case.bar().n_dofs
    if any(k == n for k, _ in nodes):
        raise InputError(f"--load-node {n} is the contact DOF (at the wall); the paper's load acts on DOFs 1..{n - 1} "
                         f"(a force on the contact goes straight into the reaction): give --load-node 1..{n - 1} "
                         "or --load-at S")


def case_flags(a, skip=()) -> str:
    """The model and load options given in ``a`` as command-line text (``--case FILE`` for a case file), leaving out
    the dest names ``skip``: to name another command on the same case."""
    if getattr(a, "case", None):
        return f"--case {a.case}"
    words = []
    for dest, flag in CASE_OPTIONS.items():
        v = getattr(a, dest, None)
        if v is None or dest in skip:
            continue
        flag = flag.split("/")[0]
        if v is True:
            words.append(flag)
        elif isinstance(v, (list, tuple)) and dest in ("load_node", "load_at"):
            words += [f"{flag} {x:g}" for x in v]
        elif isinstance(v, (list, tuple)):
            words.append(f"{flag} {' '.join(f'{x:g}' for x in v)}")
        else:
            words.append(f"{flag} {v:g}" if isinstance(v, (int, float)) else f"{flag} {v}")
    return " ".join(words)


def progress(a) -> bool:
    """Progress bars (stderr) unless ``--quiet`` or ``--json``."""
    return not (getattr(a, "quiet", False) or getattr(a, "json", False))


def _paths(files):
    """``files`` with every path as a string (name -> path, or a list of paths)."""
    if isinstance(files, dict):
        return {k: _paths(v) for k, v in files.items()}
    if isinstance(files, (list, tuple)):
        return [str(f) for f in files]
    return str(files)


def report(a, summary: dict, files: dict, text: str, **data) -> None:
    """Print the result as JSON (``--json``), ``text`` (default) or nothing (``--quiet``).

    The JSON is one shape for every command: ``{"summary": {...}, "files": {name: path or [paths]}}``, and the
    command's tables ``data`` (``refine``: ``rates``, ``rows``) beside them.
    """
    if a.json:
        print(json.dumps({"summary": summary, "files": _paths(files), **data}, default=str))
    elif not a.quiet:
        print(text)


def plural(n: int, word: str, width: int = 0) -> str:
    """``"1 point"``, ``"2 points"``, ``"3 branches"`` (``n`` right-aligned in ``width``)."""
    if n != 1:
        word += "es" if word.endswith(("ch", "sh", "s", "x")) else "s"
    return f"{n:{width}d} {word}"
