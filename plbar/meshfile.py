"""1D line meshes on disk (any format meshio reads) and the shipped ``meshes/``.

A mesh file holds the vertices of the bar along ``x`` (the first coordinate)
and line cells (``line`` or ``line3``; only the end vertices are used).  The
cells must form one unbranched, connected chain starting at ``x = 0``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .bar import graded_nodes, uniform_nodes
from .errors import InputError

__all__ = ["read_nodes", "write_nodes", "SHIPPED", "write_shipped"]

#: the meshes shipped in ``meshes/``: file name -> vertex coordinates
SHIPPED = {
    "bar_uniform_8.msh": lambda: uniform_nodes(8),
    "bar_uniform_32.msh": lambda: uniform_nodes(32),
    "bar_graded_16.msh": lambda: graded_nodes(16, ratio=0.25),
}


def read_nodes(path) -> np.ndarray:
    """Sorted vertex coordinates of a 1D line mesh file.

    Raises
    ------
    InputError
        If the file cannot be read, has no line cells, or its lines branch,
        are disconnected, or do not start at ``x = 0``.
    """
    import meshio

    path = Path(path)
    if not path.is_file():
        raise InputError(f"mesh file {str(path)!r} does not exist")
    try:
        m = meshio.read(path)
    except Exception as exc:  # meshio raises many types
        raise InputError(f"mesh file {str(path)!r} cannot be read by meshio: {exc}") from None
    lines = [c.data[:, [0, -1]] if c.type == "line3" else c.data for c in m.cells if c.type in ("line", "line3")]
    if not lines:
        raise InputError(f"mesh file {str(path)!r} has no line cells (found: "
                         f"{', '.join(c.type for c in m.cells) or 'none'})")
    e = np.concatenate(lines).astype(int)
    x = np.asarray(m.points, float)[:, 0]
    used = np.unique(e)
    deg = np.bincount(e.ravel(), minlength=x.size)[used]
    if np.any(deg > 2):
        j = used[int(np.argmax(deg))]
        raise InputError(f"mesh file {str(path)!r} is branched: node at x = {x[j]:g} joins {deg.max()} lines")
    if np.count_nonzero(deg == 1) != 2 or e.shape[0] != used.size - 1:
        raise InputError(f"mesh file {str(path)!r} is disconnected: its lines do not form one chain")
    xs = np.sort(x[used])
    if np.any(np.diff(xs) <= 0):
        raise InputError(f"mesh file {str(path)!r} has duplicate node positions")
    order = {int(v): k for k, v in enumerate(used[np.argsort(x[used])])}
    if not all(abs(order[int(a)] - order[int(b)]) == 1 for a, b in e):
        raise InputError(f"mesh file {str(path)!r}: lines must join neighbouring nodes along x")
    if xs[0] != 0.0:
        raise InputError(f"mesh file {str(path)!r} must start at the clamp x = 0, starts at x = {xs[0]:g}")
    return xs


def write_nodes(path, nodes) -> None:
    """Write vertices as a gmsh 2.2 ASCII line mesh (reproducible text)."""
    import meshio

    x = np.asarray(nodes, float)
    pts = np.c_[x, np.zeros_like(x), np.zeros_like(x)]
    cells = [("line", np.c_[np.arange(x.size - 1), np.arange(1, x.size)])]
    tags = {"gmsh:physical": [np.ones(x.size - 1, int)], "gmsh:geometrical": [np.ones(x.size - 1, int)]}
    meshio.write(str(path), meshio.Mesh(pts, cells, cell_data=tags), file_format="gmsh22", binary=False)


def write_shipped(folder) -> list[Path]:
    """Regenerate the shipped meshes into ``folder`` (``plbar mesh``)."""
    from .io import atomic_path

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for name, make in SHIPPED.items():
        with atomic_path(folder / name) as tmp:
            write_nodes(tmp, make())
        out.append(folder / name)
    return out
