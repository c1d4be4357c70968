"""Convergence estimation (plbar.studies.refine.convergence) on manufactured sequences q = q_inf + C h^p (1 + d h)."""

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plbar.errors import InputError
from plbar.studies.refine.convergence import (AT_LIMIT, NO_CHANGE, NOT_CONVERGING, OSCILLATORY, converge, known_limit,
                                       pair_rates, richardson, triple_rates)
from plbar.studies.refine.decay import decay_fit

Q_INF, C = 1.25, 2.0
SEQUENCES = {"ratio 2": np.array([8, 16, 32, 64, 128]), "mixed ratios": np.array([8, 12, 20, 32, 64])}


def manufactured(N, p, d=0.0, q_inf=Q_INF, c=C):
    h = 1.0 / np.asarray(N, float)
    return h, q_inf + c * h**p * (1.0 + d * h)


def _json(res):
    text = json.dumps(res.as_dict(), allow_nan=False)
    assert json.loads(text) == res.as_dict()
    return text


@pytest.mark.parametrize("seq", SEQUENCES)
@pytest.mark.parametrize("p", [1, 2, 4])
def test_pure_power_rates_and_limit_exact(p, seq):
    N = SEQUENCES[seq]
    h, q = manufactured(N, p)
    res = converge("q", h, q, expected=p, n=N.tolist())
    assert res.why == "" and res.ok
    np.testing.assert_allclose(res.rates, p, rtol=0, atol=1e-10)
    assert res.rate == pytest.approx(p, abs=1e-10)
    assert res.fitted == pytest.approx(p, abs=1e-9)
    assert abs(res.limit - Q_INF) <= 1e-12 * Q_INF
    assert abs(res.limit - Q_INF) < res.error
    assert res.expected == p and res.method == "richardson"


@pytest.mark.parametrize("d", [0.5, -0.5])
@pytest.mark.parametrize("seq", SEQUENCES)
@pytest.mark.parametrize("p", [1, 2, 4])
def test_rates_tend_to_p_with_a_higher_order_term(p, seq, d):
    N = SEQUENCES[seq]
    h, q = manufactured(N, p, d)
    res = converge("q", h, q, expected=p)
    dev = np.abs(np.array(res.rates) - p)
    assert np.all(np.diff(dev) < 0)                              # each finer triple is closer to p
    assert dev[-1] < 0.05
    assert res.fitted == pytest.approx(p, abs=0.1)
    assert abs(res.limit - Q_INF) < res.error                    # the estimate covers the true error ...
    assert res.error < 1.5 * abs(q[-1] - Q_INF)                  # ... and is of the size of the finest error


def test_mixed_ratios_solve_the_generalised_equation():
    """At the returned p, e1/e2 = r2^p (r1^p - 1)/(r2^p - 1) holds; with a constant ratio p = ln(e1/e2)/ln r."""
    h = np.array([1 / 7, 1 / 11, 1 / 23, 1 / 31, 1 / 60])
    q = 0.3 + 0.7 * h**1.7 + 0.4 * h**2.9
    p, why = triple_rates(h, q)
    assert why == ["", "", ""]
    e = q[:-1] - q[1:]
    r = h[:-1] / h[1:]
    rhs = r[1:]**p * (r[:-1]**p - 1) / (r[1:]**p - 1)
    np.testing.assert_allclose(e[:-1] / e[1:], rhs, rtol=1e-12)
    h2 = 0.1 / 2.0**np.arange(4)
    q2 = 1 + h2**1.5 + h2**2
    p2, _ = triple_rates(h2, q2)
    e2 = q2[:-1] - q2[1:]
    np.testing.assert_allclose(p2, np.log(e2[:-1] / e2[1:]) / np.log(2.0), rtol=1e-13)


def test_oscillatory_sequence_has_no_rate():
    N = np.array([8, 16, 32, 64, 128])
    h = 1.0 / N
    q = 1.0 + (-1.0)**np.arange(5) * h**2
    res = converge("osc", h, q, n=N.tolist())
    assert res.reasons == (OSCILLATORY,) * 3 and res.rates == (None,) * 3
    assert res.rate is None and res.limit is None and res.error is None and res.fitted is None
    assert res.why == f"no rate from the last triple (N = 32, 64, 128): {OSCILLATORY}"
    assert '"rate": null' in _json(res)


def test_round_off_plateau_and_noise_level():
    h = 1.0 / np.array([8, 16, 32, 64, 128])
    q = np.array([1.1, 1.01, 1.0, 1.0, 1.0 + 2e-16])
    p, why = triple_rates(h, q)
    assert why == ["", NO_CHANGE, NO_CHANGE] and np.isfinite(p[0]) and np.isnan(p[1:]).all()
    assert converge("flat", h, q).why.endswith(NO_CHANGE)
    q = 1.0 + 1e-9 * h**2                                          # a real but tiny change ...
    assert triple_rates(h, q)[1] == ["", "", ""]
    assert triple_rates(h, q, noise=1e-12)[1] == ["", NO_CHANGE, NO_CHANGE]   # ... below a declared noise level


def test_diverging_sequence_is_not_converging():
    h = 1.0 / np.array([8, 16, 32, 64])
    res = converge("div", h, 1.0 + np.sqrt(1.0 / h))
    assert res.reasons == (NOT_CONVERGING,) * 2 and res.rate is None and NOT_CONVERGING in res.why


def test_missing_sizes_are_dropped_and_named():
    N = np.array([8, 16, 32, 64, 128])
    h, q = manufactured(N, 2)
    one = q.copy()
    one[2] = np.nan                                               # the rate survives (mixed ratios 2, 4)
    res = converge("q", h, one, n=N.tolist())
    assert res.missing == (h[2],) and res.h == tuple(np.delete(h, 2)) and res.why == ""
    assert res.rate == pytest.approx(2, abs=1e-10) and res.limit == pytest.approx(Q_INF, rel=1e-12)
    two = q[:4].copy()
    two[1:3] = np.nan
    res = converge("q", h[:4], two, n=N[:4].tolist())
    assert res.rate is None and res.limit is None
    assert res.why == "only 2 sizes; a rate needs 3 (the quantity is missing at N = 16, 32)"
    osc = 1.0 + (-1.0)**np.arange(5) * h**2
    osc[3:] = np.nan
    res = converge("q", h, osc, n=N.tolist())
    assert res.why == (f"no rate from the last triple (N = 8, 16, 32): {OSCILLATORY}; "
                       "the quantity is missing at N = 64, 128")
    _json(res)


def test_as_dict_is_plain_json():
    N = np.array([8, 16, 32, 64])
    h, q = manufactured(N, 2, 0.5)
    for res in (converge("ok", h, q, expected=2), converge("few", h[:2], q[:2]),
                converge("nan", h, np.where(N == 16, np.nan, q)), known_limit("E", h, q, Q_INF),
                known_limit("flat", h, np.ones(4), 1.0)):
        d = json.loads(_json(res))
        assert set(d) >= {"name", "h", "q", "rates", "rate", "fitted", "limit", "error", "why", "missing"}
        assert (d["rate"] is None) == bool(d["why"])


def test_input_order_and_errors():
    N = np.array([8, 16, 32, 64])
    h, q = manufactured(N, 2, 0.5)
    assert converge("q", h[::-1], q[::-1]).as_dict() == converge("q", h, q).as_dict()
    with pytest.raises(InputError, match="decrease strictly"):
        converge("q", [0.1, 0.1, 0.05], [1, 2, 3])
    with pytest.raises(InputError, match="positive"):
        converge("q", [0.1, -0.05, 0.02], [1, 2, 3])
    with pytest.raises(InputError, match="differ in length"):
        converge("q", [0.1, 0.05], [1, 2, 3])
    with pytest.raises(InputError, match="positive"):
        richardson(h, q, 0.0)


def test_richardson_safety_factor():
    N = np.array([8, 16, 32])
    h, q = manufactured(N, 2)
    lim, err = richardson(h[1:], q[1:], 2.0)                      # two sizes: assumed order, Fs = 3
    assert lim == pytest.approx(Q_INF, rel=1e-14) and err == pytest.approx(3 * abs(lim - q[-1]), rel=1e-12)
    lim, err = richardson(h, q, 2.0)                              # observed and consistent: Fs = 1.25
    assert err == pytest.approx(1.25 * abs(lim - q[-1]), rel=1e-12)
    lim, err = richardson(h, q, 1.0)                              # assumed 1, observed 2: Fs = 3
    assert err == pytest.approx(3 * abs(lim - q[-1]), rel=1e-12)


def test_error_estimate_catches_a_drifting_extrapolation():
    """Pre-asymptotic data (a log factor): the change between the last two extrapolations exceeds the GCI."""
    h = 1.0 / np.array([2.0, 4, 8, 16])
    q = 1.0 + h**2 * (1.0 + 5.0 * np.log(1.0 / h))
    p, _ = triple_rates(h, q)
    lim, err = richardson(h, q, p[-1])
    prev = q[-2] + (q[-2] - q[-3]) / ((h[-3] / h[-2])**p[-2] - 1.0)
    assert err == pytest.approx(abs(lim - prev), rel=1e-12) and err > 1.4 * 1.25 * abs(lim - q[-1])
    assert abs(lim - 1.0) < err


def test_known_limit_rates():
    N = np.array([8, 16, 32, 64, 128])
    res = known_limit("E", 1.0 / N, 1.0 + 1.0 / (2 * N), 1.0, expected=1)
    np.testing.assert_allclose(res.rates, 1.0, rtol=0, atol=1e-12)
    assert res.rate == pytest.approx(1, abs=1e-12) and res.fitted == pytest.approx(1, abs=1e-12)
    assert (res.limit, res.error, res.why, res.method) == (1.0, 0.0, "", "known limit")
    p, why = pair_rates(1.0 / N[:3], [1.1, 1.0, 1.0], 1.0)
    assert why == [AT_LIMIT, AT_LIMIT] and np.isnan(p).all()
    assert known_limit("x", [0.5], [1.2], 1.0).why == "only 1 size; a rate needs 2"


def test_decay_fit_picks_the_logarithmic_law():
    N = np.array([8, 16, 32, 64, 128, 256])
    fit = decay_fit(1.0 / N, 0.3 / (1.5 + np.log(N)), name="xi")
    assert fit.model == "log" and fit.why == ""
    assert fit.a == pytest.approx(0.3, rel=1e-10) and fit.b == pytest.approx(1.5, rel=1e-10)
    assert fit.log_residual < 1e-12 and fit.power_residual > 1e-3
    assert fit.formula() == "q ~ 0.3 / (1.5 + ln(1/h))"
    json.dumps(fit.as_dict(), allow_nan=False)


def test_decay_fit_picks_the_power_law():
    N = np.array([8, 16, 32, 64, 128, 256])
    fit = decay_fit(1.0 / N, 2.0 * N**-1.3)
    assert fit.model == "power" and fit.rate == pytest.approx(1.3, rel=1e-12) and fit.coef == pytest.approx(2.0)
    assert fit.power_residual < 1e-12
    assert fit.log_residual is None or fit.log_residual > 1e-3
    assert decay_fit([0.5, 0.25], [0.1, 0.05]).why == "only 2 sizes; choosing a model needs 3"
    assert decay_fit([0.5, 0.25, 0.1], [0.1, 0.0, 0.05]).model == ""


def test_repr_is_short():
    h, q = manufactured([8, 16, 32], 2)
    text = repr(converge("T0_I/L", h, q))
    assert text.startswith("Convergence('T0_I/L', rate=2,") and len(text) < 100


@settings(max_examples=150, deadline=None)
@given(p=st.floats(0.5, 4.0), c=st.floats(0.5, 5.0), sign=st.sampled_from([-1.0, 1.0]),
       q_inf=st.floats(-2.0, 2.0), n=st.integers(4, 6))
def test_pure_power_property(p, c, sign, q_inf, n):
    h = 2.0 ** -np.arange(n)
    res = converge("q", h, q_inf + sign * c * h**p)
    assert res.why == ""
    assert res.rate == pytest.approx(p, abs=1e-8)
    assert all(math.isclose(r, p, abs_tol=1e-8) for r in res.rates)
    assert abs(res.limit - q_inf) <= 1e-8 * max(1.0, abs(q_inf))
