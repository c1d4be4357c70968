"""Builders of a :class:`~plbar.model.Structure`: the finite-element bar and the paper's chain.

The bar (scikit-fem, :func:`plbar.model.assemble`) is clamped at ``x = 0`` with the contact on its last DOF,
``x = L`` (the contact row ``e_{n-1}``, so its contact coordinates are its DOFs); the chain is the bar of
:func:`plbar.model.chain` (Eqs. (23)-(24)).  What built the structure stays with it as a :class:`BarOrigin`
(for its description, its unit point loads and the bar's own studies); the solvers never read it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..util.check import finite
from .bar import Assembled, Bar, assemble
from .load import Load
from .structure import Structure

__all__ = ["BarOrigin", "bar_structure"]


@dataclass(frozen=True)
class BarOrigin:
    """Where a bar's structure came from: the bar, its load (None for a given vector) and its assembly."""

    bar: Bar
    load: Load | None
    asm: Assembled


def bar_structure(bar: Bar, load: Load | None = None, q=None, rayleigh=None, restitution: float = 0.0,
                  asm: Assembled | None = None, gap: float = 0.0, gravity: float = 0.0) -> Structure:
    """The :class:`Structure` of ``bar`` under ``load`` (or the amplitude vector ``q`` over its free DOFs).

    Parameters
    ----------
    bar : Bar
    load : Load, optional
        The harmonic load; or give the amplitude vector ``q`` directly.
    rayleigh : (float, float), optional
        Rayleigh damping ``(alpha, beta)``; default none.
    restitution : float
        Coefficient of restitution of the contact; default 0, the paper's plastic impact.
    asm : Assembled, optional
        ``assemble(bar)`` when it is already at hand.
    gap : float
        The stop's distance from the bar's end at rest (``x_c <= gap``; FORMULATION §9); default 0, the paper.
    gravity : float
        A uniform acceleration along the bar, towards the stop (> 0) or away from it: the constant load
        ``q_s = g b`` with ``b`` the load of a unit uniform acceleration (:attr:`plbar.model.Assembled.body`: the
        whole mass matrix times ones, the clamp's columns included; the consistent body force for a consistent
        mass, since the shape functions sum to 1, the row sums for a lumped one; end masses included).
        Default 0: none.
    """
    if not isinstance(bar, Bar):
        raise InputError(f"bar must be a plbar.Bar (or give a plbar.Structure), got {type(bar).__name__}")
    a = assemble(bar) if asm is None else asm
    if load is not None:
        qv = load.vector(bar, a)
    elif q is not None:
        qv = np.asarray(q, float)
        if qv.shape != (a.n,) or not np.all(np.isfinite(qv)) or not np.any(qv):
            raise InputError(f"load vector q must be finite, non-zero and of length {a.n}")
    else:
        raise InputError("give a load (plbar.point / plbar.node) or a load vector q")
    r = a.contact_row()
    g = finite("gravity", gravity, "a finite number (an acceleration along the bar, > 0 towards the stop)")
    q_s = g * a.body if g else None
    return Structure(a.M, a.K, r, qv, rayleigh, restitution, a.x, BarOrigin(bar, load, a), gap, q_s)
