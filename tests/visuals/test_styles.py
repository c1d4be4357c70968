"""Issue 30, item 9 (figures): one style per signature, "1P" never among the other signatures, the times of the
paper's class and of the signature search apart, axis labels with their units."""

import time
import warnings

import numpy as np
import pytest

import plbar

pytest.importorskip("matplotlib")

from plbar.visuals import plots, survey  # noqa: E402

#: 30 signatures (more than colours or markers alone)
MANY = [f"{m}{'P' * p}{'Z' * z}" for m in (1, 2, 3) for p in range(2) for z in range(1, 6)]

#: the signatures of the default run
DEFAULT = "1Z 1PZ 1PP 2PZ 2PZZ 3PPZZ 1P 2ZZ 1ZZ 2PZPZ 3PZPZZ 1PPZ 2ZZZ".split()


def _pairs(ax):
    """``label -> (colour, marker)`` of the legend's marker entries."""
    from matplotlib.colors import to_hex

    h, labels = ax.get_legend_handles_labels()
    return {lab: (to_hex(x.get_color()), x.get_marker()) for x, lab in zip(h, labels) if hasattr(x, "get_marker")}


def _survey_table(sigs):
    n = len(sigs)
    T = np.linspace(6.0, 14.0, n)
    one = np.ones(n)
    return {"T": T, "start": np.full(n, "rest", dtype=object), "kind": np.full(n, "periodic", dtype=object),
            "signature": np.array(sigs, dtype=object), "m": one, "impacts_per_T": one,
            **{c: 0.01 * one for c in ("loss_per_T", "loss_min", "loss_max", "xi_eq", "xi_min", "xi_max", "xi_w",
                                       "amp_c", "amp_c_max")}}


def test_many_signatures_get_distinct_styles_the_same_in_every_figure(keep_figures, tmp_path):
    figs = keep_figures(survey)
    survey.survey_plot(_survey_table(MANY), tmp_path)
    survey.survey_plot(_survey_table(DEFAULT), tmp_path)
    for k in range(len(DEFAULT)):
        survey.survey_plot(_survey_table(DEFAULT[k:k + 1]), tmp_path)
    many, default, *alone = ({k.split("signature ")[1]: v for k, v in _pairs(f.axes[0]).items() if "signature" in k}
                             for f in figs)
    assert sorted(many) == sorted(MANY) and sorted(default) == sorted(DEFAULT)
    assert len(set(many.values())) == len(many)                 # no two signatures alike
    assert len(set(default.values())) == len(default)
    for one in alone:                                           # a signature's style is the same in every figure
        ((lab, style),) = one.items()
        assert default[lab] == style, lab


def test_default_run_legend_is_unique_and_1p_is_the_papers(default_run, keep_figures, tmp_path):
    figs = keep_figures(plots)
    plots.frequency_response(default_run, tmp_path)
    pairs = _pairs(figs[0].axes[0])
    sig = {k: v for k, v in pairs.items() if k.startswith("signature")}
    # the signatures with the most points named, each its own style; the rest under one grey entry
    assert len(sig) == plots.MAX_SIGNATURE_ENTRIES and len(set(sig.values())) == len(sig)
    others = {b.label for b in default_run.branches} - {"1P"} - {k.split("signature ")[1] for k in sig}
    grey = [k for k in pairs if k.startswith(f"{len(others)} other signatures (grey)")]
    assert len(others) >= 7 and len(grey) == 1 and all(lab in grey[0].replace("\n", " ") for lab in others)
    assert "signature 1P" not in pairs                         # the paper's class is not another signature
    assert any(k.startswith("1P (paper's class)") for k in pairs)


def test_summary_lists_every_signature_once_the_papers_first(default_run):
    from plbar.cli.run import _human

    text = _human(default_run.summary(), {}, False)
    rows = [line.split() for line in text[text.index("by signature"):].splitlines()[1:] if line.startswith("    ")]
    labels = [r[0] for r in rows]
    assert labels[0] == "1P" and len(labels) == len(set(labels))
    families = {b.sig.family for b in default_run.branches}
    assert set(labels) == families
    n1p = len(default_run.paper)
    assert f"the paper's class (1P): {n1p} branches" in text and int(rows[0][1]) == n1p


@pytest.mark.slow                    # long: with the slow tests (the default suite under 10 minutes)
def test_times_of_the_papers_class_and_the_search_apart(monkeypatch):
    """The search's own work (here a stand-in taking 0.4 s) is not charged to the paper's class."""
    from plbar.app import run as app_run

    class Slow:
        def __init__(self, *a):
            pass

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return False

        def ready(self):
            pass

        def seeds(self):
            time.sleep(0.4)
            return []

        def curve(self):
            pass

    monkeypatch.setattr(app_run, "Search", Slow)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", plbar.errors.CoarseGridWarning)
        res = plbar.solve(plbar.Case(grid=(40, 40)))
    s = res.summary()
    assert s["signatures_time"] >= 0.4 and s["paper_time"] <= s["run_time"] - 0.4
    assert s["paper_time"] + s["signatures_time"] <= s["run_time"]
    from plbar.cli.run import _human

    assert f"found in {s['paper_time']:.3g} s of scan and {s['signatures_time']:.3g} s more" in _human(s, {}, False)


def _labels(fig):
    return [t for ax in fig.axes for t in (ax.get_xlabel(), ax.get_ylabel()) if t]


@pytest.mark.parametrize("model, note", [("chain", "m = k = 1"), ("fe", "L = c = 1")])
def test_axis_labels_say_their_units(model, note, keep_figures, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", plbar.errors.CoarseGridWarning)
        res = plbar.solve(plbar.Case(model=model, n=4, signatures="paper", grid=(40, 40)))
    figs = keep_figures(plots)
    plots.frequency_response(res, tmp_path)
    plots.paths_plane(res, tmp_path)
    labels = [x for f in figs for x in _labels(f)]
    assert len(labels) == 5
    assert all(note in x or "dimensionless" in x for x in labels), labels
    assert sum(note in x for x in labels) == 4


def test_survey_axis_labels_say_their_units(keep_figures, tmp_path):
    figs = keep_figures(survey)
    survey.survey_plot(_survey_table(MANY[:3]), tmp_path, units="m = k = 1")
    labels = _labels(figs[0])
    assert len(labels) == 4 and all("m = k = 1" in x or "dimensionless" in x for x in labels), labels
