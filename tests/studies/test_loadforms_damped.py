"""The load structure with Rayleigh damping (issue 21) against brute force: a full solve per load.

Finding: the paths in (T^I, T^II) survive damping.  The load enters the switch conditions only
through the complex contact response h(q) = ((K - W^2 M + i W C)^-1 q)_c, so every load with
h(q) != 0 has the reference paths, at the phase phi_ref + arg(h(q) / h_ref) (no longer just
phi mod pi: the shift is continuous), with Delta_PL scaled by |h(q) / h_ref|^2
(docs/load_structure.md section 9, plbar.studies.loads.damped).
"""

import numpy as np
import pytest

import plbar
from plbar.paths import find_paths
from plbar.response import check, coefficients, damping, orbits, phase
from plbar.studies.loads.forms import DampedLoadForms, load_forms

CASES = {
    "chain": plbar.Case(grid=(80, 80), rayleigh=plbar.rayleigh_from_ratio(0.02, 8.0, 12.0), signatures="paper"),
    "fe_p2": plbar.Case(model="fe", n=5, element="P2", mass="consistent", point_masses=((1.0, 0.3),),
                        load_points=((0.37, 1.0),), grid=(60, 60), rayleigh=(0.05, 0.01), signatures="paper"),
}


@pytest.fixture(scope="module", params=list(CASES))
def solved(request):
    case = CASES[request.param]
    res = plbar.solve(case)
    assert len(res.branches) > 0
    lf = load_forms(res.paths)
    assert isinstance(lf, DampedLoadForms)
    return request.param, case, res.paths, lf


def _h(prob, W, q):
    s = prob.system
    return np.array([np.linalg.solve(s.K - w * w * s.M + 1j * w * s.C, q)[-1] for w in W])


def test_paths_survive_damping_with_a_phase_shift(solved):
    """A full find_paths per load: the same (T1, T2), phi = phi_ref + arg(h / h_ref), Delta_PL ~ |h|^2."""
    name, case, paths, _ = solved
    prob = paths.prob
    ref = paths.points()
    h0 = _h(prob, ref.W, prob.q)
    rng = np.random.default_rng(7)
    shifts = []
    for q in (rng.standard_normal(prob.system.n), rng.standard_normal(prob.system.n)):
        bf = find_paths(prob.under(q), paths.domain, case.grid)
        o = bf.points()
        assert [len(b) for b in bf.branches] == [len(b) for b in paths.branches], name
        assert np.abs(o.T1 - ref.T1).max() < 1e-9 * ref.T.max() and np.abs(o.T2 - ref.T2).max() < 1e-9 * ref.T.max()
        r = _h(prob, o.W, q) / h0
        assert np.abs(np.angle(np.exp(1j * (o.phi - ref.phi)) / np.exp(1j * np.angle(r)))).max() < 1e-9
        d0, d = damping(ref), damping(o)
        assert np.abs(d.dPL / d0.dPL - np.abs(r) ** 2).max() < 1e-9
        shifts.append(np.abs(np.angle(np.exp(2j * np.angle(r))) / 2).max())
    # the shift is not 0 or pi as without damping: phi mod pi does depend on the load
    assert max(shifts) > 1e-2


def test_xi_dpl_and_phase_equal_brute_force(solved):
    """DampedLoadForms against the per-load periodicity solve at the path's (T1, T2), every point: 1e-9."""
    name, _, paths, lf = solved
    prob = paths.prob
    Q = np.random.default_rng(3).standard_normal((8, lf.n))
    xi, dpl, ph = lf.xi(Q), lf.dPL(Q), lf.phase(Q)
    for k, q in enumerate(Q):
        pq = prob.under(q)
        co = coefficients(pq, lf.T1, lf.T2)
        assert np.abs(np.angle(np.exp(2j * (phase(co) - ph[:, k])))).max() / 2 < 1e-9, name
        o = orbits(pq, lf.T1, lf.T2, ph[:, k], co=co)
        d = damping(o)
        assert np.abs(d.xi - xi[:, k]).max() < 1e-9 * d.xi.max(), name
        assert np.abs(d.dPL - dpl[:, k]).max() < 1e-9 * d.dPL.max(), name
        assert check(o).ok.all()                      # admissible at its own phase, like the reference
        assert np.all(o.contact_velocity(o.T2[:, None])[:, 0] > 0)


def test_reference_load_reproduces_the_solver(solved):
    _, _, paths, lf = solved
    xi = np.concatenate([b.xi for b in paths.branches])
    dpl = np.concatenate([b.dPL for b in paths.branches])
    assert np.abs(lf.xi(lf.q_ref) - xi).max() < 1e-12
    assert np.abs(lf.dPL(lf.q_ref) - dpl).max() < 1e-12 * dpl.max()
    assert np.abs(lf.phase(lf.q_ref) - np.mod(lf.phi, 2 * np.pi)).max() < 1e-12


def test_worst_load_bounds_random_loads_and_is_attained(solved):
    _, _, _, lf = solved
    w = lf.worst()
    R = np.random.default_rng(5).standard_normal((400, lf.n))
    assert np.all(lf.xi(R) <= w.xi[:, None] * (1 + 1e-9))
    att = np.array([lf.xi(w.q[i])[i] for i in range(len(lf))])
    assert np.abs(att - w.xi).max() < 1e-12 * w.xi.max()
    assert np.allclose(np.linalg.norm(w.q, axis=1), 1.0)


def test_element_maximum_bounds_dense_sampling(solved):
    _, _, _, lf = solved
    em = lf.element_max()
    s = np.linspace(1e-6, lf.x[-1], 3001)
    xs = lf.xi_point(s)
    best, at = em.best()
    assert np.all(best >= xs.max(axis=1) * (1 - 1e-10))
    assert np.abs(best - xs.max(axis=1)).max() < 1e-6 * best.max()
    assert np.abs(lf.xi_point(at[:, None].ravel())[np.arange(len(lf)), np.arange(len(lf))] - best).max() < 1e-12


def test_zero_contact_response_has_no_path(solved):
    _, _, paths, lf = solved
    s = paths.prob.system
    i = len(lf) // 2
    # a real load with h = 0 at point i: orthogonal to Re and Im of the contact row of H (two conditions)
    Hc = lf.H[i, -1, :]
    q = np.linalg.svd(np.stack([Hc.real, Hc.imag]))[2][-1]
    assert lf.no_path(q)[i] and lf.dPL(q)[i] < 1e-20 * lf.dPL(lf.q_ref)[i] + 1e-30
    assert not lf.no_path(lf.q_ref).any()
    assert s.damped
