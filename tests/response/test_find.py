"""One response from a guess (plbar.response): against the path points, the batched orbit/energy code,
and the fallback and error paths."""

import numpy as np
import pytest

import plbar
from plbar.response import find as response
from plbar.response import damping
from plbar.errors import InputError
from plbar.response import orbits
from plbar.response import NoResponseError, find_response


def _well_conditioned(res, every=5):
    """Path points away from folds in T (where T1 at fixed T is ill-conditioned), with their T."""
    out = []
    for b in res.branches:
        if len(b) < 5:
            continue
        dT = np.gradient(b.T) / np.hypot(np.gradient(b.T1), np.gradient(b.T2))
        for k in range(2, len(b) - 2, every):
            if abs(dT[k]) > 0.2:
                out.append((b, k))
    return out


def test_finds_every_path_point_from_a_perturbed_guess(default_result):
    prob = default_result.prob
    pts = _well_conditioned(default_result, every=3)
    assert len(pts) > 80
    for b, k in pts:
        r = find_response(prob, b.T[k], b.T1[k] * (1 + 1e-3))
        assert r.T1 == pytest.approx(b.T1[k], rel=1e-11, abs=1e-11)
        assert np.angle(np.exp(1j * (r.phi - b.phi[k]))) == pytest.approx(0, abs=1e-9)
        assert r.xi == pytest.approx(b.xi[k], rel=1e-9)
        assert r.dPL == pytest.approx(b.dPL[k], rel=1e-9)
        assert max(r.e1, r.e2, r.periodicity) < 1e-12
        assert r.v_impact > 0


def test_plain_python_orbit_matches_the_batched_code(default_result):
    """The scalar final evaluation (plbar._scalar) against plbar.orbit + plbar.energy on the same triplets."""
    prob = default_result.prob
    for b, k in _well_conditioned(default_result, every=11):
        r = find_response(prob, b.T[k], b.T1[k])
        orb = orbits(prob, [r.T1], [r.T2], [r.phi])
        d = damping(orb)
        assert np.allclose(r.eta0, orb.eta0[0], rtol=1e-10, atol=1e-12 * np.abs(orb.eta0).max())
        assert np.allclose(r.eta_s, orb.eta_s[0], rtol=1e-10, atol=1e-12 * np.abs(orb.eta_s).max())
        assert r.xi == pytest.approx(d.xi[0], rel=1e-10)
        assert r.dPL == pytest.approx(d.dPL[0], rel=1e-10)
        e1, e2 = orb.residuals()
        assert abs(e1[0]) < 1e-10 and abs(e2[0]) < 1e-10
        # the numpy final evaluation (used for large systems) gives the same
        k_small = response._lean(prob).small
        try:
            object.__setattr__(response._lean(prob), "small", None)
            r2 = find_response(prob, b.T[k], b.T1[k])
        finally:
            object.__setattr__(response._lean(prob), "small", k_small)
        assert r2.T1 == r.T1 and r2.xi == pytest.approx(r.xi, rel=1e-12) and r2.phi == pytest.approx(r.phi, abs=1e-12)


def test_response_is_admissible_and_its_orbit_is_consistent(default_result):
    prob = default_result.prob
    b = max(default_result.paths.branches, key=len)
    k = len(b) // 2
    r = find_response(prob, b.T[k], b.T1[k] * 1.001)
    assert plbar.response.check(r.orbit).ok[0] and b.adm.ok[k]
    x, v, _ = r.orbit.response(np.array([0.0]))
    assert np.allclose(x[0, 0], r.x0) and np.allclose(v[0, 0], r.xdot0)
    assert r.x0[-1] == 0 and r.xdot0[-1] == 0


def test_fe_system_both_final_paths_agree(fe_p2_coarse):
    prob = fe_p2_coarse.prob
    b = max(fe_p2_coarse.branches, key=len)
    k = len(b) // 2
    r = find_response(prob, b.T[k], b.T1[k] * (1 + 1e-4))
    assert r.T1 == pytest.approx(b.T1[k], rel=1e-9)
    assert r.xi == pytest.approx(b.xi[k], rel=1e-8)
    lean = response._lean(prob)
    small = lean.small
    try:
        object.__setattr__(lean, "small", None)          # the numpy path (systems above SMALL modes)
        r2 = find_response(prob, b.T[k], b.T1[k] * (1 + 1e-4))
    finally:
        object.__setattr__(lean, "small", small)
    assert r2.T1 == r.T1 and r2.xi == pytest.approx(r.xi, rel=1e-11) and r2.periodicity < 1e-12


def test_fallback_when_the_interpolant_is_poor(default_result):
    """Four nodes over a wide window: the interpolant's root fails the check, direct steps finish the job."""
    prob = default_result.prob
    b = max(default_result.paths.branches, key=len)
    k = len(b) // 2
    r = find_response(prob, b.T[k], b.T1[k] * 1.01, nodes=4, width=0.4)
    assert r.evaluations > 4
    assert r.T1 == pytest.approx(b.T1[k], rel=1e-11)


def test_no_response_near_the_guess_raises():
    prob = plbar.Case().problem()
    T = 0.9 * prob.system.T0[0] / 2          # short period, deep in a region without paths near this T1
    with pytest.raises(NoResponseError, match="no periodic response"):
        find_response(prob, T, 0.5 * T, width=1e-3 * T)


@pytest.mark.parametrize("args, match", [
    ((-1.0, 0.5), "T1_guess"), ((10.0, 10.0), "T1_guess"), ((10.0, 0.0), "T1_guess"),
    ((float("nan"), 1.0), "period T"), (("10", 1.0), "period T"),
])
def test_bad_input(args, match):
    prob = plbar.Case().problem()
    with pytest.raises(InputError, match=match):
        find_response(prob, *args)


def test_bad_problem_and_nodes():
    with pytest.raises(InputError, match="Problem"):
        find_response("chain", 10.0, 1.0)
    prob = plbar.Case().problem()
    with pytest.raises(InputError, match="nodes"):
        find_response(prob, 10.0, 1.0, nodes=2.5)
