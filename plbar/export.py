"""ParaView output: one periodic response as a time series on the bar mesh.

The bar is written as line cells along ``x`` (quadratic ``line3`` cells with
their midside nodes for P2), the clamped node ``x = 0`` included with zero
displacement.  Every step holds

point data
    ``displacement`` (axial ``u``), ``displacement_vec`` ``(u, 0, 0)`` for
    *Warp By Vector*, ``velocity``, ``velocity_vec``,
    ``kinetic_energy_density`` and ``potential_energy_density`` (see below);
cell data
    ``strain``, ``stress`` (the axial force ``EA * strain``) and
    ``strain_energy`` (the element's exact share of the potential energy);
field data (``.vtu`` only; also in ``<name>_steps.csv``)
    ``time``, ``phase_time`` (time within the period), ``state`` (1 stuck,
    2 free), ``contact_reaction`` (``-R >= 0``, the force the wall pushes
    with, Eq. (4); zero in state II), ``gap`` (``-x_c >= 0``, zero in state I),
    ``kinetic_energy``, ``potential_energy`` (Eqs. (12)-(13)),
    ``T1``, ``T2``, ``phi``, ``T``.

The displacements and velocities are those of :meth:`Orbits.response`, so the
file holds exactly the solver's response.

Definitions of the derived fields
---------------------------------
* The strain on an element is ``du/dx`` of its interpolant.  P1: constant.
  P2: the cell value is the strain at the element midpoint, which for a
  linear strain field is also its element average.
* ``strain_energy`` of an element is ``1/2 int EA (du/dx)^2 dx`` exactly
  (P1: ``1/2 EA h eps^2``; P2: ``EA h (e0^2 + e0 e1 + e1^2) / 6`` with the end
  strains ``e0, e1``).  The element values sum to the total potential energy.
* ``kinetic_energy_density = 1/2 rhoA v^2`` is the continuum density per unit
  length at the node.  ``potential_energy_density = 1/2 EA eps^2`` at the node,
  ``eps`` being the one-sided strain of each adjacent element there; at a
  vertex shared by two elements the two element densities are averaged.
  Point masses carry kinetic energy that has no density; the totals in the
  field data include them.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from .errors import InputError, PlbarError
from .io import atomic_path, write_csv, write_json, write_text

__all__ = ["ResponseData", "ResponseFiles", "response_data", "select", "from_run", "write_response", "write_data",
           "write_xi_along_mesh", "FORMATS"]

FORMATS = ("pvd", "xdmf", "both")

FIELD_KEYS = ("time", "phase_time", "state", "contact_reaction", "gap", "kinetic_energy", "potential_energy")


@dataclass(frozen=True)
class ResponseData:
    """One periodic response sampled on the bar mesh.

    Attributes
    ----------
    points : ndarray, shape (n_points,)
        Node coordinates sorted along ``x`` (clamp first).
    cells : ndarray of int, shape (n_cells, 2) or (n_cells, 3)
        ``line`` cells, or ``line3`` cells ``(end, end, midside)``.
    cell_type : {"line", "line3"}
    times : ndarray, shape (K,)
        Absolute times ``k T / steps``.
    point_data : dict of name -> ndarray (K, n_points)
    cell_data : dict of name -> ndarray (K, n_cells)
    field_data : dict of name -> ndarray (K,)
    info : dict
        The orbit: ``T1, T2, phi, T`` and, where known, ``branch, index, xi, dPL``.
    """

    points: np.ndarray
    cells: np.ndarray
    cell_type: str
    times: np.ndarray
    point_data: dict
    cell_data: dict
    field_data: dict
    info: dict

    @property
    def n_steps(self) -> int:
        return self.times.size

    def points3(self) -> np.ndarray:
        """Points as ``(n_points, 3)`` with ``y = z = 0``."""
        return np.c_[self.points, np.zeros((self.points.size, 2))]


@dataclass(frozen=True)
class ResponseFiles:
    """What :func:`write_response` wrote."""

    folder: Path
    pvd: Path | None
    vtus: tuple[Path, ...]
    xdmf: Path | None
    h5: Path | None
    steps_csv: Path
    info_json: Path
    info: dict


# ----------------------------------------------------------------------------- selection

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
    from .energy import damping
    from .orbit import Orbits

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
        if isinstance(source, tuple) and len(source) == 2:
            prob, orb = source
            if orb.prob is not prob:
                orb = Orbits(prob, *(getattr(orb, f) for f in ("T1", "T2", "phi", "eta0", "v0", "eta_s", "v_s")))
        elif isinstance(source, Orbits):
            orb = source
        else:
            raise InputError(f"cannot export a {type(source).__name__}; give a Result, Paths, Orbits "
                             "or (Problem, Orbits)")
        if branch is not None:
            raise InputError("branch = ... needs a Result or Paths; an Orbits has no branches")
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
    import json

    from .case import Case
    from .energy import damping
    from .orbit import orbits

    folder = Path(folder)
    sfile, cfile = folder / "summary.json", folder / "paths.csv"
    for f in (sfile, cfile):
        if not f.is_file():
            raise InputError(f"{str(f)!r} does not exist; give the --out folder of a previous 'plbar run'")
    try:
        case = Case(**_tuples(json.loads(sfile.read_text())["case"]))
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{str(sfile)!r} does not hold a valid case: {exc}") from None
    rows = np.loadtxt(cfile, delimiter=",", skiprows=1, ndmin=2)
    if rows.size == 0:
        raise InputError(f"{str(cfile)!r} has no periodic path; nothing to export")
    bcol, xicol = rows[:, 0].astype(int), rows[:, 6]
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
    r = rows[sel[int(index) % sel.size]]
    orb = orbits(case.problem(), r[1], r[2], r[3])
    d = damping(orb)
    info = {"T1": float(r[1]), "T2": float(r[2]), "phi": float(r[3]), "T": float(orb.T[0]),
            "xi": float(d.xi[0]), "dPL": float(d.dPL[0]), "branch": int(branch), "index": int(index) % sel.size}
    return case, orb, info


def _tuples(o):
    if isinstance(o, dict):
        return {k: _tuples(v) for k, v in o.items()}
    if isinstance(o, list):
        return tuple(_tuples(v) for v in o)
    return o


# ----------------------------------------------------------------------------- sampling

def _mesh(prob):
    """Sorted points, cells, cell type and per-cell EA, rhoA of ``prob``'s bar."""
    bar, asm = prob.bar, prob.asm
    if bar is None or asm is None:
        raise InputError("export needs a Problem built from a Bar (plbar.problem or Case.problem)")
    xd = np.asarray(asm.basis.doflocs[0], float)
    pts = np.sort(xd)
    if pts[0] != 0.0 or pts.size != asm.n + 1 or not np.array_equal(pts[1:], asm.x):
        raise PlbarError("the bar's DOF positions do not match its free DOFs; cannot map the response")
    ne = bar.n_elements
    if bar.element == "P1":
        cells, ctype = np.c_[np.arange(ne), np.arange(1, ne + 1)], "line"
    else:
        i = np.arange(ne)
        cells, ctype = np.c_[2 * i, 2 * i + 2, 2 * i + 1], "line3"
    EA = np.broadcast_to(np.asarray(bar.EA, float), (ne,))
    rA = np.broadcast_to(np.asarray(bar.rhoA, float), (ne,))
    return pts, cells, ctype, EA, rA


def _strains(u, pts, cells, ctype):
    """Strains at each element's start, middle and end: each (K, n_cells)."""
    a, b = cells[:, 0], cells[:, 1]
    h = pts[b] - pts[a]
    if ctype == "line":
        e = (u[:, b] - u[:, a]) / h
        return e, e, e
    m = cells[:, 2]
    u0, u1, um = u[:, a], u[:, b], u[:, m]
    return (-3 * u0 - u1 + 4 * um) / h, (u1 - u0) / h, (u0 + 3 * u1 - 4 * um) / h


def _node_average(values_at, cells, n_points, K):
    """Average per-element values given at element nodes onto the points."""
    acc = np.zeros((K, n_points))
    cnt = np.zeros(n_points)
    for col, val in values_at:
        np.add.at(acc.T, cells[:, col], val.T)
        np.add.at(cnt, cells[:, col], 1.0)
    return acc / cnt


def response_data(orbit, info: dict | None = None, periods: int = 1, steps: int = 40) -> ResponseData:
    """Sample a single periodic response on its bar mesh (no files).

    Parameters
    ----------
    orbit : Orbits
        One orbit (its first is used); ``orbit.prob`` must come from a Bar.
    info : dict, optional
        Extra orbit information kept in :attr:`ResponseData.info`.
    periods : {1, 2}
        Periods to sample.
    steps : int
        Steps per period (>= 4); times ``k T / steps``, ``k = 0 .. periods*steps - 1``.
    """
    if periods not in (1, 2) or isinstance(periods, bool):
        raise InputError(f"periods = {periods!r} is not allowed; choose 1 or 2")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 4:
        raise InputError(f"steps = {steps!r} must be an integer >= 4 (steps per period)")
    orb = orbit.take([0])
    prob = orb.prob
    pts, cells, ctype, EA, rA = _mesh(prob)
    T = float(orb.T[0])
    k = np.arange(periods * steps)
    t_abs = k * T / steps
    t_loc = (k % steps) * T / steps
    x, v, state = orb.response(t_loc[None, :])
    x, v, state = x[0], v[0], state[0]
    K = t_loc.size
    u = np.concatenate([np.zeros((K, 1)), x], axis=1)
    vel = np.concatenate([np.zeros((K, 1)), v], axis=1)
    e0, em, e1 = _strains(u, pts, cells, ctype)
    h = pts[cells[:, 1]] - pts[cells[:, 0]]
    if ctype == "line":
        sen = 0.5 * EA * h * em ** 2
    else:
        sen = EA * h * (e0 ** 2 + e0 * e1 + e1 ** 2) / 6.0
    pe_at = [(0, 0.5 * EA * e0 ** 2), (1, 0.5 * EA * e1 ** 2)]
    rho_at = [(0, rA[None, :]), (1, rA[None, :])]
    if ctype == "line3":
        pe_at.append((2, 0.5 * EA * em ** 2))
        rho_at.append((2, rA[None, :]))
    ped = _node_average(pe_at, cells, pts.size, K)
    rho_pt = _node_average(rho_at, cells, pts.size, 1)[0]
    ked = 0.5 * rho_pt * vel ** 2
    tau1 = np.minimum(t_loc, orb.T1[0])[None, :]
    margin = orb.reaction_margin(tau1)[0]
    inI = state == 1
    zero = np.zeros(K)
    ek, ep = orb.energies(t_loc[None, :])
    field = {
        "time": t_abs, "phase_time": t_loc, "state": state.astype(np.int32),
        "contact_reaction": np.where(inI, margin, zero), "gap": np.where(inI, zero, -u[:, -1]),
        "kinetic_energy": ek[0], "potential_energy": ep[0],
    }
    zeros2 = np.zeros_like(u)
    point = {
        "displacement": u, "displacement_vec": np.stack([u, zeros2, zeros2], axis=-1),
        "velocity": vel, "velocity_vec": np.stack([vel, zeros2, zeros2], axis=-1),
        "kinetic_energy_density": ked, "potential_energy_density": ped,
    }
    cell = {"strain": em, "stress": EA * em, "strain_energy": sen}
    full = {"T1": float(orb.T1[0]), "T2": float(orb.T2[0]), "phi": float(np.mod(orb.phi[0], 2 * np.pi)), "T": T}
    full.update(info or {})
    full.update({"periods": periods, "steps": steps, "cell_type": ctype})
    return ResponseData(pts, cells, ctype, t_abs, point, cell, field, full)


# ----------------------------------------------------------------------------- writers

def _vtk_grid(points3, cells, ctype):
    import pyvista as pv

    ct = pv.CellType.LINE if ctype == "line" else pv.CellType.QUADRATIC_EDGE
    return pv.UnstructuredGrid({ct: np.asarray(cells, dtype=np.int64)}, points3)


def _write_vtk(path: Path, grid) -> None:
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    with atomic_path(path) as tmp:
        w = vtkXMLUnstructuredGridWriter()
        w.SetFileName(str(tmp))
        w.SetInputData(grid)
        w.SetDataModeToBinary()
        if not w.Write():
            raise PlbarError(f"VTK could not write {str(path)!r}")


def _step_grid(data: ResponseData, k: int, base=None):
    g = (base or _vtk_grid(data.points3(), data.cells, data.cell_type)).copy()
    for nm, arr in data.point_data.items():
        g.point_data[nm] = np.ascontiguousarray(arr[k])
    for nm, arr in data.cell_data.items():
        g.cell_data[nm] = np.ascontiguousarray(arr[k])
    for nm, arr in data.field_data.items():
        g.field_data[nm] = np.atleast_1d(arr[k])
    for nm in ("T1", "T2", "phi", "T"):
        g.field_data[nm] = np.atleast_1d(float(data.info[nm]))
    return g


def _pvd_text(entries) -> str:
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    for t, fname in entries:
        lines.append(f'    <DataSet timestep="{t!r}" group="" part="0" file={quoteattr(fname)}/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    return "\n".join(lines)


@contextlib.contextmanager
def _chdir(path):
    old = os.getcwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(old)


def _write_xdmf(data: ResponseData, folder: Path, name: str) -> tuple[Path, Path]:
    """XDMF + HDF5 time series with meshio, written in a private temp folder, then renamed.

    meshio's TimeSeriesWriter puts the ``.h5`` in the current directory
    (meshio issue #1442), so the writer runs with the temp folder as cwd.
    Not thread-safe (``os.chdir``).
    """
    import meshio

    tmpdir = Path(tempfile.mkdtemp(prefix=f".{name}.", suffix=".part", dir=folder))
    try:
        with _chdir(tmpdir):
            with meshio.xdmf.TimeSeriesWriter(f"{name}.xdmf", data_format="HDF") as w:
                w.write_points_cells(data.points3(), [(data.cell_type, data.cells)])
                for k in range(data.n_steps):
                    pd = {nm: np.ascontiguousarray(a[k]) for nm, a in data.point_data.items()}
                    cd = {nm: [np.ascontiguousarray(a[k])] for nm, a in data.cell_data.items()}
                    w.write_data(float(data.times[k]), point_data=pd, cell_data=cd)
        h5, xdmf = folder / f"{name}.h5", folder / f"{name}.xdmf"
        os.replace(tmpdir / f"{name}.h5", h5)     # data first: the .xdmf never points at a missing file
        os.replace(tmpdir / f"{name}.xdmf", xdmf)
        return xdmf, h5
    finally:
        shutil.rmtree(tmpdir, ignore_errors=True)


def write_response(source, folder, *, branch: int | None = None, index: int | None = None, periods: int = 1,
                   steps: int = 40, format: str = "pvd", name: str = "response") -> ResponseFiles:
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
    format : {"pvd", "xdmf", "both"}
        ``pvd``: one ``<name>_NNNN.vtu`` per step and ``<name>.pvd``;
        ``xdmf``: ``<name>.xdmf`` + ``<name>.h5`` (point and cell data; the
        per-step scalars are in ``<name>_steps.csv``).
    name : str
        File name stem.

    Returns
    -------
    ResponseFiles
        Also always written: ``<name>_steps.csv`` (time, state, reaction,
        gap, energies per step) and ``<name>.json`` (the orbit).
    """
    if format not in FORMATS:
        raise InputError(f"format = {format!r} is not allowed; choose one of {', '.join(FORMATS)}")
    orb, info = select(source, branch, index)
    data = response_data(orb, info, periods, steps)
    return write_data(data, folder, format=format, name=name)


def write_data(data: ResponseData, folder, *, format: str = "pvd", name: str = "response") -> ResponseFiles:
    """Write a :class:`ResponseData` (see :func:`write_response`)."""
    if format not in FORMATS:
        raise InputError(f"format = {format!r} is not allowed; choose one of {', '.join(FORMATS)}")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    pvd = xdmf = h5 = None
    vtus = []
    if format in ("pvd", "both"):
        base = _vtk_grid(data.points3(), data.cells, data.cell_type)
        entries = []
        for k in range(data.n_steps):
            f = folder / f"{name}_{k:04d}.vtu"
            _write_vtk(f, _step_grid(data, k, base))
            vtus.append(f)
            entries.append((float(data.times[k]), f.name))
        pvd = write_text(folder / f"{name}.pvd", _pvd_text(entries))
        keep = {f.name for f in vtus}
        for old in folder.glob(f"{name}_[0-9][0-9][0-9][0-9].vtu"):   # steps of an earlier, longer export
            if old.name not in keep:
                old.unlink()
    if format in ("xdmf", "both"):
        xdmf, h5 = _write_xdmf(data, folder, name)
    keys = list(FIELD_KEYS)
    csv = write_csv(folder / f"{name}_steps.csv", ["step"] + keys,
                    [np.arange(data.n_steps)] + [data.field_data[k] for k in keys],
                    ["%d"] + ["%.17g", "%.17g", "%d"] + ["%.17g"] * (len(keys) - 3))
    js = write_json(folder / f"{name}.json", dict(data.info, n_points=int(data.points.size),
                                                  n_cells=int(data.cells.shape[0])))
    return ResponseFiles(folder, pvd, tuple(vtus), xdmf, h5, csv, js, dict(data.info))


def write_xi_along_mesh(bar, positions, fields: dict, path) -> Path:
    """A ``.vtu`` of the bar with given values at given nodes.

    Meant for "``xi_eq`` when the load acts at this node" plots (maximum
    ``xi_eq``, per branch family, ``Delta_PL``, ...): the numbers come from
    the caller.

    Parameters
    ----------
    bar : Bar or array_like
        The bar (its vertices) or node coordinates.
    positions : array_like, shape (m,)
        Positions of the values (vertices, or any points on ``[0, L]``; a
        position that is not a vertex becomes an extra mesh point).
    fields : dict of str -> array_like, shape (m,)
        Point data; nodes without a value get 0 and ``has_value = 0`` (no
        ``nan`` is written).
    path : path
        The ``.vtu`` file (written atomically).
    """
    nodes = np.asarray(getattr(bar, "nodes", bar), float)
    pos = np.atleast_1d(np.asarray(positions, float))
    if nodes.ndim != 1 or nodes.size < 2:
        raise InputError("write_xi_along_mesh needs a Bar or at least two node coordinates")
    if pos.ndim != 1 or not np.all(np.isfinite(pos)):
        raise InputError("positions must be a 1D array of finite values")
    L = float(nodes[-1])
    if np.any((pos < nodes[0] - 1e-12 * L) | (pos > L * (1 + 1e-12))):
        raise InputError(f"positions must lie on the bar [0, {L:g}]")
    tol = 1e-10 * L
    extra = pos[np.min(np.abs(pos[:, None] - nodes[None, :]), axis=1) > tol]
    pts = np.unique(np.concatenate([nodes, extra]))
    pts = pts[np.concatenate([[True], np.diff(pts) > tol])]
    where = np.argmin(np.abs(pts[:, None] - pos[None, :]), axis=0)
    if np.unique(where).size != where.size:
        raise InputError("positions must be distinct")
    grid = _vtk_grid(np.c_[pts, np.zeros((pts.size, 2))],
                     np.c_[np.arange(pts.size - 1), np.arange(1, pts.size)], "line")
    has = np.zeros(pts.size, np.int32)
    has[where] = 1
    grid.point_data["has_value"] = has
    for nm, vals in fields.items():
        vals = np.asarray(vals, float)
        if vals.shape != pos.shape:
            raise InputError(f"field {nm!r} has shape {vals.shape}; it needs one value per position {pos.shape}")
        if not np.all(np.isfinite(vals)):
            raise InputError(f"field {nm!r} has non-finite values; give finite numbers")
        arr = np.zeros(pts.size)     # nodes without a value: 0 with has_value = 0 (never nan)
        arr[where] = vals
        grid.point_data[str(nm)] = arr
    path = Path(path)
    _write_vtk(path, grid)
    return path
