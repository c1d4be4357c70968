"""A mixin for frozen dataclasses that hold one array entry per item (orbits, verdicts, energies)."""

from __future__ import annotations

from dataclasses import fields

import numpy as np

__all__ = ["Batch"]


class Batch:
    """``take(idx)`` and ``concat(parts)`` along the first axis of every field but those in ``_shared``."""

    _shared: tuple[str, ...] = ()

    def take(self, idx):
        """A subset (or reordering) of the items."""
        return type(self)(**{f.name: getattr(self, f.name) if f.name in self._shared else getattr(self, f.name)[idx]
                             for f in fields(self)})

    @classmethod
    def concat(cls, parts):
        """The items of ``parts`` (instances of this class, shared fields taken from the first) in order."""
        parts = list(parts)
        if len(parts) == 1:
            return parts[0]
        return cls(**{f.name: getattr(parts[0], f.name) if f.name in cls._shared else
                      np.concatenate([getattr(p, f.name) for p in parts]) for f in fields(cls)})
