"""ParaView output: one periodic response, or a simulated motion, as a time series on the bar mesh.

The bar is written as line cells along ``x`` (quadratic ``line3`` cells with
their midside nodes for P2), the clamped node ``x = 0`` included with zero
displacement.  Every step holds

point data
    ``displacement`` (axial ``u``), ``displacement_vec`` ``(u, 0, 0)`` for
    *Warp By Vector*, ``velocity``, ``velocity_vec``,
    ``kinetic_energy_density``, ``potential_energy_density``,
    ``kinetic_energy_nodal`` and ``stress_nodal`` (see below);
cell data
    ``strain``, ``stress`` (the axial force ``EA * strain``) and
    ``strain_energy`` (the element's exact share of the potential energy);
field data (``.vtu`` only; also in ``<name>_steps.csv``)
    ``time``, ``phase_time`` (time within the period), ``state`` (1 stuck,
    2 free), ``contact_reaction`` (``-R >= 0``, the force the wall pushes
    with, Eq. (4); zero in state II), ``gap`` (the opening ``d - u >= 0`` of the contact coordinate ``u``:
    ``-x_c`` at ``d = 0``; zero in state I),
    ``kinetic_energy``, ``potential_energy`` (Eqs. (12)-(13)),
    ``T1``, ``T2``, ``phi``, ``T``; a simulated motion (:func:`plbar.io.motion_data`)
    adds ``event`` (0 a regular sample, 1 the gap opens, 2 an impact, 3 an
    impact and the opening at once: a step just after each event, at its
    time) and ``impact_loss`` (Eq. (14) at an
    impact step), and its ``T`` is the length of the window written (its
    times run from 0 at the window's start; ``time`` is absolute).
XDMF (``.xdmf`` + ``.h5``)
    The same point and cell data.  meshio's XDMF time series has no field
    data, so the per-step scalars ``phase_time``, ``state``,
    ``contact_reaction``, ``gap``, ``kinetic_energy`` and ``potential_energy``
    (and a motion's ``event``, ``impact_loss``) are written as point data
    constant over the mesh (same names, same values as the ``.vtu`` field data
    and ``<name>_steps.csv``); the time is the XDMF step time.

The displacements and velocities are those of :meth:`Orbits.response` (or of
the simulator's recorded window, :func:`plbar.motion.motion_series`), so the
file holds exactly the solver's response.

Definitions of the derived fields
---------------------------------
* The strain on an element is ``du/dx`` of its interpolant.  P1: constant.
  P2: the cell value is the strain at the element midpoint, which for a
  linear strain field is also its element average.
* ``stress_nodal`` is ``EA du/dx`` at the points, from the element end strains
  that the energy densities use (P2 also at the midside node, where it is the
  cell ``stress``): at a vertex shared by two elements the two end stresses are
  averaged (P1: the mean of the two adjacent cell ``stress`` values).  It shows
  the linear stress variation inside P2 elements that the one cell value hides.
* ``strain_energy`` of an element is ``1/2 int EA (du/dx)^2 dx`` exactly
  (P1: ``1/2 EA h eps^2``; P2: ``EA h (e0^2 + e0 e1 + e1^2) / 6`` with the end
  strains ``e0, e1``).  The element values sum to the total potential energy.
* ``kinetic_energy_density = 1/2 rhoA v^2`` is the continuum density per unit
  length at the node.  ``potential_energy_density = 1/2 EA eps^2`` at the node,
  ``eps`` being the one-sided strain of each adjacent element there; at a
  vertex shared by two elements the two element densities are averaged.
  Point masses carry kinetic energy that has no density; the totals in the
  field data include them.
* ``kinetic_energy_nodal = 1/2 v_i (M v)_i`` is each node's share of the
  kinetic energy (Eq. (12)): the point values sum to the total for any mass
  matrix (consistent or lumped, point masses, the chain).  With the cell
  ``strain_energy`` the energy fields integrate to the mechanical energy.
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

from ..errors import InputError, PlbarError
from ..util.files import atomic_path, write_csv, write_json, write_text
from ..util.reprs import build
from .sampling import FIELD_KEYS, ResponseData

__all__ = ["ResponseFiles", "write_data", "write_xi_along_mesh", "load_pvd", "FORMATS"]

FORMATS = ("pvd", "xdmf", "both")


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

    def __repr__(self) -> str:
        names = [p.name for p in (self.pvd, self.xdmf, self.h5, self.steps_csv, self.info_json) if p is not None]
        return build("ResponseFiles", {"folder": str(self.folder), "files": names, "vtus": len(self.vtus),
                                       "T": self.info.get("T"), "xi": self.info.get("xi")})


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
                    n = data.points.size    # per-step scalars: constant point data (XDMF has no field data)
                    pd.update({nm: np.full(n, data.field_data[nm][k]) for nm in data.field_data
                               if nm != "time"})
                    cd = {nm: [np.ascontiguousarray(a[k])] for nm, a in data.cell_data.items()}
                    w.write_data(float(data.times[k]), point_data=pd, cell_data=cd)
        h5, xdmf = folder / f"{name}.h5", folder / f"{name}.xdmf"
        os.replace(tmpdir / f"{name}.h5", h5)     # data first: the .xdmf never points at a missing file
        os.replace(tmpdir / f"{name}.xdmf", xdmf)
        return xdmf, h5
    finally:
        shutil.rmtree(tmpdir, ignore_errors=True)


def write_data(data: ResponseData, folder, *, format: str = "pvd", name: str = "response") -> ResponseFiles:
    """Write a :class:`~plbar.io.sampling.ResponseData` for ParaView.

    Parameters
    ----------
    data : ResponseData
    folder : path
        Output folder (created).  Every file is written atomically.
    format : {"pvd", "xdmf", "both"}
        ``pvd``: one ``<name>_NNNN.vtu`` per step and ``<name>.pvd``;
        ``xdmf``: ``<name>.xdmf`` + ``<name>.h5`` (point and cell data; the
        per-step scalars ``state``, ``contact_reaction``, ``gap``, ... as
        point data constant over the mesh).
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
    keys = list(FIELD_KEYS) + [k for k in data.field_data if k not in FIELD_KEYS]     # + a motion's event marks
    csv = write_csv(folder / f"{name}_steps.csv", ["step"] + keys,
                    [np.arange(data.n_steps)] + [data.field_data[k] for k in keys],
                    ["%d"] + ["%d" if np.asarray(data.field_data[k]).dtype.kind in "iu" else "%.17g" for k in keys])
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


def load_pvd(path):
    """Read a ``.pvd`` written by :func:`write_data` back as :class:`~plbar.io.sampling.ResponseData`."""
    import pyvista as pv

    path = Path(path)
    rd = pv.PVDReader(str(path))
    times = np.asarray(rd.time_values, float)
    pd, cd, fd = {}, {}, {}
    mesh = None
    for k in range(times.size):
        rd.set_active_time_point(k)
        mesh = rd.read()[0]
        for store, src in ((pd, mesh.point_data), (cd, mesh.cell_data), (fd, mesh.field_data)):
            for nm in src.keys():
                store.setdefault(nm, []).append(np.asarray(src[nm]).copy())
    if mesh is None:
        raise InputError(f"{str(path)!r} holds no time step")
    ctype = "line" if int(mesh.celltypes[0]) == pv.CellType.LINE else "line3"
    cells = np.asarray(mesh.cells_dict[int(mesh.celltypes[0])])
    fd = {k: np.concatenate(v) for k, v in fd.items()}
    info = {nm: float(fd[nm][0]) for nm in ("T1", "T2", "phi", "T") if nm in fd}
    return ResponseData(np.asarray(mesh.points)[:, 0].copy(), cells, ctype, times,
                        {k: np.stack(v) for k, v in pd.items()}, {k: np.stack(v) for k, v in cd.items()}, fd, info)
