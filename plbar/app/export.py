"""From results to files and pictures: pick one response, rebuild it from a run folder, export and render it.

The file formats live in :mod:`plbar.io` and the drawing in :mod:`plbar.visuals`;
this module decides *which* response (a branch and a point of a
:class:`~plbar.app.run.Result`, a ``plbar run`` folder, or given orbits).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io import FORMATS, ResponseData, load_pvd, response_data, write_data
from ..io.vtk import ResponseFiles
from ..response import Orbits, damping, orbits
from ..util.outputs import claim_folder, clear_owned, fingerprint, require
from .case import Case
from .run import case_fingerprint, read_paths

__all__ = ["select", "from_run", "case_of_run", "write_response", "write_response_data", "response_of",
           "render_response",
           "export_owned", "RENDER_OWNED"]

#: what :func:`plbar.visuals.render` writes (cleared before a new render)
RENDER_OWNED = ("snapshot_[0-9][0-9].png", "snapshots.png", "spacetime.png", "response.gif")


def export_owned(name: str = "response") -> tuple[str, ...]:
    """What an export named ``name`` writes (cleared before a new export, so no old format stays)."""
    return (f"{name}_[0-9][0-9][0-9][0-9].vtu", f"{name}.pvd", f"{name}.xdmf", f"{name}.h5", f"{name}_steps.csv",
            f"{name}.json")


def _requirements(format: str, what: str) -> None:
    """The optional packages a format needs (a one-line error naming the extra, before any file is made)."""
    if format in ("pvd", "both"):
        require("pyvista", what)
    if format in ("xdmf", "both"):
        require("h5py", what)
        require("meshio", what)


def _orbits_of(source) -> Orbits:
    """The orbits of ``source``: an Orbits, or (Problem, Orbits) (re-attached to that problem)."""
    if isinstance(source, tuple) and len(source) == 2:
        prob, orb = source
        if orb.prob is not prob:
            orb = Orbits(prob, *(getattr(orb, f) for f in ("T1", "T2", "phi", "eta0", "v0", "eta_s", "v_s")))
        return orb
    if isinstance(source, Orbits):
        return source
    raise InputError(f"cannot export a {type(source).__name__}; give a Result, Paths, Orbits or (Problem, Orbits)")


def select(source, branch: int | None = None, index: int | None = None):
    """Pick one periodic response.

    Parameters
    ----------
    source : Result, Paths, Orbits or (Problem, Orbits)
        Where the response comes from.
    branch : int, optional
        Branch id (``Result`` / ``Paths``); default: the branch holding the
        largest ``xi_eq``.
    index : int, optional
        Point index along the branch (or into the ``Orbits``; negative counts
        from the end); default: the point of largest ``xi_eq``.

    Returns
    -------
    orbit : Orbits
        A single orbit (length 1).
    info : dict
        ``T1, T2, phi, T, xi, dPL`` and ``branch, index`` where known.
    """
    paths = getattr(source, "paths", source)
    if hasattr(paths, "branches"):
        brs = paths.branches
        if not brs:
            raise InputError("the result has no periodic path; nothing to export")
        if branch is None:
            b = max(brs, key=lambda x: float(np.max(x.xi)))
        else:
            ids = [x.id for x in brs]
            if branch not in ids:
                raise InputError(f"branch = {branch!r} does not exist; branches are {_ranges(ids)}")
            b = brs[ids.index(branch)]
        orb, xi, dpl, bid = b.orbits, b.xi, b.dPL, b.id
    else:
        if branch is not None:
            raise InputError("branch = ... needs a Result or Paths; an Orbits has no branches")
        orb = _orbits_of(source)
        d = damping(orb)
        xi, dpl, bid = d.xi, d.dPL, None
    n = len(orb)
    if index is None:
        i = int(np.argmax(xi))
    else:
        if isinstance(index, bool) or not isinstance(index, (int, np.integer)) or not -n <= index < n:
            raise InputError(f"index = {index!r} is out of range; the branch has {n} points (0..{n - 1})")
        i = int(index) % n
    one = orb.take([i])
    info = {"T1": float(one.T1[0]), "T2": float(one.T2[0]), "phi": float(np.mod(one.phi[0], 2 * np.pi)),
            "T": float(one.T[0]), "xi": float(xi[i]), "dPL": float(dpl[i]), "index": i}
    if bid is not None:
        info["branch"] = int(bid)
    return one, info


def _ranges(ids) -> str:
    return ", ".join(str(i) for i in ids) if len(ids) <= 12 else f"{ids[0]}..{ids[-1]}"


def from_run(folder, branch: int | None = None, index: int | None = None):
    """Rebuild one orbit of a previous ``plbar run`` from ``summary.json`` and ``paths.csv``.

    The triplet ``(T1, T2, phi)`` is read from the CSV row (written with 17
    digits) and the orbit rebuilt with :func:`plbar.orbits`; nothing is
    re-scanned.

    Returns
    -------
    case : Case
    orbit : Orbits (length 1)
    info : dict
    """
    folder = Path(folder)
    cfile = folder / "paths.csv"
    case = case_of_run(folder)
    if not cfile.is_file():
        raise InputError(f"{str(cfile)!r} does not exist; give the --out folder of a previous 'plbar run'")
    cols = read_paths(cfile)
    if cols["branch"].size == 0:
        raise InputError(f"{str(cfile)!r} has no periodic path; nothing to export")
    bcol, xicol = cols["branch"].astype(int), cols["xi"]
    if branch is None:
        branch = int(bcol[int(np.argmax(xicol))])
    sel = np.flatnonzero(bcol == branch)
    if sel.size == 0:
        raise InputError(f"branch = {branch!r} does not exist in {str(cfile)!r}; branches are "
                         f"{_ranges(sorted(set(bcol.tolist())))}")
    if index is None:
        index = int(np.argmax(xicol[sel]))
    if isinstance(index, bool) or not -sel.size <= index < sel.size:
        raise InputError(f"index = {index!r} is out of range; branch {branch} has {sel.size} points "
                         f"(0..{sel.size - 1})")
    k = sel[int(index) % sel.size]
    T1, T2, phi = (float(cols[c][k]) for c in ("T1", "T2", "phi"))
    if "signature" in cols and cols["signature"][k] != "1P":          # another signature: rebuilt exactly
        return case, *_hybrid_row(case, cols, k, int(branch), int(index) % sel.size)
    orb = orbits(case.problem(), T1, T2, phi)
    d = damping(orb)
    info = {"T1": T1, "T2": T2, "phi": phi, "T": float(orb.T[0]),
            "xi": float(d.xi[0]), "dPL": float(d.dPL[0]), "branch": int(branch), "index": int(index) % sel.size}
    return case, orb, info


def case_of_run(folder) -> Case:
    """The case of a previous ``plbar run`` in ``folder`` (from its ``summary.json``)."""
    sfile = Path(folder) / "summary.json"
    if not sfile.is_file():
        raise InputError(f"{str(sfile)!r} does not exist; give the --out folder of a previous 'plbar run'")
    try:
        return Case(**_tuples(json.loads(sfile.read_text())["case"]))
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{str(sfile)!r} does not hold a valid case: {' '.join(str(exc).split())}") from None


def _hybrid_row(case, cols, k: int, branch: int, index: int):
    """The orbit of row ``k`` of another signature, as a :class:`plbar.motion.Series`
    (:func:`plbar.periodic.orbit_series`), and its info."""
    from ..periodic import from_row, orbit_series, signature

    sig = signature(cols["signature"][k])
    d = [float(x) for x in str(cols["durations"][k]).split(";")]
    orb = from_row(case.problem(), sig, float(cols["T"][k]), d, float(cols["phi"][k]))
    info = {"T1": float(cols["T1"][k]), "T2": float(cols["T2"][k]), "phi": orb.phi, "T_forcing": orb.T,
            "signature": str(sig), "m": sig.m, "xi": orb.xi, "dPL": orb.dPL, "branch": branch, "index": index}
    return orbit_series(orb), info


def _tuples(o):
    if isinstance(o, dict):
        return {k: _tuples(v) for k, v in o.items()}
    if isinstance(o, list):
        return tuple(_tuples(v) for v in o)
    return o




def _owner(case, data) -> str:
    """The fingerprint an export or render records: its case's (to join that run's folder), else the response's."""
    if isinstance(case, Case):
        return case_fingerprint(case)
    return fingerprint({k: v for k, v in data.info.items() if k in ("T1", "T2", "phi", "T")})


def write_response(source, folder, *, branch: int | None = None, index: int | None = None, periods: int = 1,
                   steps: int = 40, format: str = "pvd", name: str = "response",
                   overwrite: bool = False) -> ResponseFiles:
    """Write one periodic response for ParaView.

    Parameters
    ----------
    source : Result, Paths, Orbits or (Problem, Orbits)
        See :func:`select`.
    folder : path
        Output folder (created).  Every file is written atomically.
    branch, index : int, optional
        Which response (default: the largest ``xi_eq``).
    periods : {1, 2}
    steps : int
        Time steps per period.
    format, name
        As in :func:`plbar.io.write_data` (which writes the files).
    overwrite : bool
        Replace what another command or case owns in ``folder`` (see :func:`write_response_data`).

    Returns
    -------
    ResponseFiles
    """
    if format not in FORMATS:
        raise InputError(f"format = {format!r} is not allowed; choose one of {', '.join(FORMATS)}")
    orb, info = select(source, branch, index)
    return write_response_data(response_data(orb, info, periods, steps), folder, format=format, name=name,
                               case=getattr(source, "case", None), overwrite=overwrite)


def write_response_data(data: ResponseData, folder, *, format: str = "pvd", name: str = "response", case=None,
                        overwrite: bool = False) -> ResponseFiles:
    """:func:`plbar.io.write_data` into a folder cleared of an earlier export (optional packages checked first).

    The folder is claimed for ``export`` (:func:`plbar.util.outputs.claim_folder`): a folder of another command
    or case is refused unless ``overwrite``; the folder of the ``run`` of the same ``case`` is joined (the export's
    files become that run's, so a later run of another case removes them).
    """
    if format not in FORMATS:
        raise InputError(f"format = {format!r} is not allowed; choose one of {', '.join(FORMATS)}")
    _requirements(format, "the ParaView export")
    with claim_folder(folder, "export", _owner(case, data), export_owned(name), overwrite, joins=("run",)):
        clear_owned(folder, export_owned(name))
        return write_data(data, Path(folder), format=format, name=name)


def response_of(source, branch: int | None = None, index: int | None = None, steps: int = 40) -> ResponseData:
    """One response sampled on its mesh, from a ``.pvd``, a folder (with a ``.pvd`` or a ``plbar run``
    result), :class:`~plbar.io.ResponseData`, or anything :func:`select` takes."""
    if isinstance(source, ResponseData):
        return source
    if isinstance(source, (str, os.PathLike)):
        p = Path(source)
        if p.is_file() and p.suffix == ".pvd":
            return load_pvd(p)
        if p.is_dir():
            pvds = sorted(p.glob("*.pvd")) or sorted((p / "vtk").glob("*.pvd"))
            named = [f for f in pvds if f.stem == "response"]
            if named or pvds:
                return load_pvd((named or pvds)[0])
            if (p / "summary.json").is_file():
                _, orb, info = from_run(p, branch, index)
                return response_data(orb, info, 1, steps)
        raise InputError(f"{str(p)!r} is neither a .pvd file nor a folder with one or with a 'plbar run' result")
    orb, info = select(source, branch, index)
    return response_data(orb, info, 1, steps)


def render_response(source, out, *, branch: int | None = None, index: int | None = None, steps: int = 40,
                    case=None, overwrite: bool = False, **options):
    """:func:`plbar.visuals.render` of the response :func:`response_of` picks from ``source``.

    ``out`` is claimed for ``render`` as :func:`write_response_data` claims its folder (``case``: the run's case).
    """
    from ..visuals.render import render

    require("pyvista", "rendering")
    require("PIL", "rendering")
    data = response_of(source, branch, index, steps)
    claim = claim_folder(out, "render", _owner(case if case is not None else getattr(source, "case", None), data),
                         RENDER_OWNED, overwrite, joins=("run",))
    with claim:
        clear_owned(out, RENDER_OWNED)
        return render(data, Path(out), **options)
