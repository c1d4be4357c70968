"""Keyword options collected into their record: a function ``f(a, b, **options)`` takes the fields of a frozen
dataclass by name (:func:`collect`), so that the options travel on as one record and callers pass them as before.
"""

from __future__ import annotations

from dataclasses import fields

__all__ = ["collect", "keywords"]


def collect(cls, options: dict, func: str):
    """``cls(**options)``, the keyword ``options`` that ``func`` was given as its record ``cls`` (a dataclass whose
    fields all have defaults); a name that is not a field is a :class:`TypeError` naming ``func`` and its options."""
    names = [f.name for f in fields(cls)]
    bad = [k for k in options if k not in names]
    if bad:
        raise TypeError(f"{func}() got an unexpected keyword argument {bad[0]!r} (its options: {', '.join(names)})")
    return cls(**options)


def keywords(record) -> dict:
    """The fields of a dataclass ``record`` by name, the values themselves (not copies, unlike
    :func:`dataclasses.asdict`): to pass a record on as keyword options."""
    return {f.name: getattr(record, f.name) for f in fields(record)}
