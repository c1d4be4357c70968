"""Short ``repr`` strings for result objects: class name, sizes and key ranges (never whole arrays).

``arr(a)`` describes an array (``shape (P,) in [lo, hi]``), ``value(v)`` any field value,
and ``build(name, items, lines)`` joins them into ``Name(k=v, ...)``, optionally with indented
lines below (the first few items of a long collection and ``... N more``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["arr", "rng", "count", "value", "build", "listing", "MAX_VALUE"]

MAX_VALUE = 120   #: longest repr of a plain field value kept as is; longer ones are summarised


def rng(a) -> str:
    """``[lo, hi]`` of the finite values of ``a`` (``[]`` if none), 4 significant digits; ``|.|`` for complex."""
    a = np.asarray(a)
    if a.dtype.kind == "c":
        a = np.abs(a)
    if a.dtype.kind not in "biuf" or a.size == 0:
        return "[]"
    a = a[np.isfinite(a)] if a.dtype.kind == "f" else a
    if a.size == 0:
        return "[]"
    return f"[{float(a.min()):.4g}, {float(a.max()):.4g}]"


def count(a) -> str:
    """``k/P`` true entries of a boolean array."""
    a = np.asarray(a, bool)
    return f"{int(a.sum())}/{a.size}"


def arr(a) -> str:
    """``shape (P,) in [lo, hi]`` (numbers), ``k/P true`` (bool), or ``shape (...) <dtype>``."""
    a = np.asarray(a)
    shape = f"shape {a.shape}"
    if a.size == 0:
        return shape
    if a.dtype.kind == "b":
        return f"{shape}, {int(a.sum())} true"
    if a.dtype.kind in "iuf":
        return f"{shape} in {rng(a)}"
    if a.dtype.kind == "c":
        return f"{shape} complex, |.| in {rng(a)}"
    return f"{shape} {a.dtype}"


def value(v) -> str:
    """A field value, short: arrays by :func:`arr`, floats with 6 digits, long reprs as ``<type, len n>``."""
    if isinstance(v, np.ndarray):
        return arr(v)
    if isinstance(v, (bool, np.bool_)) or v is None:
        return repr(bool(v) if v is not None else None)
    if isinstance(v, (float, np.floating)):
        return f"{float(v):.6g}"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, dict) and len(repr(v)) > MAX_VALUE:
        return "{" + ", ".join(map(str, list(v)[:8])) + (", ..." if len(v) > 8 else "") + "}"
    r = repr(v)
    if len(r) <= MAX_VALUE:
        return r
    n = f", len {len(v)}" if hasattr(v, "__len__") else ""
    return f"<{type(v).__name__}{n}>"


def build(name: str, items: dict, lines=()) -> str:
    """``name(k=value(v), ...)``; string values are used as given; ``lines`` go below, indented."""
    body = ", ".join(f"{k}={v if isinstance(v, str) else value(v)}" for k, v in items.items())
    out = f"{name}({body})"
    lines = list(lines)
    return out if not lines else out + "\n" + "\n".join("  " + ln for ln in lines)


def listing(rows, first: int = 5) -> list[str]:
    """The first ``first`` of ``rows`` (strings) and ``... N more`` if there are more."""
    rows = list(rows)
    return rows[:first] + ([f"... {len(rows) - first} more"] if len(rows) > first else [])
