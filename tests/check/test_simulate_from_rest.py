"""plbar.simulate from rest on an FE bar loaded far from its contact (issue 29 item 5).

At rest the contact margin of the lumped P1 bar, ``-R = (EA / h) x_{N-1}``, vanishes to a high order in time
until the wave from the load arrives (its exact value at ``t = 0.0112`` is 1.4e-66 at ``N = 32``), but its
modal sums cancel only to ~1e-17, of either sign.  The simulator took that noise for events: at ``N = 32`` an
opening at ``t = 0.0112`` and impacts at ``t = 0.0174`` and ``0.2448``; at ``N = 64`` scipy's raw
"f(a) and f(b) must have different signs" (the batched and the scalar evaluation disagreed on the sign).
"""

from decimal import Decimal, getcontext

import numpy as np
import pytest

import plbar
from plbar.check import simulate
from plbar.check.segments import SimulationError, _refine

T = 2.5


def _problem(n):
    return plbar.Case(model="fe", n=n, element="P1", mass="lumped", end_mass=0.5,
                      load_points=((0.37, 1.0),)).problem()


def _from_rest(prob, periods):
    n = prob.system.n
    return simulate(prob, T, 0.0, np.zeros(n), np.zeros(n), state=1, n_periods=periods)


def test_n64_runs_and_opens_with_the_wave():
    """The reported reproducer: N = 64 raised scipy's ValueError in the first segment (t ~ 0.0125)."""
    sim = _from_rest(_problem(64), 2)
    assert sim.events["kind"][0] == 1 and sim.events["time"][0] == pytest.approx(1.25190047, abs=1e-7)
    assert abs(sim.energy_residual) < 1e-12


def test_n32_no_events_before_the_wave():
    """N = 32: the first event is the opening at t = 1.26178 (the compiled simulator and the exact series agree)."""
    sim = _from_rest(_problem(32), 2)
    assert sim.events["time"][0] == pytest.approx(1.26178339, abs=1e-7)
    assert list(sim.events["kind"][:3]) == [1, 2, 1]


def _exact_margin(prob, times, terms=260, digits=120):
    """The state I margin ``-R`` from rest by its Taylor series in ``digits``-digit decimals (lumped mass)."""
    getcontext().prec = digits
    M, K, q = prob.system.M, prob.system.K, prob.q
    m, n = np.diag(M)[:-1], M.shape[0] - 1
    A = [[-Decimal(K[i, j]) / Decimal(m[i]) for j in range(n)] for i in range(n)]
    b = [Decimal(q[i]) / Decimal(m[i]) for i in range(n)]
    W = Decimal(2 * np.pi / T)
    cos = [Decimal(1), Decimal(0)]
    for k in range(2, terms):
        cos.append(-cos[k - 2] * W * W / (k * (k - 1)))
    a = [[Decimal(0)] * n, [Decimal(0)] * n]
    for k in range(terms - 2):      # x'' = A x + b cos(W t), x(0) = x'(0) = 0
        a.append([(sum(A[i][j] * a[k][j] for j in range(max(0, i - 1), min(n, i + 2))) + b[i] * cos[k])
                  / ((k + 1) * (k + 2)) for i in range(n)])
    g = [-sum(Decimal(K[-1, i]) * a[k][i] for i in range(n)) + Decimal(q[-1]) * cos[k] for k in range(terms)]
    return [sum(g[k] * Decimal(t) ** k for k in range(terms)) for t in times]


def test_exact_margin_is_positive_where_the_old_events_were():
    prob = _problem(32)
    assert np.all(prob.system.M[-1, :-1] == 0)
    old = (0.011175, 0.017433, 0.079763, 0.244808)       # the events the simulator used to report
    exact = _exact_margin(prob, old)
    assert all(v > 0 for v in exact)
    assert float(exact[0]) == pytest.approx(1.4036e-66, rel=1e-3)       # far below the modal sums' round-off
    assert float(exact[-1]) == pytest.approx(1.3985e-13, rel=1e-3)


def test_refine_without_a_sign_change_is_a_plbar_error():
    with pytest.raises(SimulationError, match="no sign change"):
        _refine(lambda t: 1e-17, 0.0, 1.0)
