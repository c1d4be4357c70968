"""The two-state structure record: any contact row, checked against an integrator written here.

A contact row that is not the last DOF is solved in the contact coordinates of
:func:`plbar.model.contact_coordinates`.  These tests do not trust that reduction: the periodic responses
plbar finds are mapped back to the structure's own DOFs and replayed with scipy's ``solve_ivp`` in those
DOFs, the stuck phase with a Lagrange multiplier on ``r . x = 0``, the impact as the plastic impulse along
``M^-1 r``; the orbit must close, the reaction push, the gap stay open, and the impact lose ``Delta_PL``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import plbar
from plbar.errors import InputError
from plbar.model import contact_coordinates
from plbar.paths import default_domain, find_paths


def _chain_K(n: int, clamp_left: bool, clamp_right: bool) -> np.ndarray:
    K = np.zeros((n, n))
    for i in range(n - 1):
        K[np.ix_([i, i + 1], [i, i + 1])] += [[1.0, -1.0], [-1.0, 1.0]]
    K[0, 0] += clamp_left
    K[-1, -1] += clamp_right
    return K


def two_bodies() -> plbar.Structure:
    """A clamped chain of 3 masses whose free end hits the first of 2 masses of a second clamped chain.

    ``u = x_2 - x_3 <= 0``: the first body's end cannot pass the second body's face; the load is on DOF 0.
    """
    K = np.zeros((5, 5))
    K[:3, :3] = _chain_K(3, True, False)
    K[3:, 3:] = 2.0 * _chain_K(2, False, True)
    M = np.diag([1.0, 1.0, 0.5, 0.7, 1.0])
    r = np.array([0.0, 0.0, 1.0, -1.0, 0.0])
    q = np.array([1.0, 0.0, 0.0, 0.0, 0.0])
    return plbar.Structure(M, K, r, q, x=np.arange(5.0))


def replay(st: plbar.Structure, x0, v0, T, phi, durations):
    """The pairs ``(stuck tau^I, free tau^II)`` of ``durations`` from ``(x0, v0)`` at the start of a stuck phase, in
    the structure's DOFs (scipy only), each pair ending in a plastic impact: the end state, the smallest reaction
    and gap (relative) and the energy the impacts took."""
    M, K, r, q = st.M, st.K, st.contact, st.q
    Mi = np.linalg.inv(M)
    W, n = 2 * np.pi / T, M.shape[0]

    def lam(t, x):
        f = q * np.cos(W * t - phi) - K @ x
        return -(r @ Mi @ f) / (r @ Mi @ r)

    def stuck(t, z):
        return np.concatenate([z[n:], Mi @ (q * np.cos(W * t - phi) - K @ z[:n] + r * lam(t, z[:n]))])

    def free(t, z):
        return np.concatenate([z[n:], Mi @ (q * np.cos(W * t - phi) - K @ z[:n])])

    opts = dict(rtol=1e-12, atol=1e-13, dense_output=True, method="DOP853")
    z, t, loss, reaction, gap = np.concatenate([x0, v0]), 0.0, 0.0, [], []
    for tI, tII in np.asarray(durations).reshape(-1, 2):
        if tI > 0:
            a = solve_ivp(stuck, (t, t + tI), z, **opts)
            reaction += [-lam(u, a.sol(u)[:n]) for u in np.linspace(t, t + tI, 101)]   # the stop's push
            z, t = a.y[:, -1], t + tI
        b = solve_ivp(free, (t, t + tII), z, **opts)
        gap += list(-(r @ b.sol(np.linspace(t, t + tII, 201)[1:-1])[:n]))            # -u >= 0 while free
        z, t = b.y[:, -1], t + tII
        v = z[n:]
        vp = v - Mi @ r * (r @ v) / (r @ Mi @ r)                  # plastic impact: u' = 0 after
        loss += 0.5 * v @ M @ v - 0.5 * vp @ M @ vp
        z = np.concatenate([z[:n], vp])
    reaction, gap = np.array(reaction), np.array(gap)
    rel = (lambda a: a.min() / np.abs(a).max() if a.size and np.abs(a).max() > 0 else 0.0)
    return z[:n], z[n:], rel(reaction), rel(gap), loss


def _points(prob, k=3):
    paths = find_paths(prob, default_domain(prob), (80, 80))
    assert paths.branches, "no periodic response of the paper's class was found"
    out = []
    for b in paths.branches:
        o, d = b.orbits, b.damping
        for i in np.unique(np.linspace(0, len(o) - 1, k).astype(int)):
            out.append((o, d, int(i)))
    return out


def test_contact_coordinates_of_the_bar_are_its_dofs():
    """A contact row ``e_{n-1}`` (every bar) transforms nothing: the matrices are the same objects."""
    prob = plbar.Case(model="fe", n=6).problem()
    y = contact_coordinates(prob.structure)
    assert y.identity and y.M is prob.structure.M and y.K is prob.structure.K


def test_contact_coordinates_identities():
    """``B^T r = e_u`` (the impulse acts on the contact coordinate alone) and ``r . (B y) = y_u``."""
    st = two_bodies()
    y = contact_coordinates(st)
    np.testing.assert_allclose(y.B.T @ st.contact, np.eye(5)[-1], atol=1e-15)
    np.testing.assert_allclose(y.M, y.B.T @ st.M @ y.B, rtol=1e-15)
    z = np.random.default_rng(1).normal(size=5)
    assert st.contact @ (y.B @ z) == pytest.approx(z[-1], abs=1e-14)


def test_a_difference_contact_replays_in_the_structures_own_dofs():
    """Every sampled response of a contact between two bodies closes after one period in physical DOFs."""
    st = two_bodies()
    prob = plbar.problem(st)
    checked = 0
    for o, d, i in _points(prob):
        x0 = st.physical(prob.system.embed(prob.system.V1 @ o.eta0[i]))
        v0 = st.physical(prob.system.embed(prob.system.V1 @ o.v0[i]))
        assert st.contact @ x0 == pytest.approx(0.0, abs=1e-12)
        xe, ve, reaction, gap, loss = replay(st, x0, v0, o.T[i], o.phi[i], [o.T1[i], o.T2[i]])
        scale = np.max(np.abs(x0)) + np.max(np.abs(v0))
        np.testing.assert_allclose(xe, x0, atol=1e-8 * scale)
        np.testing.assert_allclose(ve, v0, atol=1e-8 * scale)
        assert reaction >= -1e-8 and gap >= -1e-8
        assert loss == pytest.approx(d.dPL[i], rel=1e-7)
        checked += 1
    assert checked >= 3


def test_every_signature_of_a_difference_contact_replays():
    """``plbar.solve`` of a bare structure: a point of every branch of every signature (plastic: P and Z pairs)
    closes after its ``m`` periods in the structure's own DOFs, with the loss plbar gives."""
    st = two_bodies()
    res = plbar.solve(st)
    assert res.case.model == "structure" and res.summary()["case"]["structure"] == st.fingerprint
    sigs = {}
    for b in res.branches:
        sigs.setdefault(b.sig.letters + str(b.sig.m), b)
    assert len(sigs) >= 3, sorted(sigs)
    for b in sigs.values():
        o = b.orbits[len(b.orbits) // 2]
        y0, w0 = o.start
        x0, v0 = st.physical(y0), st.physical(w0)
        xe, ve, reaction, gap, loss = replay(st, x0, v0, o.T, o.phi, o.durations)
        scale = np.max(np.abs(x0)) + np.max(np.abs(v0))
        np.testing.assert_allclose(np.concatenate([xe, ve]), np.concatenate([x0, v0]), atol=1e-7 * scale,
                                   err_msg=b.describe())
        assert reaction >= -1e-7 and gap >= -1e-7, b.describe()
        assert loss == pytest.approx(o.dPL, rel=1e-6), b.describe()


def test_the_order_of_the_dofs_does_not_matter():
    """The paper's chain with its DOFs reversed (contact row ``e_0``) has the same responses and ``xi_eq``."""
    prob = plbar.Case().problem()
    st = prob.structure
    p = np.arange(st.n)[::-1]
    rev = plbar.Structure(st.M[np.ix_(p, p)], st.K[np.ix_(p, p)], st.contact[p], st.q[p], x=st.x[p])
    a, b = (find_paths(pr, default_domain(prob), (80, 80)) for pr in (prob, plbar.problem(rev)))
    np.testing.assert_allclose(plbar.problem(rev).system.w2, prob.system.w2, rtol=1e-14)
    assert len(a.branches) == len(b.branches)
    for u, v in zip(a.branches, b.branches):
        np.testing.assert_allclose(v.orbits.T1, u.orbits.T1, rtol=1e-9)     # roots converged to ~1e-12
        np.testing.assert_allclose(v.damping.xi, u.damping.xi, rtol=1e-10, atol=1e-10 * u.damping.xi.max())


@pytest.mark.parametrize("bad, match", [
    (dict(contact=np.zeros(5)), "contact row"),
    (dict(contact=np.ones(4)), "shape"),
    (dict(restitution=2.0), "restitution"),
    (dict(rayleigh=(-1.0, 0.0)), "rayleigh|alpha|damping"),
])
def test_bad_structures_are_refused(bad, match):
    st = two_bodies()
    kw = dict(M=st.M, K=st.K, contact=st.contact, q=st.q) | bad
    with pytest.raises(InputError, match=match):
        plbar.Structure(**kw)


def test_a_structure_carries_its_own_load():
    with pytest.raises(InputError, match="carries its own"):
        plbar.problem(two_bodies(), restitution=0.5)
