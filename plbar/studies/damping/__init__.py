"""Inherent damping: one case for several Rayleigh ratios, and the impact's share on top of each.

* :mod:`.inherent` -- :func:`with_rayleigh` solves a case with every ratio (:class:`DampedRun`),
  :func:`ratio_table` the table of ``examples/inherent_damping.py``.
"""

from .inherent import RATIOS, DampedRun, ratio_table, with_rayleigh

__all__ = ["RATIOS", "DampedRun", "ratio_table", "with_rayleigh"]
