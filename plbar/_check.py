"""Small validators shared by the public constructors."""

from __future__ import annotations

import numpy as np

from .errors import InputError


def positive(name: str, value, *, allow_array: bool = False) -> np.ndarray | float:
    """Return ``value`` as float (or float array) if finite and > 0, else raise."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r} is not a number; it must be a finite value > 0") from None
    if arr.ndim > 0 and not allow_array:
        raise InputError(f"{name} must be a single number, got an array of shape {arr.shape}")
    if arr.size == 0:
        raise InputError(f"{name} is empty; it must be a finite value > 0")
    bad = ~np.isfinite(arr) | (arr <= 0)
    if np.any(bad):
        first = arr.flat[int(np.flatnonzero(bad.ravel())[0])]
        raise InputError(f"{name} = {first!r} is not allowed; it must be a finite value > 0")
    return float(arr) if arr.ndim == 0 else arr


def finite(name: str, value) -> float:
    """Return ``value`` as a finite float, else raise."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r} is not a number") from None
    if not np.isfinite(x):
        raise InputError(f"{name} = {x!r} is not finite")
    return x


def choice(name: str, value, allowed: tuple[str, ...]) -> str:
    """Return ``value`` if it is one of ``allowed``, else raise."""
    if value not in allowed:
        raise InputError(f"{name} = {value!r} is not allowed; choose one of {', '.join(allowed)}")
    return value
