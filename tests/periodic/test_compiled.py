"""The compiled chain (plbar.periodic.kernel) against independent references: the numpy flows, finite differences,
numpy's LU, the independent simulator."""


import numpy as np
import pytest

import plbar
from plbar.periodic import evaluate, from_motion, monodromy, orbit_at, polish, signature, zero_dwell
from plbar.periodic.solve import AMPLITUDE_SAMPLES
from plbar.periodic.chain import layout, state_data, switch_maps
from plbar.periodic.follow import correct, scale_of
from plbar.model import rayleigh_from_ratio
from plbar.motion import run, steady
from plbar.response import Forcing, Modes, psi, segment

SIGNATURES = ["1P", "1Z", "1PZ", "2PZ", "2PZZ", "3PPZZ"]


@pytest.fixture(scope="module", params=["undamped", "damped", "contact-loaded"])
def prob(request):
    """The default chain; with Rayleigh damping 5 %; damped and loaded on the contact DOF too (``r_q != 0``)."""
    if request.param == "damped":
        return plbar.Case(rayleigh=rayleigh_from_ratio(0.05, 6.0, 14.0)).problem()
    if request.param == "contact-loaded":
        return plbar.Case(load_nodes=((1, 1.0), (5, 0.5)), rayleigh=rayleigh_from_ratio(0.05, 6.0, 14.0)).problem()
    return plbar.Case().problem()


def reference(prob, sig, T, X):
    """The chain by the numpy flows of plbar.response (:func:`plbar.response.segment`, damped modes by
    plbar.response.damped): ``F``, zero-dwell margins, switch scales, contact velocities, segment end states."""
    E, G = switch_maps(prob)
    nz, q, _ = layout(prob, sig)
    W, phi = 2 * np.pi / T, X[-1]
    z, t, col = X[:nz].copy(), 0.0, 0
    F, zero, scale, vimp, ends = [], [], [], [], []
    for positive in sig.dwell:
        for s in (1, 2):
            w, f, c, rq, zeta, cv = state_data(prob, s)
            m = w.size
            cv = np.zeros(m) if cv is None else cv
            if s == 1 and not positive:
                zero.append(c @ z[:m] + cv @ z[m:] + rq * np.cos(W * t - phi))
            else:
                tau = X[nz + col]
                e, v = segment(w, f, W, t, tau, z[:m], z[m:], np.cos(phi), np.sin(phi), zeta=zeta)
                z, t, col = np.concatenate([e, v]), t + tau, col + 1
                F.append(c @ e + cv @ v + rq * np.cos(W * t - phi))
                scale.append(np.abs(c) @ np.abs(e) + np.abs(cv) @ np.abs(v) + abs(rq))
                ends.append(z)
                if s == 2:
                    vimp.append(np.asarray(prob.system.gap_row, float) @ v)
            z = (E if s == 1 else G) @ z
    F = np.concatenate([F, [np.sum(X[nz:nz + q]) - sig.m * T], z - X[:nz]])
    return F, np.array(zero), np.array(scale), np.array(vimp), ends


def random_point(prob, sig, seed):
    rng = np.random.default_rng(seed)
    nz, q, _ = layout(prob, sig)
    X = np.concatenate([rng.normal(size=nz), rng.uniform(0.3, 3.0, q), [rng.uniform(0, 2 * np.pi)]])
    return X, float(np.sum(X[nz:nz + q]) / sig.m * rng.uniform(0.95, 1.05))


@pytest.mark.parametrize("text", SIGNATURES)
def test_chain_against_the_numpy_flows(prob, text):
    sig = signature(text)
    for seed in range(3):
        X, T = random_point(prob, sig, seed)
        ch = evaluate(prob, sig, T, X, jac=False)
        F, zero, scale, vimp, ends = reference(prob, sig, T, X)
        size = np.max(np.abs(X[:-1])) + np.max(np.abs(np.concatenate(ends)))
        assert np.max(np.abs(ch.F - F)) <= 1e-13 * size
        assert np.allclose(ch.zero_margins, zero, rtol=0, atol=1e-13 * size)
        assert np.allclose(ch.switch_scale, scale, rtol=1e-13)
        assert np.allclose(ch.v_impact, vimp, rtol=0, atol=1e-13 * size)
        for s, z in zip(ch.segments, ends):
            assert np.allclose(s.z1, z, rtol=0, atol=1e-13 * size)
        nz = 2 * prob.system.w1.size
        zs = max(np.abs(X[:nz]).max(), 1e-300)
        rel = np.max(np.abs(F) / np.concatenate([np.maximum(scale, 1e-300), [T], np.full(nz, zs)]))
        assert ch.residual == pytest.approx(rel, rel=1e-9)
        assert np.array_equal(evaluate(prob, sig, T, X).F, ch.F)        # with or without the Jacobian


@pytest.mark.parametrize("text", SIGNATURES)
def test_jacobian_by_central_differences(prob, text):
    sig = signature(text)
    for seed in range(2):
        X, T = random_point(prob, sig, 10 + seed)
        J = evaluate(prob, sig, T, X).J
        fd = np.empty_like(J)
        for j in range(X.size):
            h = 1e-6 * max(1.0, abs(X[j]))
            e = np.zeros(X.size)
            e[j] = h
            fd[:, j] = (evaluate(prob, sig, T, X + e, jac=False).F
                        - evaluate(prob, sig, T, X - e, jac=False).F) / (2 * h)
        assert np.max(np.abs(fd - J)) <= 1e-6 * np.abs(J).max()


def test_polished_orbits_have_residuals_at_round_off(prob):
    """Orbits from the closed-form zero-dwell class and from a simulated motion, polished: the numpy flows give
    relative residuals at round-off too (the polish is not fooled by its own evaluation)."""
    orbs = [o for T in (7.0, 8.5, 11.0) for o in zero_dwell(prob, T)]
    Ts = [8.4, 10.0]
    r = run(prob, Ts, periods=800, record=60)
    st = steady(r)
    for b in np.flatnonzero(st.kind == 0):
        orbs.append(from_motion(prob, r, int(b), int(st.m[b])))
    assert len(orbs) >= 7 and any(o.sig.dwell[0] for o in orbs)
    for o in orbs:
        o = polish(prob, o.sig, o.T, o.X)
        F, _, scale, _, _ = reference(prob, o.sig, o.T, o.X)
        nz = 2 * prob.system.w1.size
        sc = np.concatenate([np.maximum(scale, 1e-300), [o.T], np.full(nz, np.abs(o.X[:nz]).max())])
        assert o.residual <= 1e-12 and np.max(np.abs(F) / sc) <= 1e-12


def test_energy_against_the_numpy_integrals(prob):
    """Psi sums (xi, xi_w, the viscous loss) and the contact amplitude of orbits of several signatures against
    plbar.response.psi and samples of plbar.response.segment."""
    sy = prob.system
    m2 = sy.w2.size
    for text in ("1Z", "1PZ", "2PZZ"):
        sig = signature(text)
        X, T = random_point(prob, sig, 20)
        o = orbit_at(prob, sig, T, X)
        W = 2 * np.pi / T
        den = kin = visc = 0.0
        amp = 0.0
        for seg in o.chain.segments:
            w, f, _, _, zeta, _ = state_data(prob, seg.state)
            m = w.size
            p, _ = psi(Modes(w, f, zeta), Forcing.at(W, o.phi), seg.t0, seg.tau, seg.z0[:m], seg.z0[m:])
            den, kin = den + p @ w, kin + p.sum()
            visc += 0.0 if zeta is None else p @ (2 * zeta * w)
            if seg.state == 2:
                u = np.linspace(0.0, seg.tau, AMPLITUDE_SAMPLES)[:, None]
                e, _ = segment(sy.w2, prob.f2, W, seg.t0, u, seg.z0[:m2], seg.z0[m2:], np.cos(o.phi), np.sin(o.phi),
                               zeta=zeta)
                amp = max(amp, np.abs(e @ sy.gap_row).max())
        assert o.xi == pytest.approx(o.dPL / (2 * den), rel=1e-12)
        assert o.xi_w == pytest.approx(o.dPL / (2 * W * kin), rel=1e-12)
        assert o.viscous == pytest.approx(visc, rel=1e-12, abs=1e-15 * kin)
        assert o.amplitude == pytest.approx(amp, rel=1e-12)


def test_corrector_lands_on_the_curve_and_the_plane(prob):
    """A Newton correction from off the curve: residuals at round-off, on the plane through the predicted point."""
    o = zero_dwell(prob, 8.5)[0]
    Y = np.concatenate([o.X, [o.T]])
    S = scale_of(prob, o.sig, o.X, o.T)
    t = np.random.default_rng(3).normal(size=Y.size)
    t /= np.linalg.norm(t)
    Yp = Y + 1e-3 * t * S
    c = correct(prob, o.sig, Yp, t, S)
    assert c is not None and c.residual <= 1e-12
    assert abs(t @ ((np.concatenate([c.X, [c.T]]) - Yp) / S)) <= 1e-12
    assert np.max(np.abs(np.concatenate([c.X, [c.T]]) - Y) / S) <= 1e-2


def test_lu_and_tangent_against_numpy():
    from plbar.periodic.kernel.newton import lu_factor, lu_solve, tangent
    from plbar.util.jit import python_twin

    lu_factor, lu_solve, tangent = map(python_twin, (lu_factor, lu_solve, tangent))

    rng = np.random.default_rng(0)
    for n in (2, 5, 13, 40):
        A = rng.normal(size=(n, n))
        A[0, 0] = 0.0                                  # a pivot must be chosen
        b = rng.normal(size=n)
        LU, piv, x = A.copy(), np.empty(n, np.int64), b.copy()
        assert lu_factor(LU, piv)
        lu_solve(LU, piv, x)
        assert np.allclose(x, np.linalg.solve(A, b), rtol=1e-10, atol=1e-12)
    assert not lu_factor(np.zeros((3, 3)), np.empty(3, np.int64))
    Ja, S, c = rng.normal(size=(7, 8)), rng.uniform(0.5, 2, 8), rng.normal(size=8)
    t = np.empty(8)
    assert tangent(Ja, S, c, t)
    null = np.linalg.svd(Ja * S)[2][-1]
    assert np.allclose(t, np.sign(c @ null) * null, atol=1e-12) and c @ t > 0


def chain_map(prob, o, z0):
    """The stroboscopic map of ``o`` from the state I ``z0`` (its phase): the durations solved from the switching
    conditions alone (Newton), the state just after the last impact carried in state I to ``m T`` by the numpy
    flows (backwards where the impact comes late: the map's continuation the saltation linearises)."""
    sig, T = o.sig, o.T
    nz, q, _ = layout(prob, sig)
    X = o.X.copy()
    X[:nz] = z0
    for _ in range(30):
        ch = evaluate(prob, sig, T, X)
        d = np.linalg.solve(ch.J[:q, nz:nz + q], -ch.F[:q])
        X[nz:nz + q] += d
        if np.abs(d).max() <= 1e-15 * T:
            break
    ch = evaluate(prob, sig, T, X, jac=False)
    after, t = ch.F[q + 1:] + z0, float(np.sum(X[nz:nz + q]))
    w, f, _, _, zeta, _ = state_data(prob, 1)
    e, v = segment(w, f, 2 * np.pi / T, t, sig.m * T - t, after[:nz // 2], after[nz // 2:], np.cos(X[-1]),
                   np.sin(X[-1]), zeta=zeta)
    return np.concatenate([e, v])


@pytest.mark.parametrize("T, text", [(8.4, "2PZ"), (10.0, "1P")])
def test_damped_monodromy_against_the_map_by_central_differences(T, text):
    """Rayleigh damping 5 %: the monodromy against central differences of the stroboscopic map (the chain's
    switching conditions and the numpy flows), on the orbits the damped bar settles on from rest.  (The
    simulator's map is no reference here: where a perturbed impact comes after ``m T`` its state at ``m T`` is
    free, and the damper's force on the other DOFs jumps at the impact, so its state I projection is not the
    map's continuation.)"""
    prob = plbar.Case(rayleigh=rayleigh_from_ratio(0.05, 6.0, 14.0)).problem()
    r = run(prob, [T], periods=800, record=60)
    o = from_motion(prob, r, 0, len(text) - 1)
    assert str(o.sig) == text
    assert np.allclose(chain_map(prob, o, o.z0), o.z0, rtol=0, atol=1e-12 * np.abs(o.z0).max())
    M = monodromy(prob, o.sig, o.T, o.phi, o.chain)
    h = 1e-6 * np.abs(o.z0).max()
    fd = np.column_stack([(chain_map(prob, o, o.z0 + h * e) - chain_map(prob, o, o.z0 - h * e)) / (2 * h)
                          for e in np.eye(o.z0.size)])
    assert np.allclose(fd, M, rtol=0, atol=1e-7 * np.abs(M).max())


def test_the_cache_key_covers_every_source_the_kernel_is_built_from():
    """The entry points close over a hash of this subpackage and of the motion kernel's sources; every module the
    kernel imports from must be one of them (numba freezes what it imports)."""
    from plbar.periodic.kernel import stamp
    from plbar.motion.kernel import jit

    from kernel_sources import assert_imports_covered

    assert_imports_covered(stamp.SOURCES[0].parent, [*stamp.SOURCES, *jit.SOURCES])
