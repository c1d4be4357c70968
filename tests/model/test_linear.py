"""The equivalent linear models: their closed-form steady responses against an integrator written here.

Each model is rebuilt here as matrices (``K = M V diag(w^2) V^T M``, ``C = M V diag(2 (xi + zeta) w) V^T M``),
integrated by scipy's DOP853 for one forcing period from the closed form's state at ``t = 0``: the integrated
motion must be the closed form at every sample and return to its start (1e-10), and the energy the dampers take
(a quadrature of ``v^T C v``) and the load's work must be the closed form's.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import plbar
from plbar.errors import InputError
from plbar.model.linear import STIFFNESSES, linear_model, steady_response


def _matrices(prob, model, xi):
    """``M, K, C`` of the linear model over the coordinates it moves (the stuck one: all but the contact)."""
    M = prob.system.M
    keep = slice(None) if model.stiffness != "stuck" else slice(0, M.shape[0] - 1)
    M = M[keep, keep]
    V = model.V[keep]
    MV = M @ V
    return M, MV @ np.diag(model.w ** 2) @ MV.T, MV @ np.diag(2 * (xi + model.zeta) * model.w) @ MV.T, keep


@pytest.mark.parametrize("case", [plbar.Case(), plbar.Case(model="fe", n=6, end_mass=0.5, rayleigh=(0.02, 0.003))],
                         ids=["chain", "fe-damped"])
@pytest.mark.parametrize("stiffness", STIFFNESSES)
def test_the_closed_form_steady_response_is_the_integrated_one(case, stiffness):
    prob = case.problem()
    model = linear_model(prob, stiffness)
    T, xi = 0.8 * prob.system.T0[1], 0.05
    st = steady_response(model, T, xi)
    M, K, C, keep = _matrices(prob, model, xi)
    q = np.asarray(prob.q, float)[keep]
    W = 2 * np.pi / T
    Mi = np.linalg.inv(M)
    n = M.shape[0]

    def rhs(t, z):
        x, v = z[:n], z[n:2 * n]
        a = Mi @ (q * np.cos(W * t) - K @ x - C @ v)
        return np.concatenate([v, a, [v @ C @ v, q @ v * np.cos(W * t)]])

    x0 = st.x[keep]
    z0 = np.concatenate([x0.real, (1j * W * x0).real, [0.0, 0.0]])
    ts = np.linspace(0.0, T, 9)
    sol = solve_ivp(rhs, (0.0, T), z0, method="DOP853", rtol=1e-13, atol=1e-15 * np.abs(z0).max(), t_eval=ts)
    scale = np.abs(x0).max()
    closed = (x0[:, None] * np.exp(1j * W * ts)[None]).real
    assert np.abs(sol.y[:n] - closed).max() <= 1e-10 * scale
    assert np.abs(sol.y[:n, -1] - x0.real).max() <= 1e-10 * scale
    assert sol.y[2 * n, -1] == pytest.approx(st.dissipated, rel=1e-9)
    assert sol.y[2 * n + 1, -1] == pytest.approx(st.work, rel=1e-9)
    assert st.work == pytest.approx(st.dissipated, rel=1e-12)
    if stiffness == "stuck":
        assert st.amplitude_contact == 0.0


def test_the_bilinear_frequency_of_one_dof_is_its_free_vibration_period():
    """One mass between a spring and a stop at rest: the bilinear oscillator (k_I in contact, k_II free) swings
    half a period on each side; the model's fundamental is 2 pi over that period."""
    M = np.diag([1.0, 1.0])
    K = np.array([[3.0, -1.0], [-1.0, 1.0]])
    prob = plbar.problem(plbar.Structure(M, K, [0.0, 1.0], [1.0, 0.0]))
    s = prob.system
    w = linear_model(prob, "bilinear").w
    assert 2 * np.pi / w[0] == pytest.approx(np.pi / s.w1[0] + np.pi / s.w2[0], rel=1e-14)
    assert w[-1] == s.w2[-1]


def test_bad_inputs_are_refused():
    prob = plbar.Case().problem()
    with pytest.raises(InputError, match="is not one of"):
        linear_model(prob, "secant")
    with pytest.raises(InputError, match="xi"):
        steady_response(linear_model(prob), 10.0, -0.1)
    with pytest.raises(InputError, match="truncated"):
        linear_model(plbar.Case(modes=3).problem())
