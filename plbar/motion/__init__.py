"""The long-run motion: a compiled, certified event-driven simulator and the accounts of every period.

* :mod:`.model` -- the two-state system padded to one size for both states;
* :mod:`.kernel` -- the compiled kernel (numba, imported when a simulation runs): closed-form flows,
  the certified event search, switches, accounts of every piece, one trajectory at a time;
* :mod:`.run` -- :func:`run`, many forcing periods on every core, and its record :class:`Run`;
* :mod:`.compile` -- the kernel's first compile: due or not, ahead, in another process;
* :mod:`.series` -- :class:`Series`, a motion at any times, vectorised (export, render): a recorded window
  (:func:`motion_series`) or a periodic orbit (:func:`plbar.periodic.orbit_series`);
* :mod:`.steady` -- :func:`steady`: periodic (stroboscopic period ``m``) or not, loss, ``xi_eq``, ``xi_w``.
"""

from .model import CHATTER, FREE, IMPACT, OK, OPENS, REBOUND, STALLED, STICK, STUCK, Padded, padded
from .compile import COMPILE_NOTE, Elsewhere, compile_elsewhere, compiled
from .run import Run, Start, Stopped, energy, given, halt_flag, prepare, rest, run
from .series import Series, boundary_mismatch, motion_series
from .steady import BATCHES, DRIFT_TOL, KINDS, M_MAX, PERIODIC_TOL, T_CRIT, Steady, periodicity, steady, trend

__all__ = [
           "CHATTER",
           "IMPACT",
           "OPENS",
           "REBOUND",
           "STICK",
           "Elsewhere",
           "COMPILE_NOTE",
           "FREE",
           "KINDS",
           "BATCHES",
           "DRIFT_TOL",
           "T_CRIT",
           "trend",
           "M_MAX",
           "Series",
           "motion_series",
           "boundary_mismatch",
           "OK",
           "PERIODIC_TOL",
           "STALLED",
           "STUCK",
           "Padded",
           "Run",
           "Start",
           "Stopped",
           "halt_flag",
           "Steady",
           "compile_elsewhere",
           "compiled",
           "energy",
           "given",
           "padded",
           "periodicity",
           "prepare",
           "rest",
           "run",
           "steady",
]
