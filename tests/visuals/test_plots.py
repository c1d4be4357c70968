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
    return plbar.solve(plbar.Case(signatures="paper", model="fe", n=8, grid=(60, 60)))


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
    """Anchors that (nearly) coincide share one label: not two labels stacked or on top of each other."""
    T0I, T0II = fe8.prob.system.T0
    assert abs(T0I - T0II / 2) < 0.03 * (T0I + T0II)          # FE bar: both near 2
    plots.frequency_response(fe8, tmp_path)
    (fig,) = figures
    fig.canvas.draw()
    anchors = [t for t in _texts(fig) if "T_0" in t.get_text()]
    assert [t.get_text() for t in anchors] == ["$T_0^I \\approx T_0^{II}/2$"]


def test_separate_anchors_get_one_label_each(default_result, figures, tmp_path):
    plots.frequency_response(default_result, tmp_path)
    (fig,) = figures
    fig.canvas.draw()
    anchors = [t for t in _texts(fig) if "T_0" in t.get_text()]
    assert sorted(t.get_text() for t in anchors) == ["$T_0^I$", "$T_0^{II}/2$"]
    r = fig.canvas.get_renderer()
    assert len({t.get_position()[1] for t in anchors}) == 1                    # one line, not stacked
    assert not anchors[0].get_window_extent(r).overlaps(anchors[1].get_window_extent(r))


def test_paths_plane_labels_only_the_largest_xi(fe8, figures, tmp_path):
    plots.paths_plane(fe8, tmp_path)
    (fig,) = figures
    (ax,) = fig.axes
    ids = sorted(int(t.get_text().lstrip("#")) for t in ax.texts)
    top = sorted(b.id for b in sorted(fe8.branches, key=lambda b: -b.xi.max())[:plots.MAX_BRANCH_LABELS])
    assert ids == top and len(ids) == 8 < len(fe8.branches)
    labels = _legend_labels(ax)
    assert len(labels) == len(set(labels)) and set(labels) == _kinds(fe8)


def test_paths_plane_without_events_has_no_event_legend(default_result, figures, tmp_path):
    import dataclasses

    bare = [dataclasses.replace(b, events=[]) for b in default_result.branches]
    res = dataclasses.replace(default_result, branches=tuple(bare))
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
    assert all(a.get_legend() is None for a in fig.axes)         # nothing drawn over the data: the maximum is
    assert "max" in ax.get_title() and "at s =" in ax.get_title()   # said in the panel's title
    import matplotlib.pyplot as plt

    plt.close(fig)


# issue 22, "smaller": labels that read as numbers, log ticks, a legend for what is not there ---------------------

def test_branch_labels_never_touch(default_result, figures, tmp_path):
    """The default case draws branches 0 and 1 side by side: their labels read "10" before."""
    plots.paths_plane(default_result, tmp_path)
    (fig,) = figures
    (ax,) = fig.axes
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    from matplotlib.text import Text

    boxes = [Text.get_window_extent(t, r) for t in ax.texts]             # the text, not its leader line
    assert all(t.get_text().startswith("#") for t in ax.texts) and len(boxes) >= 8
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])


def test_log_ticks_are_plain_numbers(fe8, figures, tmp_path):
    plots.frequency_response(fe8, tmp_path)
    (fig,) = figures
    ax1 = fig.axes[0]
    ax1.set_ylim(0.5, 20.0)                                    # a narrow log range: minor ticks get labels
    fig.canvas.draw()
    labels = [t.get_text() for t in ax1.get_yticklabels(minor=True) + ax1.get_yticklabels()]
    assert any(labels) and not any("times" in x or "^" in x for x in labels), labels


def test_stability_legend_lists_only_what_is_there(fe_p2_coarse, figures, tmp_path):
    res = fe_p2_coarse
    assert not any(b.stable.any() for b in res.branches)       # this FE bar: no stable point
    plots.frequency_response(res, tmp_path)
    (fig,) = figures
    assert _legend_labels(fig.axes[0]) == ["1P, unstable"]                  # no entry "stable"


def test_render_scalar_bar_title_is_above_its_top_label():
    from plbar.visuals.render import BAR_LABEL_FONT, bar_title_position

    for size, (x, y, h) in (((1200, 340), (0.86, 0.1, 0.62)), ((900, 760), (0.88, 0.1, 0.76))):
        px, py = bar_title_position(size, x, y, h, "kinetic energy density")
        assert py >= (y + h) * size[1] + 1.5 * BAR_LABEL_FONT and py < size[1] - 10
        assert px + 10 * len("kinetic energy density") <= size[0]


@pytest.mark.slow                    # long: with the slow tests (the default suite under 10 minutes)
def test_refine_plot_titles_have_no_internal_names(tmp_path, monkeypatch):
    from plbar.cli import main
    from plbar.visuals import convergence as vc

    titles = []
    real = vc.convergence_plot

    def spy(items, *a, **k):
        titles.extend(it.name for it in items)
        return real(items, *a, **k)

    monkeypatch.setattr("plbar.visuals.convergence_plot", spy)
    assert main(["refine", "-N", "3", "4", "5", "6", "--grid", "30", "30", "--executor", "serial", "-q",
                 "--out", str(tmp_path)]) == 0
    assert titles and all("family near $T_0^{II}/2$" in t for t in titles)
    assert not any(x in t for t in titles for x in ("T0_I_L", "T_mid_T0I", "T0_II/2 ", "xi_max"))


def test_frequency_response_draws_xi_w_on_request(tmp_path, small):
    """paths.csv has xi_w; the frequency-response plot draws it instead of xi_eq when asked (plbar run --plot-xi w)."""
    from plbar.visuals import frequency_response

    p = frequency_response(small, tmp_path, "fr_w", xi="w")
    assert p.stat().st_size > 10_000
    assert all(np.all(b.xi_w >= 0) and np.any(b.xi_w != b.xi) for b in small.branches if len(b))
