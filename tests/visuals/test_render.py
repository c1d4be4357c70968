"""Headless pictures: non-blank PNGs and an animated GIF."""

import numpy as np
import pytest

from plbar.app import export
from plbar.errors import InputError

pytest.importorskip("pyvista")
Image = pytest.importorskip("PIL.Image")


def _stats(path):
    a = np.asarray(Image.open(path).convert("RGB"), dtype=float)
    colours = np.unique(a.reshape(-1, 3), axis=0).shape[0]
    return a.std(), colours, a.shape


def test_render_from_pvd_folder(small, tmp_path):
    export.write_response(small, tmp_path / "vtk", steps=12)
    f = render_(tmp_path / "vtk", tmp_path / "png", snapshots=3)
    assert len(f.snapshots) == 3
    imgs = []
    for p in f.snapshots + (f.montage, f.spacetime):
        std, colours, shape = _stats(p)
        assert std > 10 and colours > 20, p
        imgs.append(np.asarray(Image.open(p)))
    assert not np.array_equal(imgs[0], imgs[1]), "snapshots at different times must differ"
    g = Image.open(f.gif)
    assert g.format == "GIF" and g.n_frames == 12
    g.seek(5)
    std, colours, _ = _stats_img(g)
    assert std > 10 and colours > 5


def test_render_result_cell_field_no_gif(p2_small, tmp_path):
    f = render_(p2_small, tmp_path, field="stress", snapshots=2, gif=False, steps=8)
    assert f.gif is None and not (tmp_path / "response.gif").exists()
    std, colours, _ = _stats(f.snapshots[0])
    assert std > 10 and colours > 20
    with pytest.raises(InputError, match="field = 'nope'"):
        render_(p2_small, tmp_path, field="nope", gif=False, steps=8)


def render_(*a, **k):
    from plbar.app import render_response as render

    return render(*a, **k)


def _stats_img(im):
    a = np.asarray(im.convert("RGB"), dtype=float)
    return a.std(), np.unique(a.reshape(-1, 3), axis=0).shape[0], a.shape


def test_a_cracked_bar_is_drawn_open_at_its_crack(tmp_path):
    """A crack between two clamps: no segment joins the faces (the tube splits where the crack opens), a clamp and no
    stop at x = L; the scene's segments map to the cells that hold them; a beam is refused by name."""
    import plbar
    from plbar import io as pio
    from plbar.visuals.render import _scene

    c = plbar.Case(model="fe", n=8, crack_at=0.5, supports="clamped-clamped", load_points=((0.25, 1.0),),
                   signatures="paper", grid=(60, 60))
    b = max(plbar.solve(c).paths.branches, key=lambda b: b.xi.max())
    d = pio.response_data(b.orbits.take([0]), {}, steps=8)
    sc = _scene(d, "strain", None)
    assert sc.crack == 4 and sc.far == "clamp" and sc.x[4] == sc.x[5] == 0.5
    assert np.array_equal(sc.seg_cell[np.r_[0:4, 5:9]], np.arange(8))
    from plbar.visuals.render import render

    f = render(d, tmp_path, field="strain", snapshots=2, gif=False)
    std, colours, _ = _stats(f.montage)
    assert std > 10 and colours > 20
    from plbar.io.beamfields import BEAM_POINT_FIELDS

    beam = pio.ResponseData(d.points, d.cells, d.cell_type, d.times, {k: d.point_data["displacement"]
                                                                     for k in BEAM_POINT_FIELDS}, {}, d.field_data, {})
    with pytest.raises(InputError, match="beam"):
        render(beam, tmp_path / "beam", gif=False)
