"""Damped closed-form flows (issue 21): against solve_ivp, the textbook steady state, and the undamped limit.

Every mode obeys ``eta'' + 2 zeta w eta' + w^2 eta = f cos(W (ts + u) - phi)``; under-, critically and
over-damped modes, at and away from resonance, must agree with DOP853 (rtol 1e-12) to 1e-10, and the
periodic steady state of each state alone must be the textbook ``|H| f`` with phase lag
``atan2(2 zeta w W, w^2 - W^2)`` to 1e-12.
"""

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

import plbar
from plbar.model import chain, node, point, problem, uniform_bar
from plbar.response import Forcing, Modes, flow
from plbar.response.damped import kernels as dkernels

ODE = dict(method="DOP853", rtol=1e-12, atol=1e-15)
#: (w, zeta): under-damped, exactly critical, either side of critical by 1e-9, over-damped, strongly over-damped
MODES = [(1.3, 0.02), (1.3, 0.5), (1.3, 1.0), (1.3, 1 - 1e-9), (1.3, 1 + 1e-9), (1.3, 1.7), (2.0, 30.0)]
F, TS, PHI, E0, V0 = 0.7, 0.4, 1.1, 0.3, -0.2


def _mode_ivp(w, z, W, taus):
    rhs = lambda t, y: [y[1], -w * w * y[0] - 2 * z * w * y[1] + F * np.cos(W * (TS + t) - PHI)]  # noqa: E731
    return solve_ivp(rhs, (0, taus[-1]), [E0, V0], t_eval=taus, **ODE).y


@pytest.mark.parametrize("w,z", MODES)
@pytest.mark.parametrize("W", [0.9, 1.3, 2.5])
def test_single_mode_against_solve_ivp(w, z, W):
    taus = np.linspace(0.0, 7.3, 12)[1:]
    e, v = flow.segment(w, F, W, TS, taus, E0, V0, np.cos(PHI), np.sin(PHI), zeta=z)
    ref = _mode_ivp(w, z, W, taus)
    scale = np.abs(ref).max()
    assert np.abs(e - ref[0]).max() < 1e-10 * scale
    assert np.abs(v - ref[1]).max() < 1e-10 * scale
    assert np.all(np.isfinite(e)) and np.all(np.isfinite(v))


def test_short_segments_and_exact_resonance_are_finite_and_accurate():
    """The kernel series (tiny tau) and ``zeta = 0`` at ``W = w`` (the limit ``tau sin(w tau) / (2 w)``)."""
    tau = np.array([1e-3, 0.3, 2.0])
    C, S, Cp = dkernels(1.3, 1.3, tau, 0.0)
    C0, S0, Cp0 = flow.kernels(1.3, 1.3, tau)
    for a, b in ((C, C0), (S, S0), (Cp, Cp0)):        # to round-off of the kernels' scale tau / w
        assert np.all(np.abs(a - b) <= 1e-14 * tau)
    assert np.allclose(C, tau * np.sin(1.3 * tau) / 2.6, rtol=1e-13, atol=0)
    tau = np.array([1e-12, 1e-6])                     # from rest: C = tau^2 / 2, S = W tau^3 / 6, C' = tau
    for z in (0.0, 0.3, 1.0, 5.0):
        C, S, Cp = dkernels(1.3, 0.9, tau, z)
        assert np.allclose(C, tau ** 2 / 2, rtol=1e-5, atol=0)
        assert np.allclose(S, 0.9 * tau ** 3 / 6, rtol=1e-5, atol=0)
        assert np.allclose(Cp, tau, rtol=1e-5, atol=0)


def test_zeta_zero_reproduces_the_undamped_flows():
    w = np.array([0.3, 1.0, 1.3, 1.3 + 1e-9, 2.0, 7.0])
    tau = np.linspace(0.0, 9.0, 40)[:, None]
    args = (w, F, 1.3, TS, tau, E0, V0, np.cos(PHI), np.sin(PHI))
    e0, v0 = flow.segment(*args)
    e1, v1 = flow.segment(*args, zeta=np.zeros_like(w))
    assert np.abs(e1 - e0).max() < 1e-12 * np.abs(e0).max()
    assert np.abs(v1 - v0).max() < 1e-12 * np.abs(v0).max()
    for a, b in zip(flow.flow_matrix(w, tau), flow.flow_matrix(w, tau, np.zeros_like(w))):
        assert np.abs(a - b).max() < 1e-13 * np.abs(a).max()
    p0, _ = flow.psi(Modes(w, F), Forcing.at(0.9, PHI), TS, 7.3, E0, V0)
    p1, _ = flow.psi(Modes(w, F, np.zeros_like(w)), Forcing.at(0.9, PHI), TS, 7.3, E0, V0)
    assert np.allclose(p1, p0, rtol=1e-12, atol=0)


@pytest.mark.parametrize("w,z", MODES + [(0.9, 1e-6)])
@pytest.mark.parametrize("W", [0.9, 1.3])
def test_psi_against_adaptive_quadrature(w, z, W):
    """``Psi = int eta'^2`` (Eq. (20)) in closed form, or Gauss-Legendre where it would cancel: 1e-12."""
    tau = 7.3

    def v2(u):
        return float(flow.segment(w, F, W, TS, u, E0, V0, np.cos(PHI), np.sin(PHI), zeta=z)[1]) ** 2

    pts = [0, 1e-4, 1e-3, 1e-2, 0.05, 0.1, 0.5, 1, 2, 4, tau]
    ref = sum(quad(v2, a, b, epsabs=0, epsrel=1e-13, limit=400)[0] for a, b in zip(pts[:-1], pts[1:]))
    p, closed = flow.psi(Modes(w, F, z), Forcing.at(W, PHI), TS, tau, E0, V0)
    assert abs(float(p) - ref) < 1e-12 * ref
    if z == 1.0 or abs(z - 1) < 1e-8 or z < 1e-5 and W == w:
        assert not closed            # the closed form cancels there: quadrature took over


def _state_ode(M, C, K, q, W, y0, taus):
    Minv = np.linalg.inv(M)
    n = M.shape[0]

    def rhs(t, y):
        x, v = y[:n], y[n:]
        return np.r_[v, Minv @ (q * np.cos(W * t) - K @ x - C @ v)]

    return solve_ivp(rhs, (0, taus[-1]), y0, t_eval=taus, **ODE).y


@pytest.mark.parametrize("beta", [0.02, 0.3])
def test_whole_states_against_solve_ivp(beta):
    """Both states of a damped FE bar (``beta = 0.3``: the high modes over-damped) in physical coordinates."""
    bar = uniform_bar(6, element="P2", mass="consistent")
    prob = problem(bar, point(0.37), rayleigh=(0.05, beta))
    s = prob.system
    assert (s.zeta2 > 1).any() == (beta > 0.1)
    W, T = 2.1, 2 * np.pi / 2.1
    T1 = 0.8
    rng = np.random.default_rng(3)
    eta0, v0 = rng.normal(size=s.w1.size), rng.normal(size=s.w1.size)
    orb = plbar.response.Orbits(prob, np.array([T1]), np.array([T - T1]), np.array([0.0]), eta0[None], v0[None],
                                rng.normal(size=(1, s.n)), rng.normal(size=(1, s.n)))
    taus = np.linspace(0, T1, 6)[1:]
    e, v = orb.state_I(taus[None])
    C, M, K, q = s.C, s.M, s.K, prob.q
    ref = _state_ode(M[:-1, :-1], C[:-1, :-1], K[:-1, :-1], q[:-1], W, np.r_[s.V1 @ eta0, s.V1 @ v0], taus)
    assert np.abs(e[0] @ s.V1.T - ref[:s.n - 1].T).max() < 1e-10 * np.abs(ref).max()
    assert np.abs(v[0] @ s.V1.T - ref[s.n - 1:].T).max() < 1e-10 * np.abs(ref).max()
    taus = np.linspace(0, T - T1, 6)[1:]
    e, v = orb.state_II(taus[None])
    y0 = np.r_[s.V2 @ orb.eta_s[0], s.V2 @ orb.v_s[0]]
    # the load's clock runs on from T1 in state II
    sol = solve_ivp(lambda t, y: np.r_[y[s.n:], np.linalg.solve(M, q * np.cos(W * t) - K @ y[:s.n] - C @ y[s.n:])],
                    (T1, T), y0, t_eval=T1 + taus, **ODE).y
    assert np.abs(e[0] @ s.V2.T - sol[:s.n].T).max() < 1e-10 * np.abs(sol).max()
    assert np.abs(v[0] @ s.V2.T - sol[s.n:].T).max() < 1e-10 * np.abs(sol).max()


def _steady_state(w, z, f, W, phi):
    """The T-periodic state of each mode from the exact one-period flow: (I - Phi(T)) z0 = forced part."""
    T = 2 * np.pi / W
    p11, p12, p21, p22 = flow.flow_matrix(w, T, z)
    ec, es, vc, vs = flow.forced_coeffs(w, f, W, 0.0, T, z)
    Fe, Fv = ec * np.cos(phi) + es * np.sin(phi), vc * np.cos(phi) + vs * np.sin(phi)
    det = (1 - p11) * (1 - p22) - p12 * p21
    return ((1 - p22) * Fe + p12 * Fv) / det, (p21 * Fe + (1 - p11) * Fv) / det


@pytest.mark.parametrize("model", ["chain", "fe"])
def test_each_state_alone_has_the_textbook_steady_amplitude_and_phase_lag(model):
    """|H| f = f / sqrt((w^2 - W^2)^2 + (2 zeta w W)^2), lag atan2(2 zeta w W, w^2 - W^2), every mode: 1e-12."""
    a, b = plbar.rayleigh_from_ratio(0.02, 8.0, 12.0) if model == "chain" else (0.3, 0.004)
    prob = (problem(chain(5), node(1), rayleigh=(a, b)) if model == "chain" else
            problem(uniform_bar(8, point_masses=((1.0, 0.5),)), point(0.5), rayleigh=(a, b)))
    s = prob.system
    for w, z, f in ((s.w1, s.zeta1, prob.f1), (s.w2, s.zeta2, prob.f2)):
        for W in (0.5 * w.min(), w[1], 1.7 * w.max()):
            for phi in (0.0, 2.2):
                T = 2 * np.pi / W
                e0, v0 = _steady_state(w, z, f, W, phi)
                t = np.linspace(0, T, 9)[:-1]
                e, v = flow.segment(w, f, W, 0.0, t[:, None], e0, v0, np.cos(phi), np.sin(phi), z)
                amp = np.abs(f) / np.sqrt((w * w - W * W) ** 2 + (2 * z * w * W) ** 2)
                lag = np.arctan2(2 * z * w * W, w * w - W * W)
                sgn = np.sign(f)
                assert np.abs(e - sgn * amp * np.cos(W * t[:, None] - phi - lag)).max() < 1e-12 * amp.max()
                assert np.abs(v + sgn * amp * W * np.sin(W * t[:, None] - phi - lag)).max() < 1e-12 * W * amp.max()


def test_no_nan_or_overflow_for_extreme_damping():
    """Strongly over-damped high modes (zeta up to 1e6) over long segments: finite, decaying flows."""
    w = np.array([0.1, 1.0, 1e2, 1e4])
    for z in (1e-8, 1.0, 1e3, 1e6):
        p = flow.flow_matrix(w, np.array([[0.0], [1e-9], [3.0], [1e4]]), z * np.ones(4))
        assert all(np.all(np.isfinite(x)) for x in p)
        C, S, Cp = flow.kernels(w, 0.7, np.array([[0.0], [3.0], [1e4]]), zeta=z * np.ones(4))
        assert np.all(np.isfinite(C)) and np.all(np.isfinite(S)) and np.all(np.isfinite(Cp))
        ps, _ = flow.psi(Modes(w, 1.0, z * np.ones(4)), Forcing(0.7, 1.0, 0.0), 0.0, 50.0, 0.1, 0.2)
        assert np.all(np.isfinite(ps)) and np.all(ps >= 0)
