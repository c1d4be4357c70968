"""The solve plots stay readable with many branches: bounded text, one legend entry per event kind present,
anchor labels that do not overlap, legends of Fig. 9 off the data (checked on the matplotlib objects)."""

import numpy as np
import pytest

import plbar

pytest.importorskip("matplotlib")

from plbar.visuals import plots  # noqa: E402


@pytest.fixture(scope="module")
def fe8():
    """An FE bar with many branches whose two anchor periods nearly coincide (T0_I ~ T0_II/2 ~ 2)."""
    return plbar.solve(plbar.Case(model="fe", n=8, grid=(60, 60)))


@pytest.fixture
def figures(keep_figures):
    """Keep the figures instead of writing and closing them."""
    return keep_figures(plots)


def _kinds(res):
    return {e["kind"] for b in res.branches for e in b.events}


def _texts(fig):
    return [t for ax in fig.axes for t in ax.texts]


def _legend_labels(ax):
    leg = ax.get_legend()
    return [t.get_text() for t in leg.get_texts()] if leg else []


def test_frequency_response_is_bounded_and_legends_kinds_present(fe8, figures, tmp_path):
    n_events = sum(len(b.events) for b in fe8.branches)
    assert len(fe8.branches) >= 20 and n_events >= 20        # the case the plot must survive
    plots.frequency_response(fe8, tmp_path)
    (fig,) = figures
    ax1, ax2 = fig.axes
    texts = _texts(fig)
    assert len(texts) < 20                                    # was one text per event (24) + 4 anchors
    assert not any(t.get_text().split(" ")[0] in ("fold", "Neimark-Sacker") for t in texts)
    labels = _legend_labels(ax2)
    assert len(labels) == len(set(labels)) and set(labels) == _kinds(fe8)
    # every event is drawn as a marker on the xi axis, one series per kind
    marks = {ln.get_label(): ln for ln in ax2.lines if ln.get_label() in _kinds(fe8)}
    for kind, ln in marks.items():
        n = sum(1 for b in fe8.branches for e in b.events if e["kind"] == kind)
        assert len(ln.get_xdata()) == n


def test_anchor_labels_do_not_overlap(fe8, figures, tmp_path):
    T0I, T0II = fe8.paths.prob.system.T0
    assert abs(T0I - T0II / 2) < 0.03 * (T0I + T0II)          # FE bar: both near 2
    plots.frequency_response(fe8, tmp_path)
    (fig,) = figures
    fig.canvas.draw()
    anchors = [t for t in _texts(fig) if t.get_text() in ("$T_0^I$", "$T_0^{II}/2$")]
    assert sorted(t.get_text() for t in anchors) == ["$T_0^I$", "$T_0^{II}/2$"]
    a, b = anchors
    assert a.get_position()[1] != b.get_position()[1]
    r = fig.canvas.get_renderer()
    assert not a.get_window_extent(r).overlaps(b.get_window_extent(r))


def test_paths_plane_labels_only_the_largest_xi(fe8, figures, tmp_path):
    plots.paths_plane(fe8, tmp_path)
    (fig,) = figures
    (ax,) = fig.axes
    ids = sorted(int(t.get_text()) for t in ax.texts)
    top = sorted(b.id for b in sorted(fe8.branches, key=lambda b: -b.xi.max())[:plots.MAX_BRANCH_LABELS])
    assert ids == top and len(ids) == 8 < len(fe8.branches)
    labels = _legend_labels(ax)
    assert len(labels) == len(set(labels)) and set(labels) == _kinds(fe8)


def test_paths_plane_without_events_has_no_event_legend(default_result, figures, tmp_path):
    import dataclasses

    bare = [dataclasses.replace(b, events=()) for b in default_result.branches]
    res = dataclasses.replace(default_result, paths=dataclasses.replace(default_result.paths, branches=tuple(bare)))
    plots.paths_plane(res, tmp_path)
    (fig,) = figures
    assert _legend_labels(fig.axes[0]) == []


def test_fig9_legend_does_not_hide_data(monkeypatch, tmp_path):
    from plbar.visuals import paper

    figs = []
    monkeypatch.setattr(paper, "_save", lambda fig, out, name: figs.append(fig) or [])
    # data fill the lower right quarter of the axes (where the legend used to sit); upper left is empty
    T, s = np.meshgrid(np.linspace(5.0, 10.0, 30), np.linspace(0.0, 2.5, 12))
    T, s = T.ravel(), s.ravel()
    rs = []
    for sk in np.unique(s):
        k = s == sk
        rs.append({"branches": [{"T1": 0.3 * T[k], "T2": 0.7 * T[k], "xi": 0.01 + 0.001 * T[k]}], "T0_II": 12.0})
    allres = [(5, list(np.unique(s)), rs)]
    fams = [[["T0_II/2"] for _ in rs]]
    paper.draw_fig9(tmp_path, allres, fams)
    (fig,) = figs
    ax = fig.axes[0]
    ax.set_xlim(0.0, 10.5)
    ax.set_ylim(0.0, 5.0)
    fig.canvas.draw()
    leg = ax.get_legend()
    box = leg.get_window_extent(fig.canvas.get_renderer())
    xy = ax.transData.transform(np.c_[T, s])
    inside = (xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)
    assert inside.sum() == 0
    import matplotlib.pyplot as plt

    plt.close(fig)
