"""Small validators shared by the public constructors.

Each returns the value in canonical form (plain Python ``float``/``int``, or
a float array) or raises :class:`plbar.errors.InputError` with a one-line
message naming the offending value, as a plain Python number, and the
allowed range.  Booleans, strings and ``None`` are never numbers.
"""

from __future__ import annotations

import numbers
import warnings

import numpy as np

from ..errors import CoarseGridWarning, InputError

#: allowed range of positive model quantities (lengths, EA, rhoA, masses, stiffnesses)
TINY, HUGE = 1e-24, 1e24
#: scan grids with fewer points than this along an axis get a :class:`CoarseGridWarning`
MIN_GRID_WARN = 20
#: a search interval's non-zero lower end must be at least this times its upper end
MIN_LOW = 1e-9
#: branches with fewer points than this get a :class:`CoarseGridWarning`
MIN_BRANCH_POINTS = 3


def show(value) -> str:
    """``value`` for a message: numbers as plain Python numbers (``0.0``, ``nan``), others by ``repr``."""
    if isinstance(value, (bool, np.bool_)):
        return repr(bool(value))
    if isinstance(value, numbers.Integral):
        return repr(int(value))
    if isinstance(value, numbers.Real):
        return repr(float(value))
    if isinstance(value, np.ndarray) and value.ndim == 0:
        return show(value.item())
    if isinstance(value, (tuple, list)):
        inner = ", ".join(show(v) for v in value)
        return f"({inner})" if isinstance(value, tuple) else f"[{inner}]"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _is_number(value) -> bool:
    if isinstance(value, (bool, np.bool_)):
        return False
    if isinstance(value, np.ndarray) and value.ndim == 0:
        return _is_number(value.item())
    return isinstance(value, numbers.Real)


def number(name: str, value, must: str = "a finite number") -> float:
    """``value`` as a float if it is a real number (not bool, str or None), else raise."""
    if not _is_number(value):
        raise InputError(f"{name} = {show(value)} is not a number ({type(value).__name__}); it must be {must}")
    return float(value)


def finite(name: str, value, must: str = "a finite number") -> float:
    """Return ``value`` as a finite float, else raise."""
    x = number(name, value, must)
    if not np.isfinite(x):
        raise InputError(f"{name} = {show(x)} is not allowed; it must be {must}")
    return x


def positive(name: str, value, *, allow_array: bool = False) -> np.ndarray | float:
    """Return ``value`` as float (or float array) if finite and in ``[TINY, HUGE]``, else raise.

    The bounds keep squares and products of the model's quantities (``EA / L``,
    ``w^2``, ...) inside the floating-point range; physical inputs are far inside.
    """
    must = f"a finite value > 0 (between {TINY:g} and {HUGE:g})"
    if not allow_array or _is_number(value):
        if allow_array is False and isinstance(value, (list, tuple, np.ndarray)) and np.ndim(value) > 0:
            raise InputError(f"{name} must be a single number, got an array of shape {np.shape(value)}")
        x = number(name, value, must)
        if not (np.isfinite(x) and TINY <= x <= HUGE):
            raise InputError(f"{name} = {show(x)} is not allowed; it must be {must}")
        return x
    if isinstance(value, (str, bytes)) or value is None:
        raise InputError(f"{name} = {show(value)} is not a number; it must be {must} (or one per element)")
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {show(value)} is not an array of numbers; it must hold values > 0") from None
    if arr.dtype.kind not in "iuf":
        raise InputError(f"{name} = {show(value)} is not an array of numbers ({arr.dtype}); "
                         f"every entry must be {must}")
    arr = arr.astype(float)
    if arr.size == 0:
        raise InputError(f"{name} is empty; it must be {must} (or one per element)")
    bad = ~np.isfinite(arr) | (arr < TINY) | (arr > HUGE)
    if np.any(bad):
        i = int(np.flatnonzero(bad.ravel())[0])
        raise InputError(f"{name}[{i}] = {show(arr.flat[i])} is not allowed; every entry must be {must}")
    return arr


def integer(name: str, value, lo: int, hi: int | None = None) -> int:
    """``value`` as an int in ``[lo, hi]`` (floats such as ``2.0`` and bools are refused)."""
    rng = f">= {lo}" if hi is None else f"in {lo}..{hi}"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise InputError(f"{name} = {show(value)} is not an integer ({type(value).__name__}); it must be an "
                         f"integer {rng}")
    v = int(value)
    if v < lo or (hi is not None and v > hi):
        raise InputError(f"{name} = {v} is not allowed; it must be an integer {rng}")
    return v


def choice(name: str, value, allowed: tuple[str, ...]) -> str:
    """Return ``value`` if it is one of ``allowed``, else raise."""
    if not isinstance(value, str) or value not in allowed:
        raise InputError(f"{name} = {show(value)} is not allowed; choose one of {', '.join(allowed)}")
    return value


def pair(name: str, value, what: str = "(low, high)") -> tuple:
    """``value`` as a 2-tuple (not a string), else raise."""
    if isinstance(value, (str, bytes, dict)) or value is None:
        raise InputError(f"{name} = {show(value)} must be a pair {what}")
    try:
        items = tuple(value)
    except TypeError:
        raise InputError(f"{name} = {show(value)} must be a pair {what}") from None
    if len(items) != 2:
        raise InputError(f"{name} = {show(value)} must be a pair {what}, got {len(items)} values")
    return items


def pairs(name: str, value, what: str) -> tuple:
    """``value`` as a tuple of 2-tuples (e.g. loads ``((s, a), ...)``), else raise."""
    if isinstance(value, (str, bytes, dict)) or value is None:
        raise InputError(f"{name} = {show(value)} must be a sequence of pairs {what}")
    try:
        items = tuple(value)
    except TypeError:
        raise InputError(f"{name} = {show(value)} must be a sequence of pairs {what}") from None
    return tuple(pair(f"{name} entry", v, what) for v in items)


def interval(name: str, value) -> tuple[float, float]:
    """A search interval ``(low, high]`` with ``0 <= low < high`` finite, as floats."""
    must = "a pair (low, high) with 0 <= low < high, both finite"
    items = pair(name, value, "(low, high) with 0 <= low < high")
    lo, hi = (number(name, v, must) for v in items)
    if not (np.isfinite(lo) and np.isfinite(hi)):
        raise InputError(f"{name} = ({show(lo)}, {show(hi)}) is not allowed; it must be {must}")
    if lo < 0 or hi <= 0:
        raise InputError(f"{name} = ({show(lo)}, {show(hi)}) is not allowed: periods must be > 0; "
                         f"it must be {must}")
    if hi <= lo:
        raise InputError(f"{name} = ({show(lo)}, {show(hi)}) is reversed or empty; it must be {must}")
    if 0 < lo < MIN_LOW * hi:
        raise InputError(f"{name} = ({show(lo)}, {show(hi)}) is not allowed: low must be 0 (the scan then starts "
                         f"at high / N) or at least {MIN_LOW:g} * high = {MIN_LOW * hi:g}")
    return lo, hi


def grid(value, *, warn: bool = True, stacklevel: int = 3) -> tuple[int, int]:
    """A scan grid ``(n1, n2)`` of integers >= 3; warns below :data:`MIN_GRID_WARN` points per axis."""
    must = "must be two integers >= 3 (points along T1 and T2; default 200 200)"
    items = pair("grid", value, "of integers (N1, N2) >= 3")
    for ax, v in zip(("T1", "T2"), items):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Integral):
            raise InputError(f"grid = {show(value)} {must}; {show(v)} along {ax} is not an integer")
        if v < 3:
            raise InputError(f"grid = {show(value)} {must}; {int(v)} along {ax} is too few")
    g = (int(items[0]), int(items[1]))
    if warn and min(g) < MIN_GRID_WARN:
        warnings.warn(f"grid = {g} is coarse: with fewer than {MIN_GRID_WARN} points per axis branches may be "
                      "missed or fragmented (default 200 x 200)", CoarseGridWarning, stacklevel=stacklevel)
    return g
