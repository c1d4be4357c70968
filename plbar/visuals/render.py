"""Off-screen pictures of a periodic response: snapshots, a space-time map, a GIF.

The bar is 1D and its motion axial, so the pictures exaggerate it: the bar is
drawn as a tube whose nodes sit at ``x + s u`` (``s`` chosen so that the
largest displacement is 10 % of ``L``), coloured by a field, between the
clamp block at ``x = 0`` and the wall block at ``x = L``; a thin grey line
below it shows the undeformed nodes, each joined to its displaced position.
The space-time map shows the field over ``x`` (right) and ``t / T`` (up), with
the gap opening ``t = T^I`` marked.

Rendering is headless (pyvista off-screen, EGL where available); the GIF is
written with Pillow.  Every file is written atomically.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io import ResponseData, load_pvd
from ..util.files import atomic_path

__all__ = ["bar_title_position", "RenderFiles", "render"]

SIGNED = ("displacement", "velocity", "strain", "stress")


@dataclass(frozen=True)
class RenderFiles:
    """What :func:`render` wrote."""

    snapshots: tuple[Path, ...]
    montage: Path | None
    spacetime: Path
    gif: Path | None
    field: str
    scale: float


def _field(data, field):
    """Per-frame values ``(K, n)`` and whether they live on points."""
    if field in data.point_data:
        a = np.asarray(data.point_data[field])
        return (a[..., 0] if a.ndim == 3 else a), True
    if field in data.cell_data:
        return np.asarray(data.cell_data[field]), False
    names = sorted(k for k in list(data.point_data) + list(data.cell_data) if not k.endswith("_vec"))
    raise InputError(f"field = {field!r} is not in the response; choose one of {', '.join(names)}")


def _save_png(path: Path, img: np.ndarray) -> Path:
    from PIL import Image

    with atomic_path(path) as tmp:
        Image.fromarray(np.asarray(img, np.uint8)).save(tmp, format="PNG")
    return path


def _save_gif(path: Path, frames, seconds: float) -> Path:
    from PIL import Image

    ims = [Image.fromarray(np.asarray(f, np.uint8)).quantize(colors=255, method=Image.Quantize.FASTOCTREE,
                                                             dither=Image.Dither.NONE) for f in frames]
    with atomic_path(path) as tmp:
        ims[0].save(tmp, format="GIF", save_all=True, append_images=ims[1:],
                    duration=max(20, int(1000 * seconds / len(ims))), loop=0, disposal=2)
    return path


def _clim(vals, signed):
    a = float(np.max(np.abs(vals))) if vals.size else 0.0
    a = a if a > 0 else 1.0
    return ((-a, a), "coolwarm") if signed else ((0.0, a), "viridis")


@dataclass(frozen=True)
class _Scene:
    """What every frame needs: the field, the exaggerated displacements, the period and the frames to draw."""

    data: object
    field: str
    vals: np.ndarray
    on_points: bool
    x: np.ndarray
    u: np.ndarray
    T: float
    t_loc: np.ndarray
    first: np.ndarray
    scale: float
    clim: tuple
    cmap: str
    per_seg: int
    seg_cell: np.ndarray
    state: np.ndarray
    crack: int | None = None      #: a cracked bar's inner face (the outer one is the next point): no segment joins them
    far: str = "wall"             #: what is at x = L: the stop ("wall"), a clamp ("clamp") or nothing ("free")

    @property
    def L(self) -> float:
        return float(self.x[-1])


def _scene(data, field: str, scale) -> _Scene:
    if "deflection" in data.point_data:
        raise InputError("render draws a bar's axial motion; a beam's response is for ParaView: plbar export "
                         "(Warp By Vector with displacement_vec)")
    vals, on_points = _field(data, field)
    x = np.asarray(data.points, float)
    u = np.asarray(data.point_data["displacement"])
    u = u[..., 0] if u.ndim == 3 else u
    T = float(data.info.get("T", data.times[-1] + (data.times[1] - data.times[0])))
    t_loc = np.mod(data.times, T) if "phase_time" not in data.field_data else data.field_data["phase_time"]
    umax = float(np.max(np.abs(u)))
    if scale is None:
        scale = 0.1 * float(x[-1]) / umax if umax > 0 else 1.0
    clim, cmap = _clim(vals, field in SIGNED)
    per_seg = (x.size - 1) // data.cells.shape[0]             # 1 for P1, 2 for P2
    seg_cell, crack, far = np.arange(x.size - 1) // per_seg, None, "wall"
    if np.any(np.diff(x) == 0):                               # a crack's two faces
        per_seg, seg_cell, crack, far = _cracked(data, x)
    return _Scene(data, field, vals, on_points, x, u, T, t_loc, np.flatnonzero(data.times < T * (1 - 1e-12)),
                  float(scale), clim, cmap, per_seg, seg_cell,
                  data.field_data.get("state", np.zeros(data.n_steps, int)), crack, far)


def _cracked(data, x):
    """A cracked bar's ``per_seg, seg_cell, crack, far`` (:class:`_Scene`): each segment between consecutive points
    is in the cell holding both, the crack's (two coincident points) in none; a clamp or nothing at ``x = L``."""
    cells = np.sort(np.asarray(data.cells), axis=1)
    seg_cell = np.zeros(x.size - 1, int)
    for c, cell in enumerate(cells):
        seg_cell[cell[0]:cell[-1]] = c
    far = "clamp" if data.info.get("supports") == "clamped-clamped" else "free"
    return 1 if cells.shape[1] == 2 else 2, seg_cell, int(np.flatnonzero(np.diff(x) == 0)[0]), far


def _geometry(sc: _Scene, k: int, ref: np.ndarray, r: float):
    """The bar at frame ``k``: tube coloured by the field, node dots, and links to the undeformed nodes."""
    import pyvista as pv

    x = sc.x
    verts_idx = np.r_[0:x.size:sc.per_seg]
    pts = np.c_[x + sc.scale * sc.u[k], np.zeros_like(x), np.zeros_like(x)]
    seg = np.arange(x.size - 1) if sc.crack is None else np.delete(np.arange(x.size - 1), sc.crack)
    line = pv.lines_from_points(pts) if sc.crack is None else \
        pv.PolyData(pts, lines=np.c_[np.full(seg.size, 2), seg, seg + 1].ravel())   # no segment across a crack
    if sc.on_points:
        line.point_data[sc.field] = sc.vals[k]
    else:
        line.cell_data[sc.field] = sc.vals[k][sc.seg_cell[seg]]
    conn = np.empty((2 * verts_idx.size, 3))
    conn[0::2] = ref[verts_idx]
    conn[1::2] = pts[verts_idx] + np.array([0.0, -r, 0.0])
    front = pts[verts_idx] + np.array([0.0, 0.0, 1.5 * r])      # node dots in front of the tube
    return line.tube(radius=r, n_sides=24, capping=True), front, conn


def _static(p, sc: _Scene, ref: np.ndarray) -> None:
    """Clamp block, wall block and the undeformed bar (grey line and nodes)."""
    import pyvista as pv

    L = sc.L
    p.set_background("white")
    with _quiet():
        p.enable_anti_aliasing("msaa")
    p.add_mesh(pv.Box((-0.04 * L, 0.0, -0.12 * L, 0.12 * L, -0.05 * L, 0.05 * L)), color="#6b6b6b")
    if sc.far == "wall":                                      # the stop; a far clamp as the one at x = 0
        p.add_mesh(pv.Box((L, L + 0.03 * L, -0.12 * L, 0.12 * L, -0.05 * L, 0.05 * L)), color="#3a3a3a")
    elif sc.far == "clamp":
        p.add_mesh(pv.Box((L, L + 0.04 * L, -0.12 * L, 0.12 * L, -0.05 * L, 0.05 * L)), color="#6b6b6b")
    p.add_mesh(pv.lines_from_points(ref), color="#9a9a9a", line_width=2)
    p.add_mesh(pv.PolyData(ref[np.r_[0:sc.x.size:sc.per_seg]]), color="#9a9a9a", point_size=7,
               render_points_as_spheres=True)


def _frames(sc: _Scene, ks, window_size) -> dict:
    """Screenshots of frames ``ks``; the actors are added once and updated in place (re-adding re-renders)."""
    import pyvista as pv

    L, r = sc.L, 0.022 * sc.L
    ref = np.c_[sc.x, np.full_like(sc.x, -0.075 * L), np.zeros_like(sc.x)]
    p = pv.Plotter(off_screen=True, window_size=tuple(window_size))
    try:
        _static(p, sc, ref)
        sbar = _scalar_bar(p, sc.field, window_size, x=0.86, y=0.1, height=0.62, width=0.035)
        tube, verts, conn = _geometry(sc, int(sc.first[0]), ref, r)
        nodes, links = pv.PolyData(verts.copy()), pv.line_segments_from_points(conn)
        p.add_mesh(tube, scalars=sc.field, clim=sc.clim, cmap=sc.cmap, scalar_bar_args=sbar, smooth_shading=True,
                   ambient=0.35, diffuse=0.75, specular=0.25)
        p.add_mesh(nodes, color="white", point_size=7, render_points_as_spheres=True)
        p.add_mesh(links, color="#b0b0b0", line_width=1)
        label = p.add_text(" ", position="upper_left", font_size=10, color="black")
        _fit(p, -0.07 * L, 1.1 * L, 0.2 * L, window_size, right=0.16)
        imgs = {}
        for k in ks:
            t_, v_, c_ = _geometry(sc, k, ref, r)
            tube.copy_from(t_)
            nodes.points, links.points = v_, c_
            st = {1: "I (stuck)", 2: "II (free)"}.get(int(sc.state[k]), "")
            label.SetText(2, f"t/T = {sc.t_loc[k] / sc.T:.3f}   state {st}   x from 0 (clamp) to L = {L:g}, "
                             f"axial displacement x{sc.scale:.3g}")
            p.render()
            imgs[k] = p.screenshot(return_img=True)
    finally:
        p.close()
    return imgs


def render(source, out, field: str = "displacement", snapshots: int = 4, gif: bool = True, *,
           scale: float | None = None, window_size=(1200, 340), gif_seconds: float = 3.0) -> RenderFiles:
    """Render a periodic response off-screen (drawing only).

    Parameters
    ----------
    source : ResponseData or path of a .pvd
        The sampled response (:func:`plbar.io.response_data`) or a ``.pvd``
        written by :func:`plbar.io.write_data`; :func:`plbar.app.render_response`
        picks one from results or run folders.
    out : path
        Output folder: ``snapshot_NN.png``, ``snapshots.png`` (all snapshots
        stacked), ``spacetime.png`` and ``response.gif``.
    field : str
        Point or cell field to colour by (``displacement``, ``velocity``,
        ``strain``, ``stress``, ``kinetic_energy_density``, ...).
    snapshots : int
        Number of snapshots equally spaced over one period (>= 1).
    gif : bool
        Also write an animated GIF of one period.
    scale : float, optional
        Displacement magnification (default: largest ``|u|`` drawn as ``0.1 L``).
    window_size : (int, int)
        Snapshot size in pixels.
    gif_seconds : float
        Duration of one period in the GIF.
    """
    if isinstance(snapshots, bool) or not isinstance(snapshots, (int, np.integer)) or snapshots < 1:
        raise InputError(f"snapshots = {snapshots!r} must be an integer >= 1")
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    pv.OFF_SCREEN = True
    data = source if isinstance(source, ResponseData) else load_pvd(source)
    sc = _scene(data, field, scale)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    first, nper = sc.first, sc.first.size
    ks = [int(first[int(round(j * nper / snapshots)) % nper]) for j in range(snapshots)]
    ks = ks + [int(k) for k in first if k not in ks] if gif else ks
    imgs = _frames(sc, ks, window_size)
    shots = tuple(_save_png(out / f"snapshot_{j:02d}.png", imgs[k]) for j, k in enumerate(ks[:snapshots]))
    montage = _save_png(out / "snapshots.png", np.vstack([imgs[k] for k in ks[:snapshots]]))
    gif_path = _save_gif(out / "response.gif", [imgs[int(k)] for k in first], gif_seconds) if gif else None
    st = _spacetime(out / "spacetime.png", data, sc.x, sc.vals, sc.on_points, sc.seg_cell, first, sc.t_loc, sc.T,
                    field, sc.clim, sc.cmap)
    return RenderFiles(shots, montage, st, gif_path, field, sc.scale)


def _spacetime(path, data, x, vals, on_points, seg_cell, first, t_loc, T, field, clim, cmap):
    """Field over ``(x, t/T)`` for one period (a simulated motion: its window, impacts and openings drawn), viewed
    from above."""
    import pyvista as pv

    L = float(x[-1])
    H = 0.8 * L
    motion = "event" in data.field_data                     # a simulated motion: its whole window, events marked
    if motion:
        tt, keep = np.unique(t_loc[::-1], return_index=True)   # at an event's time, the state after it
        keep = t_loc.size - 1 - keep
        tt, v = tt / T, vals[keep]
        v = v if on_points else v[:-1]
    else:
        tt = np.r_[t_loc[first], T] / T
        v = vals[first]
        v = np.vstack([v, v[:1]]) if on_points else v          # periodic closure on points
    g = pv.RectilinearGrid(x, tt * H, np.array([0.0]))
    if on_points:
        g.point_data[field] = v.ravel()                     # x fastest
    else:
        g.cell_data[field] = v[:, seg_cell].ravel()
    p = pv.Plotter(off_screen=True, window_size=(900, 760))
    try:
        p.set_background("white")
        p.add_mesh(g, scalars=field, clim=clim, cmap=cmap, show_scalar_bar=True, lighting=False,
                   scalar_bar_args=_scalar_bar(p, field, (900, 760), x=0.88, y=0.1, height=0.76, width=0.05))
        T1 = data.info.get("T1")
        if motion:
            ev = np.asarray(data.field_data["event"])
            for te, k in zip(t_loc[ev > 0], ev[ev > 0]):
                y = te / T * H
                p.add_mesh(pv.Line((0, y, 0.01 * L), (L, y, 0.01 * L)), color="black" if k == 2 else "gray",
                           line_width=3 if k == 2 else 1)
        elif T1 is not None:
            y = T1 / T * H
            p.add_mesh(pv.Line((0, y, 0.01 * L), (L, y, 0.01 * L)), color="black", line_width=3)
        ticks = np.array([[0.0, -0.04 * H, 0], [L, -0.04 * H, 0], [-0.02 * L, 0, 0], [-0.02 * L, H, 0]])
        top = f"t = {data.info.get('periods', 1)} T" if motion else "t = T"
        p.add_point_labels(ticks, ["x = 0", "x = L", "t = 0", top], shape=None, show_points=False,
                           font_size=12, text_color="black", justification_horizontal="center",
                           always_visible=True)
        what = ("t (up, over the window); black lines: impacts, grey: gap opens" if motion else
                "t/T (up); black line: gap opens, t = T1")
        p.add_text(f"{field.replace('_', ' ')} over x (right) and {what}", position="upper_left", font_size=9,
                   color="black")
        _fit(p, -0.1 * L, 1.04 * L, 0.6 * H, (900, 760), right=0.16, cy=0.5 * H)
        img = p.screenshot(return_img=True)
    finally:
        p.close()
    return _save_png(path, img)


BAR_LABEL_FONT = 12      #: font size of the scalar bar's tick labels


TITLE_CHAR = 10.0        #: width of one character of the scalar bar's title (pixels, font size 9)


def bar_title_position(window_size, x: float, y: float, height: float, title: str = "") -> tuple[float, float]:
    """Pixel position of a vertical scalar bar's title: above the bar's top tick label (never on it), and
    moved left as far as the window needs to show the whole title."""
    w, h = window_size
    return min(x * w, w - TITLE_CHAR * len(title) - 4), (y + height) * h + 1.8 * BAR_LABEL_FONT


def _scalar_bar(p, field: str, window_size, x: float, y: float, height: float, width: float) -> dict:
    """The scalar-bar arguments of ``field``; its title is a text above the bar (pyvista draws a bar's own title
    over its top tick label)."""
    title = field.replace("_", " ")
    p.add_text(title, position=bar_title_position(window_size, x, y, height, title), font_size=9, color="black")
    return dict(title=" ", n_labels=3, fmt="%.3g", color="black", vertical=True, position_x=x, position_y=y,
                height=height, width=width, label_font_size=BAR_LABEL_FONT)


def _fit(p, x0, x1, half_height, window_size, right=0.0, cy=0.0):
    """Parallel camera looking down ``-z`` showing ``[x0, x1]`` (and ``cy +- half_height``).

    ``right`` is the fraction of the window width kept free for the scalar bar.
    """
    w, h = window_size
    width = (x1 - x0) / (1.0 - right)
    cx = x0 + 0.5 * width
    scale = max(half_height, 0.5 * width * h / w)
    cam = p.camera
    cam.focal_point = (cx, cy, 0.0)
    cam.position = (cx, cy, 10.0 * width)
    cam.up = (0.0, 1.0, 0.0)
    p.enable_parallel_projection()
    cam.parallel_scale = scale
    p.renderer.ResetCameraClippingRange()


class _quiet:
    """Silence pyvista warnings about unsupported anti-aliasing on some GL drivers."""

    def __enter__(self):
        import warnings

        self._w = warnings.catch_warnings()
        self._w.__enter__()
        warnings.simplefilter("ignore")

    def __exit__(self, *exc):
        self._w.__exit__(*exc)
        return False
