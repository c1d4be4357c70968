"""Load studies on one path solve (issue #12): positions, node pairs and the worst load.

:func:`sweep_loads` solves the paths once (the case's own load is the
reference; any load with ``h(q) != 0`` has the same paths), builds the
quadratic forms of :mod:`.forms` and writes into ``out``:

``xi_positions.npz``
    ``xi`` and ``dPL`` (path points x positions) for a unit point force at each
    position ``s`` (default: ``per_element`` positions per element, the element
    ends included, the clamp ``s = 0`` excluded: a force there does nothing),
    with ``s`` and, per path point, ``branch, point, T``: 8 bytes a number,
    against about 85 characters a row of the tidy CSV, which repeats the
    path point on every row (``positions_csv=True`` writes that too:
    ``xi_positions.csv``, ``branch, point, T, s, xi, dPL``).
``worst_load.csv``
    ``branch, point, T1, T2, phi, T, xi_worst, xi_best_single, s_best_single``:
    the largest ``xi_eq`` over every load distribution (``b^T G^+ b / 2``)
    and over every single point force (exact per-element maximum).
``worst_load_shapes.npz``
    The worst load ``q*`` (unit norm) per path point, with ``x`` (DOF positions).
``xi_along_mesh.vtu``
    A polyline through the evaluated positions (``xi_positions.npz``'s ``s``), one
    point each: the max over all path points (and per family) of ``xi_eq`` and
    ``Delta_PL`` when the unit force acts there.
``load_pairs.csv``
    The paper's Fig. 9 cases as special cases of the quadratic form: a unit
    force on each free non-contact vertex and every pair of them (0.5 each);
    per load and family the ``xi_eq`` range and where its maximum is.
``summary.json``
    Per family: largest ``xi_worst``, best single position, best pair; loads
    with ``h(q) = 0`` at some path points (``"no path"`` there); timings.
``xi_T_s.png``
    ``xi_eq`` over ``(T, s)`` per family, with ``xi_worst(T)`` above it.
"""

from __future__ import annotations

import contextlib
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ...app.applies import refuse_static_part
from ...errors import InputError
from ...util.outputs import check_folder, clear_owned
from ...util.reprs import build, rng
from ...util.version import __version__
from ..execution import run_options
from .families import FAMILIES, OTHER, assign_families
from .forms import HZERO_TOL, LoadForms, load_forms
from .write import PAIRS_HEADER, POSITIONS_HEADER, WARN_BYTES, WORST_HEADER, tidy_positions, write_all

__all__ = ["sweep_loads", "LoadStudy", "mesh_positions", "vertex_loads", "family_labels", "pair_table",
           "position_table", "tidy_positions", "worst_table", "check_positions", "POSITIONS_HEADER", "WORST_HEADER",
           "PAIRS_HEADER", "SWEEP_OWNED", "WARN_BYTES"]

#: what ``sweep-loads`` owns in its folder (the old table names too: an earlier sweep's files are never left over)
SWEEP_OWNED = ("xi_positions.npz", "xi_positions.csv", "worst_load.csv", "worst_load_shapes.npz", "xi_along_mesh.vtu",
               "load_pairs.csv", "xi_T_s.png", "summary.json", "sweep.csv", "sweep_max.csv", "sweep_summary.json",
               ".*.part.*")


@dataclass(frozen=True)
class LoadStudy:
    """Every load from one path solve (:func:`sweep_loads`): the tables, the summary and the files.

    Attributes
    ----------
    case : plbar.Case
        The case; its load is the reference.
    result : plbar.Result
        The one path solve.
    forms : LoadForms
        The load quadratic forms at every path point (:func:`load_forms`).
    families : ndarray of str, shape (P,)
        Family label of every path point.
    worst : Worst
        The worst load distribution per path point (``q*`` in ``worst.q``).
    positions : dict
        ``xi_positions.npz``: ``branch, point, T`` (P,), ``s`` (S,), ``xi, dPL`` (P, S).
    worst_load : dict
        The columns of ``worst_load.csv`` (:data:`WORST_HEADER`).
    pairs : dict
        The columns of ``load_pairs.csv`` (:data:`PAIRS_HEADER`).
    summary : dict
        The content of ``summary.json``.
    files : dict
        Written files, name -> Path (empty without ``out``).
    """

    case: object
    result: object = field(repr=False)
    forms: object = field(repr=False)
    families: np.ndarray = field(repr=False)
    worst: object = field(repr=False)
    positions: dict = field(repr=False)
    worst_load: dict = field(repr=False)
    pairs: dict = field(repr=False)
    summary: dict = field(repr=False)
    files: dict = field(default_factory=dict, repr=False)

    def __len__(self) -> int:
        return len(self.forms)

    @property
    def tables(self) -> dict:
        """The three tables by name: ``positions``, ``worst``, ``pairs``."""
        return {"positions": self.positions, "worst": self.worst_load, "pairs": self.pairs}

    def __repr__(self) -> str:
        return build("LoadStudy", {"path_points": len(self), "positions": int(np.size(self.positions["s"])),
                                   "T": rng(self.forms.T), "xi_worst": rng(self.worst.xi),
                                   "families": sorted(self.summary.get("families", {})), "files": len(self.files)})


def check_positions(case, positions=None, per_element: int = 50) -> None:
    """Refuse bad positions or ``per_element`` before any solve (one line saying what to give instead)."""
    if positions is None:
        if isinstance(per_element, bool) or not isinstance(per_element, (int, np.integer)) or per_element < 1:
            raise InputError(f"per_element = {per_element!r} must be a positive integer (positions per element, "
                             "--per-element K)")
        return
    s = np.asarray(positions, dtype=float).ravel()
    L = case.bar().length
    bad = s[~(np.isfinite(s) & (s > 0) & (s <= L * (1 + 1e-12)))]
    if s.size == 0 or bad.size:
        what = f"position {bad[0]:g} is outside" if bad.size else "no position given for"
        raise InputError(f"{what} the bar (0, {L:g}]; give unit-force positions S with 0 < S <= L (--positions)")


def mesh_positions(lf: LoadForms, per_element: int = 50) -> np.ndarray:
    """``per_element`` positions per element, ``left + k h / per_element`` for ``k = 1..per_element``."""
    if int(per_element) < 1:
        raise InputError(f"per_element = {per_element!r} must be a positive integer")
    el = lf._elems()
    k = np.arange(1, int(per_element) + 1) / int(per_element)
    return (el.left[:, None] + k[None, :] * (el.right - el.left)[:, None]).ravel()


def vertex_loads(lf: LoadForms, amplitude: float = 0.5):
    """The paper's Fig. 9 load cases: each free non-contact vertex (1.0) and each pair (``amplitude`` each)."""
    el = lf._elems()
    xv = np.unique(np.r_[el.left, el.right])
    xv = xv[(xv > 0) & (xv < xv[-1])]
    singles = [((float(s), 1.0),) for s in xv]
    pairs = [((float(xv[i]), amplitude), (float(xv[j]), amplitude)) for i in range(xv.size)
             for j in range(i + 1, xv.size)]
    return singles + pairs


def family_labels(paths, lf: LoadForms) -> np.ndarray:
    """Family label of every path point (:func:`.families.assign_families` per branch)."""
    br = paths.branches
    T0I, T0II = paths.prob.system.T0
    labels = assign_families([(float(b.T.min()), float(b.T.max())) for b in br], [len(b) for b in br], T0I, T0II)
    lab = {b.id: f for b, f in zip(br, labels)}
    return np.array([lab[int(i)] for i in lf.branch], dtype=object)


def _load_vector(lf: LoadForms, load) -> np.ndarray:
    s = np.array([p[0] for p in load], float)
    a = np.array([p[1] for p in load], float)
    return a @ lf.point_vectors(s)


def pair_table(lf: LoadForms, fam: np.ndarray, loads) -> dict:
    """Per load case (sequence of ``(s, a)``) and family: the ``xi_eq`` range and its maximum (Fig. 9)."""
    Q = np.array([_load_vector(lf, ld) for ld in loads])
    xi, dpl, phase = lf.xi(Q), lf.dPL(Q), lf.phase(Q)
    nop = lf.no_path(Q)
    rows = {k: [] for k in PAIRS_HEADER}
    for li, ld in enumerate(loads):
        (s1, a1), (s2, a2) = ld[0], (ld[1] if len(ld) > 1 else (np.nan, np.nan))
        for f in FAMILIES + ("all",):
            m = np.ones(len(lf), bool) if f == "all" else (fam == f)
            if not m.any():
                continue
            i = np.flatnonzero(m)[int(np.argmax(xi[m, li]))]
            vals = dict(load="+".join(f"{a:g}@{s:g}" for s, a in ld), s1=s1, a1=a1, s2=s2, a2=a2, family=f,
                        points=int(m.sum()), T_min=lf.T[m].min(), T_max=lf.T[m].max(), xi_min=xi[m, li].min(),
                        xi_max=xi[i, li], T_at_max=lf.T[i], T1_at_max=lf.T1[i], T2_at_max=lf.T2[i],
                        phi_at_max=float(phase[i, li]), dPL_at_max=dpl[i, li],
                        no_path_points=int(nop[m, li].sum()))
            for k in PAIRS_HEADER:
                rows[k].append(vals[k])
    return rows


def position_table(lf: LoadForms, positions) -> dict:
    """``xi_eq`` and ``Delta_PL`` of a unit force at every position and path point.

    Returns ``branch, point, T`` (P,), ``s`` (S,) and ``xi, dPL`` (P, S) (what ``xi_positions.npz`` holds).
    """
    s = np.asarray(positions, float).ravel()
    xi, dpl = lf.point_loads(s)
    return {"branch": np.asarray(lf.branch), "point": np.asarray(lf.point), "T": np.asarray(lf.T), "s": s,
            "xi": xi, "dPL": dpl}


def worst_table(lf: LoadForms) -> tuple[dict, object]:
    """``worst_load.csv`` columns and the :class:`.extremes.Worst` result."""
    w = lf.worst()
    xb, sb = lf.element_max().best()
    cols = {"branch": lf.branch, "point": lf.point, "T1": lf.T1, "T2": lf.T2, "phi": np.mod(lf.phi, 2 * np.pi),
            "T": lf.T, "xi_worst": w.xi, "xi_best_single": xb, "s_best_single": sb}
    return cols, w


def _no_path(lf: LoadForms, named: list[tuple[str, np.ndarray]]) -> list[dict]:
    """Loads with ``h(q) = 0`` at some path points: no periodic response there (not dropped silently)."""
    out = []
    for name, q in named:
        if not np.any(q):
            out.append({"load": name, "points": len(lf), "all_points": True, "why": "zero load vector"})
            continue
        z = lf.no_path(q)
        if z.any():
            out.append({"load": name, "points": int(z.sum()), "all_points": bool(z.all()),
                        "why": "h(q) = (H q)_c = 0: the load does not move the contact; no periodic path",
                        "at": [{"branch": int(lf.branch[i]), "point": int(lf.point[i]), "T": float(lf.T[i])}
                               for i in np.flatnonzero(z)[:20]]})
    return out


def _summary(lf, fam, wcols, pairs_rows, positions, no_path, times) -> dict:
    fams = {}
    for f in FAMILIES + (OTHER,):
        m = fam == f
        if not m.any():
            continue
        i = np.flatnonzero(m)[int(np.argmax(wcols["xi_worst"][m]))]
        j = np.flatnonzero(m)[int(np.argmax(wcols["xi_best_single"][m]))]
        entry = {"points": int(m.sum()), "T_range": [float(lf.T[m].min()), float(lf.T[m].max())],
                 "xi_worst_max": float(wcols["xi_worst"][i]), "T_at_xi_worst_max": float(lf.T[i]),
                 "xi_best_single_max": float(wcols["xi_best_single"][j]), "T_at_best_single": float(lf.T[j]),
                 "s_at_best_single": float(wcols["s_best_single"][j])}
        pr = [k for k, ff in enumerate(pairs_rows["family"]) if ff == f and not np.isnan(pairs_rows["a2"][k])]
        if pr:
            k = max(pr, key=lambda r: pairs_rows["xi_max"][r])
            entry["best_pair"] = {"load": pairs_rows["load"][k], "xi_max": float(pairs_rows["xi_max"][k]),
                                  "T_at_max": float(pairs_rows["T_at_max"][k])}
        fams[f] = entry
    return {"path_points": len(lf), "dofs": lf.n, "positions": int(np.size(positions)),
            "reference_load": lf.q_ref.tolist(), "families": fams, "no_path": no_path,
            "h_zero_tol": HZERO_TOL, "times": {k: round(v, 6) for k, v in times.items()},
            "note": ("xi_worst = b^T G^+ b / 2 is the largest xi_eq over every in-phase load distribution at that "
                     "path point (docs/load_structure.md); loads with h(q) = 0 have no periodic path there"
                     if not hasattr(lf, "dPL_ref") else
                     "with Rayleigh damping every load with h(q) != 0 has the reference paths at the phase "
                     "phi + arg(h(q) / h_ref); xi_worst is the largest xi_eq over every in-phase load distribution "
                     "(a phase scan, docs/load_structure.md section 9); loads with h(q) = 0 have no periodic path")}


def _paper_scan_only(case) -> None:
    """Refuse a case with a static part (a gap, a constant load) or a shaking support: sweep-loads follows the
    paper's scan and sweeps a unit force."""
    refuse_static_part(case, "sweep-loads follows the paper's scan of (T1, T2)",
                       "the real motion at every load position: plbar survey --positions S ...")
    if case.base:
        raise InputError(f"base = {case.base:g}: sweep-loads sweeps a unit force over the bar, and a shaking support "
                         "is not a force at a position; the periodic responses under the base: plbar run --base A")
    if case.structure is None and case.model == "fe" and case.crack_at is not None:
        raise InputError(f"crack_at = {case.crack_at:g}: sweep-loads sweeps a unit force over a bar against a stop at "
                         "x = L (its load forms); a cracked bar's real motion at every load position: plbar survey "
                         "--crack-at S --per-element K")


def sweep_loads(case=None, out=None, positions=None, per_element: int = 50, pairs: bool = True, loads=(),
                positions_csv: bool = False, **options) -> LoadStudy:
    """One path solve, then every load position, the node pairs and the worst load.

    Parameters
    ----------
    case : plbar.Case, optional
        The bar and the reference load (default: the paper's chain ``N = 5``, DOF 1).
    out : path, optional
        Study folder; nothing is written if None.  Claimed for ``sweep-loads``
        (:func:`plbar.util.outputs.claim_folder`): another command's or case's folder
        is refused unless ``overwrite``.
    positions : array_like, optional
        Unit point-force positions in ``(0, L]``; default :func:`mesh_positions` with ``per_element``
        (both checked before the solve).
    pairs : bool
        Also the Fig. 9 table (:func:`vertex_loads`).
    loads : sequence of sequences of (s, a)
        Extra load combinations for the pair table (e.g. ones with ``h(q) = 0``).
    positions_csv : bool
        Also write the positions table as the tidy ``xi_positions.csv``.

    Other Parameters
    ----------------
    progress, overwrite, plot : bool
        The run options (:class:`plbar.studies.RunOptions`; one solve in this process: no executor): the
        solve's progress on stderr, ``overwrite`` as above, and ``xi_T_s.png`` (needs matplotlib).

    Returns
    -------
    LoadStudy
        ``files`` (name -> Path), ``summary`` (the content of ``summary.json``), ``forms``
        (:class:`LoadForms`), ``result`` (the solve), the tables ``positions``, ``worst_load``, ``pairs``.
    """
    from ...app import Case, case_fingerprint, solve

    opts = run_options(options, "sweep_loads", executor=False)
    case = Case() if case is None else case
    _paper_scan_only(case)
    if case.restitution:
        raise InputError(f"restitution = {case.restitution:g}: sweep-loads is the paper's class (one plastic impact "
                         "and a stuck phase per period, Sec. 4.2), which needs e = 0; the real motion at every load "
                         "position with rebounds: plbar survey --positions S ... --restitution E")
    check_positions(case, positions, per_element)
    claim = None if out is None else \
        check_folder(out, "sweep-loads", case_fingerprint(case), SWEEP_OWNED, opts.overwrite)   # before the solve
    files = {}
    with claim or contextlib.nullcontext():
        t0 = time.perf_counter()
        res = solve(replace(case, signatures="paper"), progress=opts.progress)   # the study is of the paper's class
        r = _study(res, positions, per_element, pairs, loads, {"solve": time.perf_counter() - t0})
        if claim is not None:
            claim.take()
            clear_owned(claim.folder, SWEEP_OWNED)
            files = write_all(claim.folder, r, res, opts.plot, positions_csv)
    return LoadStudy(case, res, **r, files=files)


def _study(res, positions, per_element, pairs, loads, times) -> dict:
    """The load study of one solve: forms, families, the tables and the summary (no files)."""
    t1 = time.perf_counter()
    lf = load_forms(res.paths)
    fam = family_labels(res.paths, lf)
    pos_s = mesh_positions(lf, per_element) if positions is None else np.asarray(positions, float).ravel()
    pos = position_table(lf, pos_s)
    wcols, w = worst_table(lf)
    cases = (vertex_loads(lf) if pairs else []) + [tuple(tuple(p) for p in ld) for ld in loads]
    prow = pair_table(lf, fam, cases) if cases else {k: [] for k in PAIRS_HEADER}
    named = [(f"1@{s:g}", q) for s, q in zip(pos_s, lf.point_vectors(pos_s))]
    named += [("+".join(f"{a:g}@{s:g}" for s, a in ld), _load_vector(lf, ld)) for ld in cases]
    no_path = _no_path(lf, named)
    times["load_study"] = time.perf_counter() - t1
    summary = _summary(lf, fam, wcols, prow, pos_s, no_path, times)
    summary["case"] = res.case.to_dict()
    summary["plbar_version"] = __version__
    return {"summary": summary, "forms": lf, "families": fam, "worst": w, "positions": pos, "worst_load": wcols,
            "pairs": prow}
