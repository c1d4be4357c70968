"""The convergence plot: one log-log panel per quantity, files written without warnings, honest labels."""

import warnings
from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from plbar.studies.refine.convergence import converge, known_limit
from plbar.visuals import convergence as vc
from plbar.visuals import convergence_plot

N = np.array([8, 16, 32, 64, 128])
H = 1.0 / N


def _items():
    """A converged quantity, one without a limit (oscillatory) and one that hits its limit exactly once."""
    ok = converge("T0_I/L", H, 1.25 + 2.0 * H**2 * (1 + 0.5 * H), expected=2)
    osc = converge("xi_max", H, 0.1 + (-1.0)**np.arange(5) * H**2)
    hit = known_limit("energy", H, np.array([1.1, 1.02, 1.0, 1.004, 1.001]), 1.0)
    assert osc.limit is None and hit.q[2] == hit.limit
    return [ok, osc, hit]


def test_writes_png_and_pdf_without_warnings(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        files = convergence_plot(_items(), tmp_path / "figs", title="refinement")
    assert [f.name for f in files] == ["refine_convergence.png", "refine_convergence.pdf"]
    assert files[0].stat().st_size > 10_000 and files[1].stat().st_size > 1_000
    assert files[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and files[1].read_bytes()[:5] == b"%PDF-"
    assert sorted(p.name for p in (tmp_path / "figs").iterdir()) == sorted(f.name for f in files)  # no temp left


@pytest.fixture
def figures(keep_figures):
    """Keep the figures instead of writing and closing them."""
    return keep_figures(vc)


def test_panels_say_what_they_show(figures):
    items = _items() + [SimpleNamespace(name="flat", h=H[:3], q=np.ones(3), limit=float("nan"), rate=None,
                                        fitted=None)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        convergence_plot(items, "unused")
    (fig,) = figures
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert len(axes) == 4 and len(fig.axes) == 6                  # 2 rows of at most 3 columns
    titles = [ax.get_title() for ax in axes]
    assert titles[0] == "T0_I/L\n|q(h) - 1.25|" and "no limit" in titles[1] and "no limit" in titles[3]
    legend = [[t.get_text() for t in ax.get_legend().get_texts()] for ax in axes]
    assert f"fitted slope p = {items[0].fitted:.3g}" in legend[0] and legend[0][-1].startswith("final observed rate 2")
    assert "final rate: none" in legend[1] and "fitted slope: none" in legend[1]
    x, y = axes[2].lines[0].get_data()                           # the exact hit is left out of the log axes
    assert len(x) == 4 and np.all(y > 0)
    x, y = axes[1].lines[0].get_data()                           # successive differences against h_{i+1}
    np.testing.assert_allclose(x, H[1:])
    assert axes[0].get_xscale() == "log" and axes[0].get_yscale() == "log"
    ref = axes[0].lines[1]                                        # dashed reference with the fitted slope
    rx, ry = ref.get_data()
    assert ref.get_linestyle() == "--"
    assert np.log(ry[1] / ry[0]) / np.log(rx[1] / rx[0]) == pytest.approx(items[0].fitted, rel=1e-12)
