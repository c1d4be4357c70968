"""The compiled kernel of the event-driven simulator (numba; imported only when a simulation runs).

* :mod:`.jit` -- the one compiler setting (cached on disk, no GIL);
* :mod:`.closed` -- closed-form flow of one mode, undamped and damped (Appendix 1);
* :mod:`.integrals` -- ``Psi`` (Eq. (20)) and the work of the load over a piece, closed form or quadrature;
* :mod:`.certify` -- the Taylor model of the margin, its certified remainder, the certified step;
* :mod:`.pieces` -- the accounts of one piece (work, ``Psi`` sums, viscous loss, time stuck, amplitude);
* :mod:`.data` -- the arrays the kernel works on (model, resumable trajectory states, records, named columns);
* :mod:`.loop` -- the event loop: :func:`advance` trajectories to a forcing period.
"""

from . import data
from .loop import advance

__all__ = ["advance", "data"]
