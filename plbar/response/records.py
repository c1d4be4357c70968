"""The two records the closed forms of a segment take: the modes and the forcing.

:func:`plbar.response.psi` and the work of the load (:mod:`.power`, :mod:`.damped`) integrate the modal velocity
of a segment: :class:`Modes` are the oscillators (``eta'' + 2 zeta w eta' + w^2 eta = f cos(W t - phi)``), and
:class:`Forcing` the load's frequency and phase.  Their fields broadcast like the arrays they hold.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Modes", "Forcing", "broadcast"]


@dataclass(frozen=True)
class Modes:
    """A mode set: natural circular frequencies ``w`` (> 0), modal load amplitudes ``f`` and damping ratios
    ``zeta`` (None: the undamped code path), broadcast together."""

    w: object
    f: object
    zeta: object = None

    def take(self, sel) -> Modes:
        """The modes at ``sel`` (an index of arrays broadcast to one shape, :func:`broadcast`)."""
        return Modes(self.w[sel], self.f[sel], None if self.zeta is None else self.zeta[sel])


@dataclass(frozen=True)
class Forcing:
    """The load ``cos(W t - phi)``: its circular frequency ``W`` (> 0) and ``cphi, sphi = cos(phi), sin(phi)``."""

    W: object
    cphi: object
    sphi: object

    @classmethod
    def at(cls, W, phi) -> Forcing:
        """The forcing of frequency ``W`` and phase ``phi`` (scalars or arrays)."""
        return cls(W, np.cos(phi), np.sin(phi))

    def take(self, sel) -> Forcing:
        """The forcing at ``sel`` (an index of arrays broadcast to one shape, :func:`broadcast`)."""
        return Forcing(self.W[sel], self.cphi[sel], self.sphi[sel])


def broadcast(modes: Modes, forcing: Forcing, *arrays) -> tuple[Modes, Forcing, list]:
    """``modes``, ``forcing`` and ``arrays`` broadcast to one shape (``np.broadcast_arrays``): ``(modes, forcing,
    arrays)``."""
    z = () if modes.zeta is None else (modes.zeta,)
    w, f, W, c, s, *rest = np.broadcast_arrays(modes.w, modes.f, forcing.W, forcing.cphi, forcing.sphi, *z, *arrays)
    zeta = rest.pop(0) if z else None
    return Modes(w, f, zeta), Forcing(W, c, s), rest
