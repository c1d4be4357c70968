"""Issue 44 (8, 10): the paper's figures mark the exact sample points, figure 9 the optimum that sweep-loads
states, the docs quote the same numbers, and the figures' titles and legends stay off the data."""

import re
from pathlib import Path

import numpy as np
import pytest

import plbar
import plbar.visuals.paper as vp
from plbar.studies.paper import figures as pf

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
    from plbar.studies.paper.points import exact_point

    pts = pf.sample_points(res)
    fams = pf.families_of(res)
    vp.draw_fig2("unused", res, fams, pts)
    vp.draw_fig3("unused", res, fams, pts)
    fig2, fig3 = figures
    for name, (T1, T2, _) in (("red", (1.7748, 8.1525, 0)), ("green", (2.3876, 9.8894, 0))):
        o = exact_point(res.prob, T1, T2)                # what examples/paper_sec41.py prints
        x, y = _marker(fig2, f"{name} point").get_data()
        assert x[0] == o.T1[0] and y[0] == o.T2[0]
        near = vp.nearest_point(res, fams, (T1, T2, 0))[0]     # the old marker: another point of the 60 x 60 grid
        assert abs(near.T2[0] - o.T2[0]) > 1e-6
        t, x1 = _marker(fig3, f"{name} x1").get_data()         # the time history is the exact orbit's
        assert np.allclose(x1, o.response(np.mod(t, o.T[0]))[0][0, :, 0], atol=1e-12, rtol=0)
        assert np.isclose(t[1200], o.T[0])                      # two periods of the exact T


def _doc() -> str:
    return " ".join(DOCS.read_text().split())


def test_figure_9_marks_the_optimum_sweep_loads_states(figures):
    from plbar.studies.loads import sweep_loads

    pf.fig9_xi_position("unused", grid=(60, 60), ns=(3,), per_element=1)
    (fig,) = figures
    T, s = (v[0] for v in _marker(fig, "optimum").get_data())
    e = sweep_loads(plbar.Case(n=3, grid=(60, 60)), pairs=False, plot=False).summary["families"]["T0_II/2"]
    assert np.isclose(s, e["s_at_best_single"], rtol=1e-12) and np.isclose(T, e["T_at_best_single"], rtol=1e-12)
    assert f"max {e['xi_best_single_max']:.4f} at s = {e['s_at_best_single']:.4g}" in fig.axes[0].get_title()


def test_the_docs_quote_the_best_load_position_of_sweep_loads():
    from plbar.studies.loads import sweep_loads

    e = sweep_loads(plbar.Case(n=5), pairs=False, plot=False, per_element=1).summary["families"]["T0_II/2"]
    m = re.search(r"best single force .{0,80}?\$s = ([0-9.]+)\$.{0,40}?\$\\xi_\{\\mathrm\{eq\}\} = ([0-9.]+)\$",
                  _doc())
    assert m, "docs/paper.md: the sentence with the best single force on N = 5 is gone"
    assert m.group(1) == f"{e['s_at_best_single']:.3f}" and m.group(2) == f"{e['xi_best_single_max']:.4f}"
    assert "plbar sweep-loads -N 5" in _doc()


def _independent_xi(o):
    """``xi_eq`` of one orbit by another route: the modes by ``scipy.linalg.eigh`` of the state matrices, the
    modal velocities ``eta' = Phi^T M v`` by Gauss-Legendre quadrature of the replayed response, the loss as
    the contact mass's kinetic energy just before the impact (plastic, lumped mass)."""
    from numpy.polynomial.legendre import leggauss
    from scipy.linalg import eigh

    s = o.prob.system
    M, K = (np.asarray(a.toarray() if hasattr(a, "toarray") else a, float) for a in (s.M, s.K))
    w1, P1 = eigh(K[:-1, :-1], M[:-1, :-1])
    w2, P2 = eigh(K, M)
    xg, wg = leggauss(300)
    den = 0.0
    for (a, b), P, Mi, w, cut in (((0.0, o.T1[0]), P1, M[:-1, :-1], w1, -1), ((o.T1[0], o.T[0]), P2, M, w2, None)):
        t = 0.5 * (b - a) * xg + 0.5 * (b + a)
        v = o.response(t)[1][0][:, :cut]
        eta = P.T @ Mi @ v.T
        den += (eta ** 2 @ (0.5 * (b - a) * wg)) @ np.sqrt(w)
    vc = o.response(np.array([o.T[0] * (1 - 1e-14)]))[1][0, 0, -1]
    return 0.5 * M[-1, -1] * vc ** 2 / (2 * den), vc


def test_xi_at_the_papers_zero_on_path_1_is_not_zero():
    """The paper's zero xi_eq at T = 10.167 (= T0_I) on path 1: Eq. (22) at the exact path point of T = T0_I,
    by plbar and by the independent route, is 0.0226, and the only zero on path 1 is its grazing end."""
    from scipy.optimize import brentq, minimize_scalar

    from plbar.paths.continuation import G
    from plbar.response import coefficients, phase
    from plbar.studies.paper.points import point_at_period

    res = plbar.solve(plbar.Case(signatures="paper"))
    fams = pf.families_of(res)
    (b,) = [b for b, f in zip(res.branches, fams) if f == "T0_I"]
    prob = res.prob
    T0I = prob.system.T0[0]
    o = point_at_period(prob, T0I, b.T1[int(np.argmin(abs(b.T - T0I)))])
    xi, vc = _independent_xi(o)
    d = plbar.damping(o)
    assert np.isclose(d.xi[0], xi, rtol=1e-9, atol=0) and abs(xi - 0.0226) < 5e-5 and vc > 0.9
    # the zero: the impact velocity of path 1 touches 0 (grazing) at its end, found on D = 0 by a minimisation
    j = int(np.argmin(b.T))

    def vc2(t1):                                            # v_c(T-)^2 on D = 0 at T^I = t1 (either phase)
        t2 = b.T2[j] - (t1 - b.T1[j])
        t2 = brentq(lambda x: G(prob, np.array([t1]), np.array([x]))[0], t2 - 0.03, t2 + 0.03, xtol=1e-14)
        p = plbar.orbits(prob, [t1], [t2], phase(coefficients(prob, [t1], [t2])))
        return p.response(np.array([p.T[0] * (1 - 1e-14)]))[1][0, 0, -1] ** 2, t1 + t2

    r = minimize_scalar(lambda t1: vc2(t1)[0], bracket=(b.T1[j] - 0.03, b.T1[j], b.T1[j] + 0.03), tol=1e-10)
    Tg = vc2(r.x)[1]
    assert r.fun < 1e-12 and abs(Tg - 9.9037) < 2e-4 and T0I - Tg > 0.25
    assert np.all(b.xi[b.T > Tg + 0.01] > 2e-4) and b.xi[j] < 1e-9     # plbar's zero is there, and only there
    doc = _doc()
    assert f"{xi:.4f}" in doc and f"{Tg:.3f}" in doc and f"{T0I:.4f}" in doc


# -- layout: titles and legends off the data and off each other (issue 44, finding 10) -------------------------
def _box(artist, fig):
    return artist.get_window_extent(fig.canvas.get_renderer())


def _apart(a, b) -> bool:
    return not a.overlaps(b)


def _fig9_input():
    T = np.linspace(11.0, 12.5, 30)
    rs = [{"T0_II": 22.0,
           "branches": [{"T1": list(T / 5), "T2": list(T * 4 / 5), "xi": list(0.05 + 0.01 * s * T / 12)}]}
          for s in (1.0, 2.0, 3.0)]
    return [(5, [1.0, 2.0, 3.0], rs), (6, [1.0, 2.0, 3.0], rs)], [[["T0_II/2"]] * 3] * 2


def test_figure_9_suptitle_clears_the_panel_titles(figures):
    allres, labels = _fig9_input()
    vp.draw_fig9("unused", allres, labels)
    (fig,) = figures
    fig.canvas.draw()
    sup = _box(fig._suptitle, fig)
    for ax in fig.axes:
        assert _apart(sup, _box(ax, fig)) and _apart(sup, _box(ax.title, fig))
    titles = [_box(ax.title, fig) for ax in fig.axes[:2]]
    assert _apart(*titles)


def test_figure_2b_legend_covers_no_branch(res, figures):
    vp.draw_fig2("unused", res, pf.families_of(res))
    (fig,) = figures
    fig.canvas.draw()
    ax2 = fig.axes[1]
    leg = _box(ax2.get_legend(), fig)
    for line in ax2.lines:
        xy = ax2.transData.transform(np.c_[line.get_xdata(), line.get_ydata()])
        inside = (xy[:, 0] >= leg.x0) & (xy[:, 0] <= leg.x1) & (xy[:, 1] >= leg.y0) & (xy[:, 1] <= leg.y1)
        assert not inside.any(), line.get_label()
    assert _apart(leg, _box(ax2, fig))


def test_refine_family_titles_do_not_run_into_each_other(keep_figures):
    import plbar.visuals.refinement as vr

    got = keep_figures(vr)
    lv = [{"n": n, "T0_I": 2.0, "A": 2.9, "pieces": [{"T1": [0.1, 0.1], "T2": [2.8, 2.9], "xi": [0.01, 0.02 / n],
                                                      "good": [1, 1]}]} for n in (8, 16, 32)]
    label = "fe-P1-lumped+Me0.5, family near $T_0^{II}/2$"
    vr.refine_family_plot([(label, lv), (label, lv)], "unused")
    (fig,) = got
    fig.canvas.draw()
    boxes = [(_box(ax.title, fig), _box(ax, fig), _box(ax.yaxis.label, fig)) for ax in fig.axes]
    for i, (ti, _, _) in enumerate(boxes):
        for j, (tj, aj, yj) in enumerate(boxes):
            if i != j:
                assert _apart(ti, tj) and _apart(ti, aj) and _apart(ti, yj), (fig.axes[i].get_title(), j)
    assert all(fig.axes[i].get_title() and len(fig.axes[i].get_title()) < 50 for i in range(len(fig.axes)))
    heads = [sf._suptitle.get_text() for sf in fig.subfigs]
    assert heads == [label, label]


class _Branch:
    def __init__(self, label, T, stable):
        self.label, self.T = label, np.asarray(T, float)
        self.stable = np.full(self.T.size, stable)
        self.xi = 0.01 * self.T
        self.orbits = [type("O", (), {"amplitude": 1.0 + t})() for t in self.T]


def test_frequency_response_legend_has_at_most_eight_entries():
    import matplotlib.pyplot as plt

    from plbar.visuals import plots

    labels = ["1Z", "1PZ", "1PP", "2PZ", "2PZZ", "3PPZZ", "2ZZ", "1ZZ", "2PZPZ", "3PZPZZ", "1PPZ", "2ZZZ"]
    branches = [_Branch(lab, np.linspace(5 + k, 5.5 + k, 3 + k), k % 2 == 0) for k, lab in enumerate(labels)]
    branches.append(_Branch("1P", [9.0, 10.0], True))
    fig, (ax1, ax2) = plt.subplots(2, 1)
    try:
        plots._draw_signatures(ax1, ax2, branches)
        ax1.plot([], [], "o", label="1P (paper's class), stable")
        ax1.plot([], [], "x", label="1P, unstable")
        names = ax1.get_legend_handles_labels()[1]
        assert len(names) <= 8
        big = [lab for lab in labels[::-1][:plots.MAX_SIGNATURE_ENTRIES]]     # the most points: named
        assert all(f"signature {lab}" in names for lab in big)
        other = [n for n in names if "other signatures" in n]
        assert len(other) == 1 and all(lab in other[0].replace("\n", " ") for lab in labels if lab not in big)
    finally:
        plt.close(fig)
