"""Issue 44 (8, 10): the paper's figures mark the exact sample points, figure 9 the optimum that sweep-loads
states, the docs quote the same numbers, and the figures' titles and legends stay off the data."""

import re
from pathlib import Path

import numpy as np
import pytest

import plbar
import plbar.visuals.paper as vp
from plbar.studies.paper import figures as pf
from plbar.studies.paper.points import exact_point

pytest.importorskip("matplotlib")

DOCS = Path(__file__).resolve().parents[2] / "docs" / "paper.md"


@pytest.fixture(scope="module")
def res():
    return plbar.solve(plbar.Case(grid=(60, 60), signatures="paper"))


@pytest.fixture
def figures(keep_figures):
    return keep_figures(vp)


def _marker(fig, gid):
    (line,) = [a for ax in fig.axes for a in ax.lines if a.get_gid() == gid]
    return line


def test_figures_2_and_3_mark_the_exact_points_the_example_computes(res, figures):
    pts = pf.sample_points(res)
    fams = pf.families_of(res)
    vp.draw_fig2("unused", res, fams, pts)
    vp.draw_fig3("unused", res, fams, pts)
    fig2, fig3 = figures
    for name, (T1, T2, _) in (("red", (1.7748, 8.1525, 0)), ("green", (2.3876, 9.8894, 0))):
        o = exact_point(res.paths.prob, T1, T2)                # what examples/paper_sec41.py prints
        x, y = _marker(fig2, f"{name} point").get_data()
        assert x[0] == o.T1[0] and y[0] == o.T2[0]
        near = vp.nearest_point(res, fams, (T1, T2, 0))[0]     # the old marker: another point of the 60 x 60 grid
        assert abs(near.T2[0] - o.T2[0]) > 1e-6
        t, x1 = _marker(fig3, f"{name} x1").get_data()         # the time history is the exact orbit's
        assert np.allclose(x1, o.response(np.mod(t, o.T[0]))[0][0, :, 0], atol=1e-12, rtol=0)
        assert np.isclose(t[1200], o.T[0])                      # two periods of the exact T
