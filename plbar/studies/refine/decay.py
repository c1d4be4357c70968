"""Two laws for a quantity that decays to 0 under mesh refinement: ``C h^p`` against ``a / (b + ln(1/h))``."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .convergence import _line, _num, _plain, _prepare

__all__ = ["DecayFit", "decay_fit"]


@dataclass(frozen=True)
class DecayFit:
    """Two models of a quantity that tends to 0 (:func:`decay_fit`); ``None`` where a model does not exist.

    ``power``: ``q ~ C h^p`` (``rate = p``, ``coef = C``); ``log``: ``q ~ a / (b + ln(1/h))``.
    ``*_residual``: rms of ``ln q - ln model(h)``.  ``model`` is the better one (``"power"`` or ``"log"``),
    ``""`` with ``why`` when neither can be chosen.
    """

    name: str
    h: tuple[float, ...]
    q: tuple[float, ...]
    rate: float | None
    coef: float | None
    power_residual: float | None
    a: float | None
    b: float | None
    log_residual: float | None
    model: str
    why: str

    def __repr__(self) -> str:
        return f"DecayFit({self.name!r}, model={self.model!r}, {self.formula() or self.why})"

    def formula(self) -> str:
        """The chosen model with its numbers, e.g. ``"q ~ 2 h^1.3"`` or ``"q ~ 0.3 / (1.5 + ln(1/h))"``."""
        if self.model == "power":
            return f"q ~ {self.coef:.4g} h^{self.rate:.4g}"
        if self.model == "log":
            return f"q ~ {self.a:.4g} / ({self.b:.4g} + ln(1/h))"
        return ""

    def as_dict(self) -> dict:
        """Plain JSON-able data; no nan or inf anywhere."""
        return {**_plain(self), "formula": self.formula()}


def decay_fit(h, q, name: str = "") -> DecayFit:
    """Fit ``q ~ C h^p`` and ``q ~ a / (b + ln(1/h))`` to a positive quantity that tends to 0; pick the better.

    The power law is a line in ``(ln h, ln q)``; the logarithmic law is a line in ``(ln(1/h), 1/q)``:
    ``1/q = b/a + ln(1/h)/a`` (it needs a positive slope ``1/a`` and ``b + ln(1/h) > 0`` at every size).
    Both are judged by the rms residual in ``ln q`` (two parameters each), so a table can say "decays like
    1/ln N" rather than report a small power.  Non-finite ``q`` are dropped; choosing needs >= 3 sizes.
    """
    h, q, _ = _prepare(h, q, None)
    fin = np.isfinite(q)
    h, q = h[fin], q[fin]
    out = {"name": str(name), "h": tuple(map(float, h)), "q": tuple(map(float, q)), "rate": None, "coef": None,
           "power_residual": None, "a": None, "b": None, "log_residual": None, "model": "", "why": ""}
    if np.any(q <= 0):
        return DecayFit(**{**out, "why": "q is not positive everywhere; a decay fit needs q > 0"})
    if h.size < 2:
        return DecayFit(**{**out, "why": f"only {h.size} size{'' if h.size == 1 else 's'}; a fit needs 2"})
    c0, p = _line(np.log(h), np.log(q))
    rms = lambda r: float(np.sqrt(np.mean(r * r)))                # the residual in ln q
    out.update(rate=p, coef=_num(np.exp(min(c0, 700.0))), power_residual=rms(np.log(q) - c0 - p * np.log(h)))
    x = -np.log(h)
    alpha, beta = _line(x, 1.0 / q)
    den = alpha + beta * x                                     # 1/model = (b + ln(1/h)) / a
    if beta > 0 and np.all(den > 0):
        out.update(a=1.0 / beta, b=alpha / beta, log_residual=rms(np.log(q) + np.log(den)))
    if h.size < 3:
        return DecayFit(**{**out, "why": "only 2 sizes; choosing a model needs 3"})
    log = out["log_residual"] is not None and out["log_residual"] < out["power_residual"]
    return DecayFit(**{**out, "model": "log" if log else "power"})
