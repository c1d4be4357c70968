"""1D line meshes on disk (any format meshio reads) and the shipped ``meshes/``.

A mesh file holds the vertices of the bar along ``x`` (the first coordinate)
and line cells (``line`` or ``line3``; only the end vertices are used).  The
cells must form one unbranched, connected chain starting at ``x = 0``.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..model.bar import graded_nodes, uniform_nodes
from ..errors import InputError

__all__ = ["read_nodes", "write_nodes", "SHIPPED", "write_shipped"]

#: the meshes shipped in ``meshes/``: file name -> vertex coordinates
SHIPPED = {
    "bar_uniform_8.msh": lambda: uniform_nodes(8),
    "bar_uniform_32.msh": lambda: uniform_nodes(32),
    "bar_graded_16.msh": lambda: graded_nodes(16, ratio=0.25),
}


def _read(path: Path):
    """``meshio.read`` with its chatter captured and its ``sys.exit`` turned into an :class:`InputError`."""
    import contextlib
    import io

    import meshio

    buf = io.StringIO()
    try:
        with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
            return meshio.read(path)
    except (Exception, SystemExit) as exc:  # meshio raises many types, and exits on unknown content
        why = " ".join(str(exc).split()) if not isinstance(exc, SystemExit) else ""
        why = why or " ".join(buf.getvalue().split()) or type(exc).__name__
        raise InputError(f"mesh file {str(path)!r} cannot be read by meshio: {why}") from None


def read_nodes(path) -> np.ndarray:
    """Sorted vertex coordinates of a 1D line mesh file.

    Raises
    ------
    InputError
        If the file cannot be read, has no line cells, has non-finite or
        duplicate vertices, is not straight along ``x``, or its lines branch,
        close a loop, are disconnected, or do not start at ``x = 0``.
    """
    if isinstance(path, (bytes, bool)) or not isinstance(path, (str, os.PathLike)):
        raise InputError(f"mesh file = {path!r} must be a path (a string)")
    path = Path(path)
    name = repr(str(path))
    if not path.is_file():
        raise InputError(f"mesh file {name} does not exist" + (" (it is a folder)" if path.is_dir() else ""))
    m = _read(path)
    lines = [c.data[:, [0, -1]] if c.type == "line3" else c.data for c in m.cells if c.type in ("line", "line3")]
    if not lines or sum(len(c) for c in lines) == 0:
        raise InputError(f"mesh file {name} has no line cells (found: "
                         f"{', '.join(c.type for c in m.cells) or 'none'}); a bar needs line or line3 cells")
    e = np.concatenate(lines).astype(int)
    pts = np.asarray(m.points, float).reshape(len(m.points), -1)
    if e.min() < 0 or e.max() >= len(pts):
        bad = int(e.max() if e.max() >= len(pts) else e.min())
        raise InputError(f"mesh file {name}: a line cell refers to vertex {bad}"
                         f", but the file has vertices 0..{len(pts) - 1}")
    used = np.unique(e)
    if not np.all(np.isfinite(pts[used])):
        j = used[int(np.flatnonzero(~np.all(np.isfinite(pts[used]), axis=1))[0])]
        raise InputError(f"mesh file {name}: vertex {int(j)} at {pts[j].tolist()} is not finite")
    return _chain_positions(name, e, pts, used)


def _chain_positions(name: str, e: np.ndarray, pts: np.ndarray, used: np.ndarray) -> np.ndarray:
    """Sorted vertex positions of the line cells ``e``, if they form one straight chain from ``x = 0``."""
    x = pts[:, 0]
    self_loop = e[:, 0] == e[:, 1]
    if np.any(self_loop):
        k = int(np.flatnonzero(self_loop)[0])
        raise InputError(f"mesh file {name}: line cell {k} joins the vertex at x = {x[e[k, 0]]:g} to itself")
    if pts.shape[1] > 1:
        span = max(float(np.ptp(x[used])), 1e-300)
        off = np.abs(pts[used, 1:]).max(axis=1)
        if off.max() > 1e-9 * span:
            j = used[int(np.argmax(off))]
            raise InputError(f"mesh file {name} is not a straight bar along x: vertex at {pts[j].tolist()} is off "
                             "the x axis (y and z must be 0)")
    deg = np.bincount(e.ravel(), minlength=x.size)[used]
    if np.any(deg > 2):
        j = used[int(np.argmax(deg))]
        raise InputError(f"mesh file {name} is branched: the vertex at x = {x[j]:g} joins {deg.max()} lines; "
                         "a bar is one unbranched chain of lines")
    ends = int(np.count_nonzero(deg == 1))
    if ends == 0:
        raise InputError(f"mesh file {name}: its lines close a loop; a bar is an open chain of lines from x = 0 to L")
    if ends != 2 or e.shape[0] != used.size - 1:
        raise InputError(f"mesh file {name} is disconnected: its {e.shape[0]} lines over {used.size} vertices do "
                         "not form one chain; a bar is one connected chain of lines")
    xs = np.sort(x[used])
    if np.any(np.diff(xs) <= 0):
        j = int(np.flatnonzero(np.diff(xs) <= 0)[0])
        raise InputError(f"mesh file {name} has two vertices at x = {xs[j]:g}; vertex positions must be distinct")
    order = {int(v): k for k, v in enumerate(used[np.argsort(x[used])])}
    for a, b in e:
        if abs(order[int(a)] - order[int(b)]) != 1:
            raise InputError(f"mesh file {name}: the line from x = {x[a]:g} to x = {x[b]:g} skips vertices; "
                             "lines must join neighbouring vertices along x")
    if xs[0] != 0.0:
        raise InputError(f"mesh file {name} must start at the clamp x = 0, starts at x = {xs[0]:g}")
    return xs


def write_nodes(path, nodes) -> None:
    """Write vertices as a gmsh 2.2 ASCII line mesh (reproducible text)."""
    import meshio

    x = np.asarray(nodes, float)
    pts = np.c_[x, np.zeros_like(x), np.zeros_like(x)]
    cells = [("line", np.c_[np.arange(x.size - 1), np.arange(1, x.size)])]
    tags = {"gmsh:physical": [np.ones(x.size - 1, int)], "gmsh:geometrical": [np.ones(x.size - 1, int)]}
    meshio.write(str(path), meshio.Mesh(pts, cells, cell_data=tags), file_format="gmsh22", binary=False)


def write_shipped(folder, names=None) -> list[Path]:
    """Regenerate the shipped meshes (or those of them in ``names``) into ``folder`` (``plbar mesh``)."""
    from ..util.files import atomic_path

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for name, make in SHIPPED.items():
        if names is not None and name not in names:
            continue
        with atomic_path(folder / name) as tmp:
            write_nodes(tmp, make())
        out.append(folder / name)
    return out
