"""The refinement picture: one row of panels per family (responses, period range, largest xi_eq)."""

import warnings

import numpy as np
import pytest

import plbar.visuals.refinement as vr
from plbar.visuals import refine_family_plot


def _level(n, T, xi, good):
    return {"n": n, "T0_I": 2.0, "A": 2.9, "pieces": [{"T1": list(0.1 * np.ones(len(T))), "T2": list(np.array(T) - 0.1),
                                                      "xi": list(xi), "good": list(good)}]}


@pytest.fixture
def figures(keep_figures):
    return keep_figures(vr)


def test_rows_per_family_with_what_they_show(figures):
    fam = [_level(8, [2.9, 3.0, 3.1], [0.01, 0.05, 0.02], [1, 1, 0]), _level(16, [3.0], [0.003], [1]),
           _level(32, [3.0, 3.05], [0.0, 0.0], [0, 0])]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        refine_family_plot([("A", fam), ("B", fam[:2])], "unused")
    (fig,) = figures
    axes = fig.axes
    assert len(axes) == 6 and "admissible responses" in axes[0].get_title()
    assert [sf._suptitle.get_text() for sf in fig.subfigs] == ["A", "B"]       # each row headed by its family
    x, y = axes[0].lines[0].get_data()                     # N = 8: the two admissible points, T / T0_I
    assert np.allclose(x, [1.45, 1.5]) and np.allclose(y, [0.01, 0.05])
    n, xi = axes[2].lines[0].get_data()                     # largest xi per N (N = 32 has none)
    assert list(n) == [8, 16] and np.allclose(xi, [0.05, 0.003])


def test_writes_png_and_pdf(tmp_path):
    files = refine_family_plot([("A", [_level(8, [2.9, 3.0], [0.01, 0.02], [1, 1])])], tmp_path, "fam")
    assert [f.name for f in files] == ["fam.png", "fam.pdf"] and files[0].stat().st_size > 10_000
