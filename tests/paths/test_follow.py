"""Scan-free following of zero curves inside a period window (plbar.paths.follow)."""

import numpy as np
import pytest

import plbar
from plbar.errors import InputError
from plbar.paths import Band, correct_onto, find_paths, follow
from plbar.response import scan_G
from plbar.studies.refine.track_check import on_curves


@pytest.fixture(scope="module")
def chain_family():
    """The paper's chain, its T0_II/2 window and the scan's branches there."""
    prob = plbar.Case().problem()
    T0I, T0II = prob.system.T0
    A = T0II / 2
    band = Band((0.0, T0I / 2), (0.85 * A, 1.15 * A))
    paths = find_paths(prob, band.domain(), (120, 120))
    main = max(paths.branches, key=len)
    return prob, band, paths, main


def test_band_coordinates_round_trip():
    band = Band((0.0, 2.0), (5.0, 9.0))
    rng = np.random.default_rng(1)
    P = np.c_[rng.uniform(0, 2, 50), rng.uniform(3, 7, 50)]
    assert np.allclose(band.from_u(band.to_u(P)), P, rtol=0, atol=1e-14)
    assert np.allclose(band.to_u([[0.0, 5.0], [2.0, 7.0]]), [[0, 0], [1, 1]])
    inside = band.contains(P)
    T = P.sum(axis=1)
    assert np.array_equal(inside, (T >= 5) & (T <= 9))
    d = band.domain()
    assert d.T1 == (0.0, 2.0) and d.T2 == (3.0, 9.0)


@pytest.mark.parametrize("T1, T", [((0.0, 1.0), (2.0, 1.5)), ((-1.0, 1.0), (2.0, 3.0)), ((0.0, 3.0), (1.0, 2.5))])
def test_empty_band_is_refused(T1, T):
    with pytest.raises(InputError, match="window"):
        Band(T1, T)


def test_correct_onto_lands_on_the_curve(chain_family):
    prob, band, _, main = chain_family
    P = np.c_[main.T1, main.T2][5:-5:10]
    U = band.to_u(P)
    t = np.gradient(band.to_u(np.c_[main.T1, main.T2]), axis=0)[5:-5:10]
    n = np.c_[-t[:, 1], t[:, 0]] / np.linalg.norm(t, axis=1)[:, None]
    V, nev = correct_onto(prob, band, U + 0.004 * n, n, 0.01)         # pushed off along the normal, then back
    assert np.all(np.isfinite(V)) and nev > 0
    Q = band.from_u(V)
    assert np.abs(scan_G(prob, Q[:, 0], Q[:, 1])).max() < 1e-12
    d, _ = on_curves(prob, band, Q, [np.c_[main.T1, main.T2]], 0.02)
    assert d.max() < 1e-10 * band.T[1]
    far, _ = correct_onto(prob, band, U + 0.05 * n, n, 1e-3)            # too far for the reach: no zero found
    assert np.all(np.isnan(far))


def test_follow_reproduces_the_scan_branch(chain_family):
    """A curve followed from one point of a scan branch holds every point of that branch (to round-off)."""
    prob, band, _, main = chain_family
    P = np.c_[main.T1, main.T2]
    tr = follow(prob, band, band.to_u(P[len(P) // 2:len(P) // 2 + 1]), 1 / 150)
    assert len(tr) == 1 and tr[0].ends[0] in ("window edge", "closed loop")
    Q = np.asarray(tr[0].P)
    assert np.abs(scan_G(prob, Q[:, 0], Q[:, 1])).max() < 1e-12
    d, _ = on_curves(prob, band, P[band.contains(P)], [Q], 0.02)
    assert d.max() < 1e-9 * band.T[1], d.max()
    # a second seed on the same curve is skipped
    assert len(follow(prob, band, band.to_u(P[[len(P) // 2, len(P) // 2 + 3]]), 1 / 150)) == 1
