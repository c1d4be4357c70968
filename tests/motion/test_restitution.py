"""Newton's impact law in the simulator (issue 31): rebounds, chattering, energy; checked by brute force.

* a sequence of rebounds against an integrator written here (scipy's solve_ivp with events on the physical
  equations of motion; the rebound ``v_c -> -e v_c`` of a lumped mass): event times to 1e-9;
* the energy budget with ``e = 0.3, 0.6, 0.9`` to 1e-12 of the work; ``e = 1`` loses nothing at its impacts;
* chattering (the contact pressed to the wall after an impact): the accumulation time and the state after it
  against a brute-force sequence of rebounds computed here one by one (closed-form flows of the modes, each
  flight's end by root finding, down to rebound speeds of 1e-15) to 1e-8;
* ``e = 0`` is the plastic simulator: the same numbers as ``restitution`` left out.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import plbar
from plbar.errors import InputError
from plbar.motion import Start, padded, run
from plbar.motion.kernel import data as D

FREE = 1


def _modal(pad, prob, x, v):
    """The padded modal state II of physical ``x, v`` (the chain: ``M = I``, modes mass-orthonormal)."""
    V2 = prob.system.V2
    eta, vel = np.zeros(pad.m), np.zeros(pad.m)
    eta[:V2.shape[1]], vel[:V2.shape[1]] = V2.T @ x, V2.T @ v
    return eta, vel


def test_restitution_is_checked():
    for bad in (-0.1, 1.5, "0.5", float("nan"), None):
        with pytest.raises(InputError, match="restitution"):
            plbar.Case(restitution=bad)
    assert plbar.Case(restitution=1).restitution == 1.0
    assert "restitution" not in plbar.Case().to_dict() and plbar.Case(restitution=0.4).to_dict()["restitution"] == 0.4


def test_zero_restitution_is_the_plastic_simulator():
    T = np.linspace(6, 14, 9)
    a = run(padded(plbar.Case().problem()), T, 0.0, 300, 20)
    b = run(padded(plbar.Case(restitution=0.0).problem()), T, 0.0, 300, 20)
    assert np.array_equal(a.loss, b.loss) and np.array_equal(a.strobe_x, b.strobe_x)
    assert set(np.unique(a.events["kind"])) <= {D.OPENS, D.IMPACT}


def _ivp_rebounds(M, K, q, W, phi, e, x0, v0, t_end):
    """Event times of the free bar with rebounds ``v_c -> -e v_c`` (lumped mass), by solve_ivp (DOP853)."""
    n = x0.size
    Minv = np.linalg.inv(M)

    def rhs(t, y):
        return np.concatenate([y[n:], Minv @ (-K @ y[:n] + q * np.cos(W * t - phi))])

    def hit(t, y):
        return y[n - 1]
    hit.terminal, hit.direction = True, 1.0
    t, y, times = 0.0, np.concatenate([x0, v0]), []
    while t < t_end:
        sol = solve_ivp(rhs, (t, t_end), y, method="DOP853", rtol=1e-13, atol=1e-15, events=hit)
        if sol.status != 1:
            break
        t, y = sol.t_events[0][0], sol.y_events[0][0].copy()
        times.append(t)
        y[n - 1], y[-1] = 0.0, -e * y[-1]
        y[n - 1] = y[-1] * 1e-12                    # 1e-12 into the flight, so that the next event is its end
        t += 1e-12
    return np.array(times)


@pytest.mark.parametrize("e", [0.3, 0.6, 0.9])
def test_a_rebound_sequence_matches_an_independent_integrator(e):
    """The chain N = 5 released away from the wall, pushed to it by the load: every rebound's time to 1e-9."""
    prob = plbar.Case(restitution=e).problem()
    pad = padded(prob)
    M, K, q = prob.asm.M, prob.asm.K, prob.q
    T, phi = 10.0, 0.0
    x0 = -0.6 * np.linalg.solve(K, q)                          # pulled away from the wall, at rest
    v0 = np.zeros_like(x0)
    eta, vel = _modal(pad, prob, x0, v0)
    r = run(pad, np.array([T]), phi, 6, 6, Start(np.array([FREE]), eta[None], vel[None]))
    kinds, times = r.events["kind"], r.events["time"]
    end = np.flatnonzero(kinds != D.REBOUND)                    # compare the rebounds before any sticking
    times = times[:end[0]] if end.size else times
    assert times.size >= 4
    ref = _ivp_rebounds(M, K, q, 2 * np.pi / T, phi, e, x0, v0, times[-1] + 1e-6)
    assert ref.size >= times.size
    assert np.abs(ref[:times.size] - times).max() <= 1e-9


@pytest.mark.parametrize("e", [0.3, 0.6, 0.9, 1.0])
@pytest.mark.parametrize("case", ["chain", "fe"])
def test_the_energy_budget_closes_with_rebounds(e, case):
    c = plbar.Case(restitution=e) if case == "chain" else plbar.Case(model="fe", n=8, end_mass=0.5, restitution=e)
    T = np.linspace(6, 14, 9) if case == "chain" else np.linspace(1.5, 4.5, 7)
    r = run(padded(c.problem()), T, 0.0, 400, 20)
    assert np.all(r.status == 0)
    assert np.abs(r.energy_residual).max() <= 1e-12
    assert r.impacts.sum() > 0
    if e == 1.0:
        assert np.all(r.losses == 0.0) and np.all(r.events["loss"] == 0.0)   # an elastic impact loses nothing
    else:
        assert np.all(r.losses > 0)


# --- chattering, against a brute-force sequence of rebounds ------------------------------------------------------

class Flow:
    """Closed-form flow of ``x'' = -K x + q cos(W t - phi)`` (``M = I``) on the modes of ``K``."""

    def __init__(self, K, q, W, phi):
        self.w2, self.V = np.linalg.eigh(K)
        self.w = np.sqrt(self.w2)
        self.f, self.W, self.phi = self.V.T @ q, W, phi

    def __call__(self, t0, x, v, t):
        W, w, f = self.W, self.w, self.f
        p = lambda s: f * np.cos(W * s - self.phi) / (self.w2 - W * W)
        dp = lambda s: -W * f * np.sin(W * s - self.phi) / (self.w2 - W * W)
        A, B = self.V.T @ x - p(t0), (self.V.T @ v - dp(t0)) / w
        u = t - t0
        eta = A * np.cos(w * u) + B * np.sin(w * u) + p(t)
        deta = w * (B * np.cos(w * u) - A * np.sin(w * u)) + dp(t)
        return self.V @ eta, self.V @ deta


def _chatter_brute_force(K, q, W, phi, e, x0, v0, T):
    """Rebounds one by one from ``x0, v0`` (state II) until their speed is below 1e-15; then the contact held to
    ``T``.  Returns ``(accumulation time, x(T), v(T), largest reaction over [t_inf, T])``."""
    II, I = Flow(K, q, W, phi), Flow(K[:-1, :-1], q[:-1], W, phi)
    t, x, v = 0.0, x0.copy(), v0.copy()
    rebounds = 0
    while True:
        xc = lambda s, t=t, x=x, v=v: II(t, x, v, s)[0][-1]
        a = (-K @ x + q * np.cos(W * t - phi))[-1]
        j = (-K @ v - q * W * np.sin(W * t - phi))[-1]
        vc = v[-1]
        if rebounds and abs(vc) ** 2 / (2 * a) < 1e-9:          # a tiny flight: its end from the cubic x_c(tau)
            tau = -2 * vc / a
            for _ in range(50):
                g = vc * tau + a * tau ** 2 / 2 + j * tau ** 3 / 6
                tau -= g / (vc + a * tau + j * tau ** 2 / 2)
        else:                                                  # bracket the return to the wall on the closed form
            est = (-2 * vc / a) if rebounds else np.sqrt(2 * -x[-1] / a)
            s = t + np.linspace(0, 3 * est, 3001)[1:]
            g = np.array([xc(si) for si in s])
            k = np.flatnonzero((g[:-1] < 0) & (g[1:] >= 0))[0]
            tau = brentq(xc, s[k], s[k + 1], xtol=1e-16, rtol=1e-15) - t
        x, v = II(t, x, v, t + tau)
        t += tau
        x[-1] = 0.0
        V, v[-1] = v[-1], -e * v[-1]
        rebounds += 1
        assert rebounds < 10_000, "the rebounds do not accumulate"
        if V < 1e-15:
            break
    v[-1] = 0.0
    xs = np.linspace(t, T, 200)
    R = max((K[-1, :-1] @ I(t, x[:-1], v[:-1], s)[0] - q[-1] * np.cos(W * s - phi)) for s in xs)
    xT, vT = I(t, x[:-1], v[:-1], T)
    return t, np.append(xT, 0.0), np.append(vT, 0.0), R, rebounds


@pytest.mark.parametrize("e, T", [(0.3, 2.0), (0.5, 2.0), pytest.param(0.8, 3.3, marks=pytest.mark.slow)])
def test_chattering_ends_where_the_rebounds_accumulate(e, T):
    """The chain released with its inner masses pushed toward the wall and the contact 0.01 from it: it hits,
    rebounds ever lower (the bar presses it to the wall) and stays.  The simulator passes to the accumulation
    point once the flights are 1e-11 of the margin's size high; the brute force follows every rebound (48 to 145
    of them, down to 1e-15).  Measured: accumulation time 5e-11 - 7e-11, state at T 1e-14."""
    prob = plbar.Case(load_nodes=((1, 0.01),), restitution=e).problem()
    pad = padded(prob)
    K, q = prob.asm.K, prob.q
    n = q.size
    F = np.zeros(n)
    F[0] = 1.0
    x0 = np.linalg.solve(K, F)
    G = np.zeros(n)
    G[-1] = 1.0
    x0 -= (x0[-1] + 0.01) / np.linalg.solve(K, G)[-1] * np.linalg.solve(K, G)   # x_c = -0.01, inner masses +
    v0 = np.zeros(n)
    phi = 0.0
    t_inf, xT, vT, R, rebounds = _chatter_brute_force(K, q, 2 * np.pi / T, phi, e, x0, v0, T)
    assert R < 0 and 0 < t_inf < T and rebounds > 20               # held against the wall to T, never pulled off
    eta, vel = _modal(pad, prob, x0, v0)
    r = run(pad, np.array([T]), phi, 1, 1, Start(np.array([FREE]), eta[None], vel[None]))
    kinds, times = r.events["kind"], r.events["time"]
    assert kinds[-1] == D.STICK and np.all(kinds[:-1] == D.REBOUND)
    assert abs(times[-1] - t_inf) <= 1e-8
    scale = np.abs(xT).max()
    assert np.abs(r.strobe_x[0, -1] - xT).max() <= 1e-8 * scale
    assert np.abs(r.strobe_v[0, -1] - vT).max() <= 1e-8 * max(np.abs(vT).max(), scale)
    assert r.strobe_state[0, -1] == 0
    assert abs(r.energy_residual[0]) <= 1e-12
