"""The damped continuum by modal superposition (plbar.continuum.modal) against closed forms, quadrature and the FE bar.

* the modes are orthonormal with the end mass and satisfy their boundary conditions (quadrature);
* the overlap of the two bases equals its quadrature;
* the steady harmonic response held closed / held open, summed over the modes with the quasi-static correction,
  equals the closed form of the Kelvin-Voigt bar (complex wavenumber) - the reaction and the end displacement that
  the switches use converge like K^-3;
* the closed-form energy accounts close the balance to round-off and equal a brute-force quadrature;
* from rest with 1 % Rayleigh damping the first impacts agree between K = 512 and 1024 modes, and with the fine
  P2 redistributed FE bar (an independent discretisation) to its own error.
"""

import math

import numpy as np
import pytest

import plbar
from plbar.continuum import ContinuumBar
from plbar.continuum.modal import simulate_modal
from plbar.continuum.modes import Segment, closed_modes, open_modes, overlap, state

BAR = ContinuumBar(end_mass=0.5, s=0.37)
RAY = plbar.rayleigh_from_ratio(0.01, 2.0, 4.0)


def _quad(f, intervals=500):
    """``int_0^L f(x) dx`` by 40-point Gauss-Legendre on ``intervals`` pieces; ``f`` maps (n,) to (n, ...)."""
    x, w = np.polynomial.legendre.leggauss(40)
    edges = np.linspace(0, BAR.L, intervals + 1)
    h = 0.5 * np.diff(edges)
    X = ((0.5 * (edges[:-1] + edges[1:]))[:, None] + h[:, None] * x).ravel()
    return np.tensordot((h[:, None] * w).ravel(), f(X), axes=(0, 0))


def test_modes_are_orthonormal_with_the_end_mass_and_meet_their_ends():
    for m in (closed_modes(BAR, 12), open_modes(BAR, 12)):
        G = _quad(lambda x, m=m: m.shapes(x)[:, :, None] * m.shapes(x)[:, None, :]) * BAR.rhoA
        if not m.closed:
            G += BAR.end_mass * np.outer(m.at_L, m.at_L)
            # the free end mass: EA phi'(L) = m_e omega^2 phi(L)
            assert np.allclose(BAR.EA * m.slope_L, BAR.end_mass * m.omega ** 2 * m.at_L, atol=1e-12)
        else:
            assert np.abs(m.at_L).max() < 1e-12
        assert np.abs(G - np.eye(12)).max() < 1e-12


def test_overlap_equals_its_quadrature():
    mc, mo = closed_modes(BAR, 10), open_modes(BAR, 10)
    P = _quad(lambda x: mc.shapes(x)[:, :, None] * mo.shapes(x)[:, None, :]) * BAR.rhoA
    assert np.abs(overlap(BAR, mc, mo) - P).max() < 1e-12


def _kelvin_voigt(T, closed):
    """The closed-form steady response ``U(x) e^{i theta}`` of the Kelvin-Voigt bar with mass damping."""
    a, b = RAY
    w = 2 * math.pi / T
    L, s, EA, q, m = BAR.L, BAR.s, BAR.EA * (1 + 1j * w * b), BAR.q, BAR.end_mass
    k = np.sqrt(BAR.rhoA * (w * w - 1j * w * a) / EA)
    y = L - s
    if closed:       # U = al sin kx | be sin k(L - x)
        A = np.array([[np.sin(k * s), -np.sin(k * y)], [EA * k * np.cos(k * s), EA * k * np.cos(k * y)]])
        al, be = np.linalg.solve(A, [0, q])
        U = lambda x: np.where(x < s, al * np.sin(k * x), be * np.sin(k * (L - x)))  # noqa: E731
        return U, EA * (-k * be)                   # sigma(L) = EA U'(L)
    A = np.array([[np.sin(k * s), -np.cos(k * y), -np.sin(k * y)],
                  [EA * k * np.cos(k * s), -EA * k * np.sin(k * y), EA * k * np.cos(k * y)],
                  [0, m * (-w * w + 1j * w * a), -EA * k]])
    al, b1, b2 = np.linalg.solve(A, [0, q, 0])
    U = lambda x: np.where(x < s, al * np.sin(k * x), b1 * np.cos(k * (L - x)) + b2 * np.sin(k * (L - x)))  # noqa: E731
    return U, EA * (-k * b2)


@pytest.mark.parametrize("T", [2.5, 0.9])
def test_held_states_equal_the_kelvin_voigt_closed_form(T):
    w = 2 * math.pi / T
    x = np.array([0.1, 0.37, 0.6, 0.95])
    errs = {}
    for closed in (True, False):
        U, sigma = _kelvin_voigt(T, closed)
        target = -sigma if closed else U(BAR.L)      # the switch function: R held closed, u(L) held open
        field = {}
        for K in (50, 100, 200):
            m = (closed_modes if closed else open_modes)(BAR, K, RAY)
            st = state(BAR, m, w, RAY)
            errs[closed, K] = abs(st.amp_f - target) / abs(target)
            field[K] = np.abs(m.shapes(x) @ st.A - U(x)) / np.abs(U(x)).max()
        # the plain modal sum of the field: like K^-2 away from the load, K^-1 at its kink
        away, at = x != BAR.s, x == BAR.s
        assert field[200][away].max() < 2e-5 and field[50][away].max() / field[200][away].max() > 10
        assert field[200][at].max() < 5e-3 and field[50][at].max() / field[200][at].max() > 3
        # the quasi-static correction makes the switch function converge like K^-3
        assert errs[closed, 200] < 1e-6
        assert errs[closed, 100] / errs[closed, 200] > 6


def test_accounts_are_exact_on_a_segment():
    """The closed-form integrals of one segment against Gauss quadrature of the modal velocities."""
    w = 2 * math.pi / 2.5
    m = open_modes(BAR, 40, RAY)
    st = state(BAR, m, w, RAY)
    rng = np.random.default_rng(3)
    sg = Segment(st, 0.3, rng.normal(size=40) * 1e-2, rng.normal(size=40) * 1e-1, w, 0.2)
    tau = 0.7
    x, wt = np.polynomial.legendre.leggauss(60)
    edges = np.linspace(0, tau, 201)
    work = dis = v2 = psi = 0.0
    for lo, hi in zip(edges[:-1], edges[1:]):
        for xi, wi in zip(x, wt):
            t = 0.5 * (lo + hi) + 0.5 * (hi - lo) * xi
            _, v = sg.modal(t)
            F = BAR.q * math.cos(w * (0.3 + t) - 0.2)
            c = 0.5 * (hi - lo) * wi
            work += c * F * (m.at_s @ v)
            dis += c * (m.damping @ v ** 2)
            v2 += c * (v @ v)
            psi += c * (m.omega @ v ** 2)
    got = sg.accounts(tau, m.at_s, BAR.q)
    assert np.allclose(got, (work, dis, v2, psi), rtol=1e-10, atol=1e-14)


@pytest.fixture(scope="module")
def runs():
    return {K: simulate_modal(BAR, 2.5, 3, RAY, modes=K) for K in (512, 1024)}


def test_energy_balance_closes_and_truncation_shrinks(runs):
    for r in runs.values():
        assert abs(r.energy_residual) < 1e-12
        assert r.loss.sum() > 0.1 and r.dissipation.sum() > 0
    # the truncation's energy change at the switches halves with each doubling of K
    t = {K: abs(r.transfer.sum()) / r.work.sum() for K, r in runs.items()}
    assert t[1024] < 0.6 * t[512] and t[1024] < 2e-4


def test_first_impacts_converge_in_modes_and_meet_the_fe_bar(runs):
    imp = {K: r.events["time"][r.events["kind"] == 2] for K, r in runs.items()}
    assert abs(imp[512][0] - imp[1024][0]) < 1e-7
    assert abs(imp[1024][0] - 3.3897682) < 1e-6            # the first impact of the continuum
    # the FE bar, P2 redistributed N = 64, same damping: its own error (table) is 2e-6
    from plbar.motion import padded, run
    case = plbar.Case(model="fe", n=64, element="P2", mass="redistributed", end_mass=0.5,
                      load_points=((0.37, 1.0),), rayleigh=RAY)
    fe = run(padded(case.problem()), np.array([2.5]), 0.0, 2, 2)
    ev = fe.events
    t_fe = ev["time"][ev["kind"] >= 2]
    assert abs(t_fe[np.argmin(abs(t_fe - imp[1024][0]))] - imp[1024][0]) < 1e-5
    u = runs[1024].contact([1.0, 2.0, 3.0, 3.3])
    assert np.all(u <= 1e-9) and u.min() < -0.05


def test_bad_input_is_refused():
    with pytest.raises(plbar.InputError):
        simulate_modal(BAR, 2.5, 0)
    with pytest.raises(plbar.InputError):
        simulate_modal(BAR, -1.0, 1)
    with pytest.raises(plbar.InputError):
        simulate_modal(BAR, 2.5, 1, rayleigh=(-1.0, 0.0))
