"""Convergence under mesh refinement: observed orders, Richardson limits and the reasons where there are none.

``q(h) = q_inf + C h^p`` on the finest sizes ``h_0 > h_1 > ...`` (``h = L/N``, any refinement ratios):
:func:`triple_rates` (observed order per triple; Roache's GCI, Celik et al. 2008), :func:`richardson`
(limit and error estimate), :func:`converge` (all of it, a :class:`Convergence`), :func:`known_limit`
(orders against an exact limit), :func:`caution` (when a rate should not be stated); the decay laws are in
:mod:`.decay`.
Pure numpy; nothing divides by zero or takes ``log(0)`` (masked first), and results hold ``None``
(never nan) with a sentence (``why``) where a number does not exist.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Callable

import numpy as np

from ...errors import InputError
from ...util import solve_brackets

__all__ = ["AT_LIMIT", "NON_FINITE", "NOT_CONVERGING", "NO_CHANGE", "OSCILLATORY", "Convergence", "converge",
           "known_limit", "pair_rates", "richardson", "triple_rates", "caution", "MIN_MESHES"]

EPS = float(np.finfo(float).eps)
ROUNDOFF = 100.0            #: a difference at or below ``ROUNDOFF * eps * |q|`` is round-off ("no change")
FS_OBSERVED = 1.25          #: GCI safety factor when the order is observed on >= 3 sizes and consistent
FS_ASSUMED = 3.0            #: GCI safety factor otherwise (Roache: two sizes or an assumed order)
CONSISTENT = 0.1            #: the order used is "consistent" within this relative distance of the observed one
SAME_RATIO = 1e-12          #: refinement ratios closer than this (relative) count as constant
OSCILLATORY = "oscillatory (the differences change sign)"
NO_CHANGE = "no change (differences at round-off)"
NON_FINITE = "non-finite value"
NOT_CONVERGING = "not converging (the differences do not shrink)"
AT_LIMIT = "at the limit (|q - limit| at round-off)"


def _num(x) -> float | None:
    """A finite float, or None (for JSON: never nan or inf)."""
    return float(x) if x is not None and np.isfinite(x) else None


def _sizes(h, q) -> tuple[np.ndarray, np.ndarray]:
    """Validated 1-D float arrays; ``h`` finite, positive and strictly decreasing (coarse to fine)."""
    h, q = np.asarray(h, float).ravel(), np.asarray(q, float).ravel()
    if h.shape != q.shape:
        raise InputError(f"h and q differ in length ({h.size} and {q.size}); give one q per mesh size")
    if not (np.all(np.isfinite(h)) and np.all(h > 0)):
        raise InputError(f"mesh sizes must be finite and positive, got h = {h.tolist()}")
    if np.any(np.diff(h) >= 0):
        raise InputError(f"mesh sizes must decrease strictly (coarse to fine), got h = {h.tolist()}")
    return h, q


def _floor(q1, q2, noise: float) -> np.ndarray:
    """The size of a difference ``q1 - q2`` that is indistinguishable from zero (round-off or ``noise``)."""
    return np.maximum(ROUNDOFF * EPS * np.maximum(np.abs(q1), np.abs(q2)), noise)


def _log_ratio(p, a, b) -> np.ndarray:
    """``ln[r2^p (r1^p - 1) / (r2^p - 1)]`` with ``a = ln r1``, ``b = ln r2`` (overflow-free; 0/0 at p = 0 removed).

    Increasing in ``p`` with slope between ``min(a, b)`` and ``max(a, b)``; equal to ``p a`` when ``a == b``.
    """
    p, a, b = (np.array(v, float) for v in np.broadcast_arrays(p, a, b))
    out = np.log(a / b) + 0.5 * p * (a + b)                 # series, exact to O(p^2 (a^2 - b^2) / 24)
    x = p * np.maximum(a, b)
    pos, neg = x >= 1e-7, x <= -1e-7
    pa, pb = p[pos] * a[pos], p[pos] * b[pos]
    out[pos] = pa + np.log(-np.expm1(-pa)) - np.log(-np.expm1(-pb))
    pa, pb = p[neg] * a[neg], p[neg] * b[neg]
    out[neg] = pb + np.log(-np.expm1(pa)) - np.log(-np.expm1(pb))
    return out


def _orders(t, a, b) -> tuple[np.ndarray, np.ndarray]:
    """Solve ``ln(e1/e2) = t = _log_ratio(p, a, b)`` for ``p`` (Celik et al. 2008, Eqs. 3-4); and converged flags.

    Constant ratio (``a == b``): ``p = t / a`` exactly.  Otherwise a bracketed root
    (:func:`plbar.util.solve_brackets`): since the slope of ``_log_ratio`` is at least
    ``min(a, b)``, the root lies in ``|p| <= |t - ln(a/b)| / min(a, b)``.
    """
    p, ok = np.empty(t.shape), np.ones(t.shape, bool)
    same = np.abs(a - b) <= SAME_RATIO * np.maximum(a, b)
    p[same] = t[same] / (0.5 * (a[same] + b[same]))
    idx = np.flatnonzero(~same)
    if idx.size:
        A, B, T = a[idx], b[idx], t[idx]
        span = np.abs(T - np.log(A / B)) / np.minimum(A, B) + 1.0

        def f(j, x):
            return _log_ratio(x, A[j], B[j]) - T[j]

        every = np.arange(idx.size)
        roots = solve_brackets(f, -span, span, f(every, -span), f(every, span), tol=1e-14, maxit=200)
        p[idx], ok[idx] = roots.x, roots.converged
    return p, ok


def triple_rates(h, q, *, noise: float = 0.0) -> tuple[np.ndarray, list[str]]:
    """Observed order of convergence of every successive triple of sizes.

    Parameters
    ----------
    h, q : array_like, shape (n,)
        Mesh sizes, strictly decreasing (coarse to fine), and the quantity (non-finite: no rate there).
    noise : float
        Absolute noise level of ``q``: differences at or below ``max(noise, 100 eps |q|)`` are "no change".

    Returns
    -------
    p : ndarray, shape (max(n - 2, 0),)
        Order of triple ``i`` from ``e1 = q_i - q_{i+1}``, ``e2 = q_{i+1} - q_{i+2}``: the root of
        ``e1/e2 = r2^p (r1^p - 1)/(r2^p - 1)``, ``r1 = h_i/h_{i+1}``, ``r2 = h_{i+1}/h_{i+2}``
        (``p = ln(e1/e2)/ln r`` for ``r1 = r2 = r``); nan where there is a reason.
    why : list of str
        ``""`` where ``p`` exists, else the reason (:data:`NON_FINITE`, :data:`NO_CHANGE`, ...).
    """
    h, q = _sizes(h, q)
    n = max(h.size - 2, 0)
    fin = np.isfinite(q)
    qq = np.where(fin, q, 0.0)
    e = qq[:-1] - qq[1:]
    flat = np.abs(e) <= _floor(qq[:-1], qq[1:], noise)
    why = np.full(n, "", object)
    e1, e2 = e[:n], e[1:n + 1]
    why[(np.sign(e1) != np.sign(e2))] = OSCILLATORY
    why[flat[:n] | flat[1:n + 1]] = NO_CHANGE
    why[~(fin[:n] & fin[1:n + 1] & fin[2:n + 2])] = NON_FINITE
    p = np.full(n, np.nan)
    ok = np.flatnonzero(why == "")
    if ok.size:
        r = np.log(h[:-1] / h[1:])
        t = np.log(np.abs(e1[ok])) - np.log(np.abs(e2[ok]))
        p[ok], solved = _orders(t, r[ok], r[ok + 1])
        why[ok[~solved]] = "no order found (the root finder did not converge)"
        why[ok[solved & (p[ok] <= 0)]] = NOT_CONVERGING
    p[why != ""] = np.nan
    return p, [str(w) for w in why]


def pair_rates(h, q, limit: float, *, noise: float = 0.0) -> tuple[np.ndarray, list[str]]:
    """Orders of successive pairs against a known limit: ``p_i = ln(|q_i - L| / |q_{i+1} - L|) / ln(h_i / h_{i+1})``.

    Returns ``(p, why)`` of length ``max(n - 1, 0)`` with nan and a reason (:data:`NON_FINITE`,
    :data:`AT_LIMIT`, :data:`NOT_CONVERGING`) where there is no order (see :func:`triple_rates`).
    """
    h, q = _sizes(h, q)
    fin = np.isfinite(q)
    err = np.where(fin, q, limit) - limit
    zero = np.abs(err) <= _floor(np.where(fin, q, 0.0), limit, noise)
    why = np.full(max(h.size - 1, 0), "", object)
    why[zero[:-1] | zero[1:]] = AT_LIMIT
    why[~(fin[:-1] & fin[1:])] = NON_FINITE
    p = np.full(why.size, np.nan)
    ok = np.flatnonzero(why == "")
    p[ok] = (np.log(np.abs(err[ok])) - np.log(np.abs(err[ok + 1]))) / np.log(h[ok] / h[ok + 1])
    why[ok[p[ok] <= 0]] = NOT_CONVERGING
    p[why != ""] = np.nan
    return p, [str(w) for w in why]


def _extrapolate(hc: float, hf: float, qc: float, qf: float, p: float) -> float:
    """Richardson: ``q_inf = q_f + (q_f - q_c) / (r^p - 1)``, ``r = h_c / h_f`` (``r^p`` capped below overflow)."""
    return float(qf + (qf - qc) / np.expm1(min(p * np.log(hc / hf), 700.0)))


def richardson(h, q, p: float, *, noise: float = 0.0) -> tuple[float, float]:
    """Richardson-extrapolated limit from the finest pair with order ``p``, and an error estimate.

    ``h, q``: >= 2 strictly decreasing sizes and finite values; ``p > 0``: observed or assumed order;
    ``noise``: see :func:`triple_rates`.  Returns

    limit : float
        ``q_inf = q_f + (q_f - q_c) / (r^p - 1)``, ``r = h_c / h_f`` (the finest pair).
    error : float
        The larger of

        * the fine-grid GCI (Roache 1994; Celik et al. 2008), ``Fs |q_f - q_c| / (r^p - 1) = Fs |q_inf - q_f|``,
          with ``Fs = 1.25`` when the last triple's observed order exists and is within 10 % of ``p``
          (the order is observed on >= 3 sizes and consistent), else ``Fs = 3``;
        * with >= 4 sizes, ``|q_inf - q_inf'|``, ``q_inf'`` extrapolated from the previous pair with the
          previous triple's order (where it has one): how much the extrapolation itself still moves.

        The GCI alone assumes the asymptotic range; the second term catches a limit that is still drifting
        (a pre-asymptotic order) and costs nothing when the data are asymptotic.
    """
    h, q = _sizes(h, q)
    if h.size < 2 or not np.all(np.isfinite(q)):
        raise InputError(f"Richardson extrapolation needs >= 2 finite values, got q = {q.tolist()}")
    if not (np.isfinite(p) and p > 0):
        raise InputError(f"the order p must be finite and positive, got {p}")
    limit = _extrapolate(h[-2], h[-1], q[-2], q[-1], p)
    rates, _ = triple_rates(h, q, noise=noise)
    seen = rates[-1] if rates.size else np.nan
    fs = FS_OBSERVED if np.isfinite(seen) and abs(seen - p) <= CONSISTENT * p else FS_ASSUMED
    error = fs * abs(limit - q[-1])
    if rates.size >= 2 and np.isfinite(rates[-2]):
        error = max(error, abs(limit - _extrapolate(h[-3], h[-2], q[-3], q[-2], rates[-2])))
    return limit, float(error)


def _slope(h: np.ndarray, err: np.ndarray, floor: np.ndarray) -> float | None:
    """Least-squares slope of ``log|err|`` against ``log h`` over the points with ``|err| > floor`` (>= 2)."""
    use = np.abs(err) > floor
    if np.count_nonzero(use) < 2:
        return None
    return _line(np.log(h[use]), np.log(np.abs(err[use])))[1]


def _line(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares ``y ~ c0 + c1 x``: ``(c0, c1)``."""
    xm, ym = x.mean(), y.mean()
    c1 = np.dot(x - xm, y - ym) / np.dot(x - xm, x - xm)
    return float(ym - c1 * xm), float(c1)


def _plain(obj) -> dict:
    """The fields of a result dataclass as JSON-able data (tuples -> lists; the results hold no nan)."""
    return {f.name: list(v) if isinstance(v, tuple) else v for f in fields(obj) for v in [getattr(obj, f.name)]}


@dataclass(frozen=True)
class Convergence:
    """Convergence of one quantity under mesh refinement (:func:`converge`, :func:`known_limit`); no field is nan.

    ``h, q``: the sizes used (coarse to fine); ``missing``: the sizes dropped (``q`` nan there).  ``rates`` /
    ``reasons``: per triple (per pair for a known limit), ``None`` and a reason where there is no order.  ``rate``:
    the finest triple's (pair's) order; ``fitted``: slope of ``log|q - limit|`` against ``log h`` over the sizes
    used; ``expected``: the formal order (recorded only).  ``limit, error``: :func:`richardson`, or the known limit
    and 0.  ``why``: ``""`` when a rate and a limit exist, else one sentence saying what is missing and why.
    ``meshes``: how many sizes the numbers rest on; ``caution``: why a rate or limit should not be stated even
    where one was computed (:func:`caution`; ``""`` if it may be).
    """

    name: str
    h: tuple[float, ...]
    q: tuple[float, ...]
    rates: tuple[float | None, ...]
    reasons: tuple[str, ...]
    rate: float | None
    fitted: float | None
    limit: float | None
    error: float | None
    why: str
    expected: float | None = None
    missing: tuple[float, ...] = ()
    method: str = "richardson"
    meshes: int = 0
    caution: str = ""

    @property
    def stated(self) -> bool:
        """A rate and a limit exist and may be stated (no :attr:`caution`)."""
        return self.ok and not self.caution

    @property
    def ok(self) -> bool:
        """A rate and a limit exist."""
        return self.rate is not None and self.limit is not None

    def as_dict(self) -> dict:
        """Plain JSON-able data (lists, floats, None, str); no nan or inf anywhere."""
        return _plain(self)

    def __repr__(self) -> str:
        rate = "None" if self.rate is None else f"{self.rate:.3g}"
        lim = "None" if self.limit is None else f"{self.limit:.10g} +- {self.error:.2g}"
        tail = f", why={self.why!r}" if self.why else ""
        return f"Convergence({self.name!r}, rate={rate}, limit={lim}, sizes={len(self.h)}{tail})"


def _prepare(h, q, n) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Sort by decreasing ``h``; check the sizes; labels for the messages (``"N = 8"`` or ``"h = 0.125"``)."""
    h, q = np.asarray(h, float).ravel(), np.asarray(q, float).ravel()
    if n is not None and len(n) != h.size:
        raise InputError(f"n has {len(n)} entries for {h.size} mesh sizes; give one N per size")
    order = np.argsort(-h, kind="stable")
    labels = [f"N = {n[i]}" if n is not None else f"h = {h[i]:.4g}" for i in order]
    _sizes(h[order], q[order] if q.size == h.size else q)
    return h[order], q[order], labels


def _join(labels: list[str]) -> str:
    """``["N = 8", "N = 16"]`` -> ``"N = 8, 16"``."""
    key = labels[0].split(" = ")[0]
    return f"{key} = " + ", ".join(s.split(" = ")[1] for s in labels)


def _why(k: int, need: int, last: str, labels: list[str], missing: list[str], unit: str) -> str:
    """One sentence: why there is no rate (``""`` if there is one)."""
    gone = f"the quantity is missing at {_join(missing)}" if missing else ""
    if k < need:
        s = "" if k == 1 else "s"
        return f"only {k} size{s}; a rate needs {need}" + (f" ({gone})" if gone else "")
    if last:
        return f"no rate from the last {unit} ({_join(labels[-need:])}): {last}" + (f"; {gone}" if gone else "")
    return ""


#: a rate or limit is stated only when it rests on at least this many meshes (3 give one triple: no check of it)
MIN_MESHES = 4


def caution(h, q, noise: float = 0.0) -> str:
    """Why a rate or limit of ``q(h)`` should not be stated (``""`` if it may): too few meshes, or no convergence.

    Fewer than :data:`MIN_MESHES` finite values (an order from one triple cannot be checked), or successive
    differences that change sign (beyond round-off or ``noise``): the values wander, and a rate fitted to them
    describes the wandering, not a convergence.
    """
    q = np.asarray(q, float)
    q = q[np.isfinite(q)]
    if q.size < MIN_MESHES:
        return f"rests on {q.size} mesh{'' if q.size == 1 else 'es'}; a rate is stated from {MIN_MESHES} on"
    d = q[1:] - q[:-1]
    d = d[np.abs(d) > _floor(q[1:], q[:-1], noise)]
    if np.any(np.sign(d[1:]) != np.sign(d[:-1])):
        return "the successive differences change sign (the values wander; no sign of convergence)"
    return ""


@dataclass(frozen=True)
class _Method:
    """How :func:`_study` rates a quantity: ``rater(hu, qu) -> (rates, reasons)`` from groups of ``need`` sizes,
    ``extrapolate(hu, qu, rate) -> (limit, error)``, and the method's ``name`` (recorded)."""

    need: int
    rater: Callable
    extrapolate: Callable
    name: str


def _study(name, h, q, n, method: _Method, expected, noise: float) -> Convergence:
    """Shared by :func:`converge` and :func:`known_limit`: drop missing sizes, rate, limit, fit, reason."""
    h, q, labels = _prepare(h, q, n)
    fin = np.isfinite(q)
    hu, qu = h[fin], q[fin]
    p, reasons = method.rater(hu, qu)
    rate = _num(p[-1]) if p.size else None
    need = method.need
    why = _why(hu.size, need, reasons[-1] if reasons else "", [lab for lab, f in zip(labels, fin) if f],
               [lab for lab, f in zip(labels, fin) if not f], "triple" if need == 3 else "pair")
    limit, error = method.extrapolate(hu, qu, rate)
    fitted = _slope(hu, qu - limit, _floor(qu, limit, noise)) if limit is not None else None
    return Convergence(str(name), tuple(map(float, hu)), tuple(map(float, qu)), tuple(map(_num, p)),
                       tuple(reasons), rate, fitted, limit, error, why, _num(expected), tuple(map(float, h[~fin])),
                       method.name, int(hu.size), caution(hu, qu, noise))


def converge(name: str, h, q, expected: float | None = None, *, n=None, noise: float = 0.0) -> Convergence:
    """Observed order, Richardson limit and error estimate of one quantity under mesh refinement.

    ``h, q``: mesh sizes (any order, distinct) and the quantity; ``q = nan`` means "missing at that size":
    the size is dropped (listed in ``missing``, named in ``why`` where it costs the rate).  ``expected``:
    the formal order (e.g. 2 for P1 periods), recorded beside the observed one, never used.  ``n``: labels
    of the sizes for the messages (e.g. the element counts N; default ``h``).  ``noise``: see
    :func:`triple_rates`.
    """
    def extrapolate(hu, qu, rate):
        return (None, None) if rate is None else richardson(hu, qu, rate, noise=noise)

    return _study(name, h, q, n, _Method(3, lambda hu, qu: triple_rates(hu, qu, noise=noise), extrapolate,
                                         "richardson"), expected, noise)


def known_limit(name: str, h, q, limit: float, expected: float | None = None, *, n=None,
                noise: float = 0.0) -> Convergence:
    """Orders against an exact known limit (e.g. 1 for an energy ratio, 0 for a decaying quantity); no Richardson.

    Like :func:`converge`, with ``rates`` from successive pairs (:func:`pair_rates`), ``rate`` the finest
    pair's, ``fitted`` the slope of ``log|q - limit|`` against ``log h``, ``limit`` as given and ``error = 0``.
    """
    if not np.isfinite(limit):
        raise InputError(f"the known limit must be finite, got {limit}")
    return _study(name, h, q, n, _Method(2, lambda hu, qu: pair_rates(hu, qu, limit, noise=noise),
                                         lambda hu, qu, rate: (float(limit), 0.0), "known limit"), expected, noise)
