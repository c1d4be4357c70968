"""Continuation: passes through every admissible scan point, runs end to end, classifies ends and events."""

import numpy as np
import pytest

import plbar
from plbar.paths.continuation import G, trace
from plbar.paths import default_domain, scan_field


@pytest.fixture(scope="module")
def grid_result():
    return plbar.solve(plbar.Case(signatures="paper", method="grid"))


def test_continuation_contains_every_admissible_scan_point(default_result, grid_result):
    cont = np.concatenate([np.c_[b.T1, b.T2, b.phi] for b in default_result.paths.branches])
    scan = np.concatenate([np.c_[b.T1, b.T2, b.phi] for b in grid_result.branches])
    assert len(cont) > 1.5 * len(scan)          # evenly resolved: more points than the crossings
    for p in scan:
        d = np.abs(cont - p)
        d[:, 2] = np.minimum(d[:, 2], 2 * np.pi - d[:, 2])
        assert d.max(axis=1).min() < 1e-9


def test_continuation_points_are_exact_and_ordered(default_result):
    for b in default_result.paths.branches:
        assert np.all(b.e1 < 1e-9) and np.all(b.e2 < 1e-9)
        if len(b) > 2:
            step = np.hypot(np.diff(b.T1), np.diff(b.T2))
            dom = default_domain(default_result.prob)
            cell = np.hypot((dom.T1[1] - dom.T1[0]) / 200, (dom.T2[1] - dom.T2[0]) / 200)
            assert step.max() < 1.5 * cell            # no jumps: consecutive points within a grid cell
            assert step.min() > 0


def test_branches_end_to_end_with_classified_ends(default_result):
    allowed_prefix = ("premature switch", "impact velocity", "domain edge", "closed loop", "not periodic",
                      "stop edge", "not a zero")
    for b in default_result.paths.branches:
        for e in b.ends:
            assert e.startswith(allowed_prefix), e
    # the paper's two paths are single branches (no fragments)
    T = [(b.T.min(), b.T.max()) for b in default_result.paths.branches]
    assert sum(lo < 12.277 < hi for lo, hi in T) == 1
    assert sum(lo < 9.9273 < hi for lo, hi in T) == 1
    assert len(default_result.paths.branches) <= 10


def test_events_are_detected_and_consistent(default_result):
    kinds = [e["kind"] for b in default_result.paper for e in b.events]
    assert kinds, "no events found on the default case"
    for b in list(default_result.paths.branches) + list(default_result.paper):
        for e in b.events:
            i = e["index"]
            if e["kind"] == "fold (mu = +1)":
                # the stability flag changes between points i - 1 and i (the periodic core's events)
                assert b.stable[i - 1] != b.stable[i]
                assert (b.max_abs_multiplier[i - 1] - 1) * (b.max_abs_multiplier[i] - 1) <= 0
            if e["kind"] == "fold in T":
                assert (b.T[i] - b.T[i - 1]) * (b.T[i + 1] - b.T[i]) < 0


def test_trace_without_scan_table_locates_crossings_itself():
    """The tracer's own root location on grid lines agrees with the scan refinement to 1e-9."""
    prob = plbar.problem(plbar.chain(5), plbar.node(1))
    t1, t2, _ = scan_field(prob, default_domain(prob), (60, 60))
    from scipy.optimize import brentq

    T1 = 2.3876
    s = brentq(lambda x: G(prob, np.array([T1]), np.array([x]))[0], 9.85, 9.93, xtol=1e-15)
    tr = trace(prob, t1, t2, np.array([T1, s]), max_steps=60)
    pts = tr.P[list(tr.edges.values())]
    assert len(pts) > 10
    g = G(prob, pts[:, 0], pts[:, 1])
    assert np.abs(g).max() < 1e-12


def test_progress_bars_do_not_change_a_bit(monkeypatch):
    """With progress bars the scan and the checks ran in other batches, and a batch's size changes the last bits of
    a BLAS product: ten path points moved by 2e-15. Now the bars count the same batches."""
    import numpy as np

    from plbar.paths import find_paths

    monkeypatch.setenv("PLBAR_PROGRESS_DELAY", "1000")           # enabled, but nothing printed
    prob = plbar.Case().problem()
    a, b = find_paths(prob, progress=False), find_paths(prob, progress=True)
    assert len(a.branches) == len(b.branches) == 8
    for x, y in zip(a.branches, b.branches):
        assert np.array_equal(x.T1, y.T1) and np.array_equal(x.T2, y.T2) and np.array_equal(x.phi, y.phi)
