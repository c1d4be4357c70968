"""The exact solution of the uniform continuum bar (issue 29): characteristics, a delay line at the contact end.

The uniform bar clamped at ``x = 0`` with an end mass and a unilateral contact at ``x = L`` is solved by
d'Alembert: the incoming invariant at the end is the outgoing one of ``2L/c`` earlier, reflected by the clamp and
crossed twice by the load, so wave transport and the load are exact; the end mass moves in closed form over each
piece of a grid step, switches (opening, plastic impact) are located by root finding on that closed form.

Front door: :class:`ContinuumBar`, :func:`from_case`, :func:`simulate` -> :class:`ContinuumRun`, :class:`Start` (or
:class:`Field`, a given initial field)
and the closed-form harmonic states :func:`held_closed`, :func:`held_open`.  With Rayleigh damping (a Kelvin-Voigt
bar: no characteristics) :func:`simulate_modal` -> :class:`ModalRun` superposes the exact modes of each contact
state (:mod:`.modal`).
"""

from .bar import ContinuumBar, from_case, natural_periods
from .harmonic import Harmonic, held_closed, held_open
from .modal import ModalOptions, ModalRun, simulate_modal
from .series import ContinuumSeries
from .simulate import ContinuumRun, simulate
from .stepper import Field, Start

__all__ = ["ContinuumBar", "from_case", "natural_periods", "simulate", "ContinuumRun", "ContinuumSeries", "Start",
           "Field", "Harmonic", "held_closed", "held_open", "simulate_modal", "ModalRun", "ModalOptions"]
