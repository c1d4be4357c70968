"""The exact load structure (issue #12) against brute force: a full solve per load.

Cases: the paper's chain N = 5 and a P2 consistent-mass FE bar with a point
mass on the contact node.  "Brute force" is the per-load machinery of
``find_paths``: the full path solve (paths test), or the periodicity solve,
exact phase and Eq. (22) of that load at the path's ``(T1, T2)``.
"""

import numpy as np
import pytest

import plbar
from plbar.response import damping
from plbar.errors import InputError
from plbar.response.flow import gauss
from plbar.studies.loads.forms import load_forms
from plbar.response import orbits
from plbar.paths import find_paths
from plbar.response import scan_G as Gfield
from plbar.response import check, coefficients, phase
from plbar.model import with_load_vector as _with_q

CASES = {
    "chain": plbar.Case(grid=(60, 60), signatures="paper"),
    "fe_p2": plbar.Case(model="fe", n=5, element="P2", mass="consistent", point_masses=((1.0, 0.3),),
                        load_points=((0.37, 1.0),), grid=(60, 60), signatures="paper"),
}


@pytest.fixture(scope="module", params=list(CASES))
def solved(request):
    case = CASES[request.param]
    res = plbar.solve(case)
    assert len(res.branches) > 0
    return request.param, case, res.paths, load_forms(res.paths)


def _brute(prob, q, T1, T2):
    """xi, dPL and the residual coefficients of load q at (T1, T2): the full per-load solve."""
    pq = prob.under(q)
    co = coefficients(pq, T1, T2)
    d = damping(orbits(pq, T1, T2, phase(co), co=co))
    return d.xi, d.dPL, co


def _compare_paths(prob, ref, bf):
    """The brute-force paths against the reference ones.

    Returns the largest distance of a brute-force point from the reference zero set (first
    order: ``|G_ref| / |grad G_ref|``), of ``phi`` mod ``pi`` from the reference phase there, and
    the pointwise distance between matched points (nearest neighbours both ways).  Points of one
    solve without a partner in the other must sit on the admissibility boundary (a relative
    margin at round-off, where the accept/reject decision is round-off): those are counted.
    """
    cat = np.concatenate
    T1b, T2b = cat([b.T1 for b in bf.branches]), cat([b.T2 for b in bf.branches])
    phb = cat([b.phi for b in bf.branches])
    h = 1e-6
    g = Gfield(prob, T1b, T2b)
    gx = (Gfield(prob, T1b + h, T2b) - Gfield(prob, T1b - h, T2b)) / (2 * h)
    gy = (Gfield(prob, T1b, T2b + h) - Gfield(prob, T1b, T2b - h)) / (2 * h)
    normal = (np.abs(g) / np.hypot(gx, gy)).max()
    dphi = (np.abs(np.angle(np.exp(2j * (phb - phase(coefficients(prob, T1b, T2b)))))) / 2).max()
    A = np.c_[cat([b.T1 for b in ref.branches]), cat([b.T2 for b in ref.branches])]
    Bp = np.c_[T1b, T2b]
    d = np.sqrt(((A[:, None, :] - Bp[None, :, :]) ** 2).sum(-1))
    da, db = d.min(axis=1), d.min(axis=0)
    margin = lambda br: np.minimum(np.abs(cat([b.adm.min_reaction for b in br])),
                                   np.abs(cat([b.adm.max_gap for b in br])))
    lone_a, lone_b = da > 1e-7, db > 1e-7
    assert np.all(margin(ref.branches)[lone_a] < 1e-9) and np.all(margin(bf.branches)[lone_b] < 1e-9)
    point = max(da[~lone_a].max(initial=0.0), db[~lone_b].max(initial=0.0))
    return np.array([point, normal, dphi, lone_a.sum() + lone_b.sum()])


def _paths_for_random_loads(solved, count):
    name, case, paths, _ = solved
    prob = paths.prob
    rng = np.random.default_rng(12)
    worst = np.zeros(4)
    for _ in range(count):
        q = rng.standard_normal(prob.system.n)
        bf = find_paths(prob.under(q), paths.domain, case.grid)
        worst = np.maximum(worst, _compare_paths(prob, paths, bf))
    point, normal, dphi, lone = worst
    # the same zero set and phase to 1e-10; the continuation points themselves may slide along the
    # curve a little more (the corrector's round-off acts tangentially where |grad G| is small)
    assert normal < 1e-10 and dphi < 1e-10 and point < 1e-7, (name, worst)
    return worst


def test_paths_do_not_depend_on_the_load(solved):
    """Claim 1: the same (T1, T2) and phi mod pi for random load vectors (a full find_paths each)."""
    _paths_for_random_loads(solved, 2)


@pytest.mark.slow
def test_paths_do_not_depend_on_the_load_20(solved):
    _paths_for_random_loads(solved, 20)


def test_xi_and_dpl_equal_brute_force(solved):
    """Claim 2: xi_eq and Delta_PL from the quadratic forms = the full per-load solve, every point."""
    name, _, paths, lf = solved
    rng = np.random.default_rng(3)
    Q = rng.standard_normal((20, lf.n))
    xi, dpl = lf.xi(Q), lf.dPL(Q)
    for k, q in enumerate(Q):
        xb, db, co = _brute(paths.prob, q, lf.T1, lf.T2)
        assert np.abs(xi[:, k] - xb).max() < 1e-9, name
        assert np.abs(dpl[:, k] - db).max() < 1e-9 * db.max(), name
        assert np.abs(np.angle(np.exp(2j * (phase(co) - lf.phi)))).max() / 2 < 1e-9       # phi mod pi


def test_reference_load_reproduces_the_solver(solved):
    _, _, paths, lf = solved
    xi = np.concatenate([b.xi for b in paths.branches])
    dpl = np.concatenate([b.dPL for b in paths.branches])
    assert np.abs(lf.xi(lf.q_ref) - xi).max() < 1e-12
    assert np.abs(lf.dPL(lf.q_ref) - dpl).max() < 1e-12 * dpl.max()
    assert np.abs(lf.phase(lf.q_ref) - np.mod(lf.phi, 2 * np.pi)).max() < 1e-12


def test_phase_is_the_admissible_one_not_its_mirror(solved):
    """LoadForms.phase: the response of load q at the path's (T1, T2) and that phase is admissible and hits the wall
    moving towards it; at the phase half a period off (the mirror image: what phi mod pi gave) it moves away."""
    name, _, paths, lf = solved
    prob = paths.prob
    Q = np.random.default_rng(4).standard_normal((6, lf.n))
    ph = lf.phase(Q)
    for k, q in enumerate(Q):
        keep = ~lf.no_path(q)
        pq = prob.under(q)
        co = coefficients(pq, lf.T1, lf.T2)
        assert np.abs(np.angle(np.exp(2j * (phase(co) - ph[:, k])))).max() / 2 < 1e-9, name     # mod pi
        o = orbits(pq, lf.T1, lf.T2, ph[:, k], co=co)
        assert check(o).ok[keep].all(), name
        assert np.all(o.contact_velocity(o.T2[:, None])[keep, 0] > 0), name
        m = orbits(pq, lf.T1, lf.T2, ph[:, k] + np.pi)
        assert np.all(m.contact_velocity(m.T2[:, None])[keep, 0] < 0), name


def test_G_is_the_gram_matrix_of_unit_load_velocities(solved):
    """G = sum over states of int etadot_k^T Omega etadot_l (n independent periodic solves, quadrature)."""
    _, _, paths, lf = solved
    s = paths.prob.system
    idx = np.linspace(0, len(lf) - 1, 12).astype(int)
    sub = lf.take(idx)
    x, wt = gauss(400)
    vel = []
    for k in range(lf.n):
        o = orbits(_with_q(s, np.eye(lf.n)[k]), sub.T1, sub.T2, sub.phi)
        parts = []
        for st, span, w in ((1, o.T1, s.w1), (2, o.T2, s.w2)):
            tau = 0.5 * span[:, None] * (x + 1)
            _, v = o.state_I(tau) if st == 1 else o.state_II(tau)
            parts.append(v * np.sqrt(0.5 * span[:, None, None] * wt[None, :, None] * w))
        vel.append(np.concatenate([p.reshape(len(o), -1) for p in parts], axis=1))
    V = np.stack(vel, axis=1)                                            # (P, n, nodes * modes)
    G = np.einsum("pkm,plm->pkl", V, V)
    assert np.abs(G - sub.G).max() < 1e-10 * np.abs(G).max()
    lam = np.linalg.eigvalsh(sub.G)
    assert lam.min() > -1e-12 * lam.max()


def test_cross_integrals_polarisation_equals_quadrature(solved):
    """Gamma_ra: polarisation of the closed-form Psi = Gauss-Legendre on the exact modal velocities."""
    from plbar.studies.loads.forms import _m_vectors, _m_vectors_quadrature

    _, _, paths, _ = solved
    orb = paths.points()
    for st in (1, 2):
        a, b = _m_vectors(orb, st), _m_vectors_quadrature(orb, st)
        assert np.abs(a - b).max() < 1e-11 * np.abs(b).max()


def test_impact_loss_is_rank_one_through_the_contact_velocity(solved):
    """Delta_PL = v_c(T-)^2 / (2 (M^-1)_cc) and b is parallel to H e_c (every switch quantity goes through h)."""
    _, _, paths, lf = solved
    s = paths.prob.system
    orb = paths.points()
    _, v = orb.end()
    vc = v @ s.V2[-1]
    dpl = np.concatenate([b.dPL for b in paths.branches])
    assert np.abs(vc ** 2 / (2 * np.linalg.inv(s.M)[-1, -1]) - dpl).max() < 1e-12 * dpl.max()
    nb = np.linalg.norm(lf.b, axis=1)
    cos = np.abs(np.einsum("pi,pi->p", lf.b, lf.hc)) / np.where(nb > 0, nb, 1)
    assert np.abs(cos[nb > 1e-8 * nb.max()] - 1).max() < 1e-10


def test_worst_load_bounds_random_loads_and_is_attained(solved):
    """Claim 3: xi_worst >= xi of 10,000 random loads; xi(q*) by the full solve of q* = xi_worst."""
    name, _, paths, lf = solved
    w = lf.worst()
    assert np.all(w.rank == lf.n) and w.b_in_null.max() == 0.0
    rng = np.random.default_rng(5)
    xr = lf.xi(rng.standard_normal((10000, lf.n)))
    assert np.all(xr.max(axis=1) <= w.xi * (1 + 1e-12) + 1e-15), name
    for p in range(len(lf)):
        xb, _, _ = _brute(paths.prob, w.q[p], lf.T1[p:p + 1], lf.T2[p:p + 1])
        assert abs(xb[0] - w.xi[p]) < 1e-9, (name, p)


def test_worst_handles_a_singular_gram_matrix(solved):
    """A null direction of G outside null(b) is dropped by the rank cutoff and reported."""
    _, _, _, lf = solved
    sub = lf.take(np.arange(min(20, len(lf))))
    u = np.zeros(lf.n)
    u[0] = 1.0                                           # u_a = 0: orthogonal to b's direction e_a
    Pm = np.eye(lf.n) - np.outer(u, u)
    Gam = Pm @ sub.Gamma @ Pm
    Binv = np.linalg.inv(sub.B)
    G = np.einsum("pji,pjk,pkl->pil", Binv, Gam, Binv)
    f = {k: getattr(sub, k) for k in sub.__dataclass_fields__}
    f.update(Gamma=Gam, G=0.5 * (G + np.swapaxes(G, 1, 2)))
    sing = type(sub)(**f)
    w = sing.worst()
    assert np.all(w.rank == lf.n - 1) and w.b_in_null.max() < 1e-12
    xr = sing.xi(np.random.default_rng(1).standard_normal((2000, lf.n)))
    assert np.all(xr.max(axis=1) <= w.xi * (1 + 1e-9))
    assert np.abs(np.einsum("pp->p", sing.xi(w.q)) - w.xi).max() < 1e-9 * w.xi.max()


def test_zero_contact_response_has_no_path(solved):
    """h(q) = 0 (q = (K - W^2 M) u, u_c = 0): flagged, xi = 0, and the per-load solve has no phase there."""
    _, _, paths, lf = solved
    s = paths.prob.system
    p = len(lf) // 2
    W = 2 * np.pi / lf.T[p]
    q = (s.K - W ** 2 * s.M)[:, 0]
    assert lf.no_path(q)[p] and not lf.no_path(lf.q_ref).any()
    assert abs(lf.h(q)[p]) < 1e-12 * abs(lf.h_ref[p]) * np.linalg.norm(q)
    assert lf.xi(q)[p] < 1e-20
    _, _, co = _brute(paths.prob, q, lf.T1[p:p + 1], lf.T2[p:p + 1])
    _, _, cr = _brute(paths.prob, lf.q_ref, lf.T1[p:p + 1], lf.T2[p:p + 1])
    size = lambda c: np.abs([c.a1[0] / c.e1_scale[0], c.b1[0] / c.e1_scale[0], c.a2[0] / c.e2_scale[0],
                             c.b2[0] / c.e2_scale[0]]).max()
    assert size(co) < 1e-12 and size(cr) > 1e-3   # residuals vanish for every phi: no path point, no phase


def test_point_vectors_are_the_shape_functions(solved):
    _, _, paths, lf = solved
    L = paths.prob.bar.length
    s = np.r_[np.linspace(0, L, 97)[1:], 0.123 * L, L]
    Q = np.array([paths.prob.asm.load_vector(v) for v in s])
    assert np.abs(lf.point_vectors(s) - Q).max() < 1e-14
    assert np.abs(lf.xi_point(s) - lf.xi(Q)).max() < 1e-14


def test_element_maximum_is_exact(solved):
    """Claim 4: the per-element maximum is >= dense sampling and attained (ratio of polynomials)."""
    _, _, paths, lf = solved
    em = lf.element_max()
    t = np.linspace(0.0, 1.0, 2001)
    for k in range(em.left.size):
        dense = lf.xi_point(em.left[k] + t * (em.right[k] - em.left[k])).max(axis=1)
        assert np.all(dense <= em.xi[:, k] + 1e-14)
        assert np.all(em.xi[:, k] - dense <= 1e-6 * max(em.xi.max(), 1e-300))
    # attained: at its position, or (s = 0) as the limit of a force approaching the clamp
    L = em.right[-1]
    at = lf.xi_point(np.maximum(em.s.ravel(), 1e-9 * L)).reshape(len(lf), *em.s.shape)
    err = np.abs(np.einsum("ppe->pe", at) - em.xi)
    assert err[em.s > 0].max() < 1e-14
    assert np.all(err[em.s == 0] < 1e-6 * em.xi[em.s == 0] + 1e-300)


def test_truncated_model_is_refused():
    """With modes < n the paths depend on the load (residuals O(1)): load_forms refuses."""
    bar = plbar.uniform_bar(8, element="P1", mass="lumped", point_masses=((1.0, 0.3),))
    a = plbar.assemble(bar)
    prob = plbar.problem(plbar.bar_structure(bar, q=a.load_vector(0.3), asm=a), modes=4)
    paths = find_paths(prob, grid=(40, 40))
    assert paths.branches
    with pytest.raises(InputError, match="full modal model"):
        load_forms(paths)
    o = paths.points()
    o2 = orbits(prob.under(np.arange(1.0, 9.0)), o.T1, o.T2, o.phi)
    x, _, _ = o2.response(np.linspace(0, 1, 40)[None] * o2.T[:, None])
    assert np.max(np.abs(o2.residuals()[1]) / np.abs(x[..., -1]).max(axis=1)) > 1e-3
