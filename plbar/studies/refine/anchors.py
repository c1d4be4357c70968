"""Where a family lives: an anchor period and a relative window around it (mesh refinement).

A family of periodic responses is picked by an *anchor*, a period written in
terms of the fundamental periods of the case, and a relative half-width ``w``:
the family's window is ``T in [A (1 - w), A (1 + w)]`` with
``T^I in (0, T0^I / 2]`` (the paper's range of ``T^I``, Sec. 4.1).

Anchor syntax (case-insensitive): ``T0_I``, ``T0_II``, with an optional factor
and divisor, ``2*T0_I``, ``T0_II/2``, ``3*T0_II/2``, or a plain number (a
period in the model's time unit).  The paper's two paths are ``T0_I`` ("near the
base period of state I") and ``T0_II/2`` ("near half of the base period of
state II").  For a uniform bar ``T0^I = 2 L / c`` for any end mass (state I
holds the contact), so ``k*T0_I`` are the periods at which a wave front sent
into the bar by the impact returns to the contact after ``k`` round trips.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ...errors import InputError
from ...paths.follow import Band
from ...util.check import show

__all__ = ["Anchor", "parse_anchor", "window_band", "DEFAULT_WINDOW", "slug", "family_label", "family_title"]

DEFAULT_WINDOW = 0.15    #: relative half-width of a family's period window (holds the chain's paths at N = 5)

_SPEC = re.compile(r"^\s*(?:(?P<a>[0-9.eE+-]+)\s*\*\s*)?T0_(?P<s>II|I)\s*(?:/\s*(?P<b>[0-9.eE+-]+))?\s*$",
                   re.IGNORECASE)


@dataclass(frozen=True)
class Anchor:
    """An anchor period ``factor * T0^state`` (``state`` None: ``factor`` is the period itself)."""

    spec: str
    state: str | None
    factor: float

    def period(self, T0_I: float, T0_II: float) -> float:
        """The anchor period of a case with fundamental periods ``T0_I``, ``T0_II``."""
        if self.state is None:
            return self.factor
        return self.factor * (T0_I if self.state == "I" else T0_II)

    def __str__(self) -> str:
        return self.spec


def _positive(text: str, spec: str) -> float:
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not v > 0 or v == float("inf"):
        raise InputError(f"family anchor {spec!r}: {text!r} must be a positive number")
    return v


def parse_anchor(spec) -> Anchor:
    """An :class:`Anchor` from its text (``"T0_II/2"``, ``"2*T0_I"``, ``"3.6"``, ...)."""
    if isinstance(spec, Anchor):
        return spec
    if not isinstance(spec, str) or not spec.strip():
        raise InputError(f"family anchor = {show(spec)} must be a string such as T0_I, T0_II/2, 2*T0_I or a period")
    m = _SPEC.match(spec)
    if m is None:
        try:
            return Anchor(spec.strip(), None, _positive(spec.strip(), spec))
        except InputError:
            raise InputError(f"family anchor {spec!r} is not understood; write T0_I, T0_II, k*T0_I, T0_II/k, "
                             "a*T0_II/b (a, b > 0) or a period such as 3.6") from None
    a = _positive(m["a"], spec) if m["a"] else 1.0
    b = _positive(m["b"], spec) if m["b"] else 1.0
    state = m["s"].upper()
    text = (f"{m['a']}*" if m["a"] else "") + f"T0_{state}" + (f"/{m['b']}" if m["b"] else "")
    return Anchor(text, state, a / b)


def window_band(anchor: Anchor, T0_I: float, T0_II: float, width: float = DEFAULT_WINDOW) -> Band:
    """The family window ``T in A (1 -+ width)``, ``T^I in (0, min(T0^I / 2, A (1 - width)))``."""
    if not 0 < width < 1:
        raise InputError(f"window = {show(width)} must be a relative half-width in (0, 1), e.g. 0.15")
    A = anchor.period(T0_I, T0_II)
    lo, hi = A * (1 - width), A * (1 + width)
    return Band((0.0, min(0.5 * T0_I, 0.999 * lo)), (lo, hi))


def slug(text: str) -> str:
    """A file-name-safe form of a family label (``T0_II/2`` -> ``T0_II_over_2``)."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text.replace("/", "_over_").replace("*", "x"))


def family_label(family: str, k: int, count: int) -> str:
    """``T0_II/2``, or ``T0_II/2#2`` for the second of several families seeded in one window."""
    return family if count == 1 else f"{family}#{k + 1}"


def family_title(label: str) -> str:
    """A family label for a plot title: ``T0_II/2`` -> ``family near $T_0^{II}/2$`` (``#2`` -> ``(seed 2)``)."""
    base, _, k = label.partition("#")
    m = _SPEC.match(base)
    if m:
        tex = (f"{m['a']} " if m["a"] else "") + f"$T_0^{{{m['s'].upper()}}}" + (f"/{m['b']}$" if m["b"] else "$")
    else:
        tex = f"T = {base}"
    return f"family near {tex}" + (f" (seed {k})" if k else "")
