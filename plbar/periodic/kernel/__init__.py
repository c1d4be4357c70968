"""The chain and its Newton loops, compiled (numba; imported only when a chain is evaluated).

* :mod:`.stamp` -- the compiler settings: entry points cached on disk, keyed by every source they are built from;
* :mod:`.walk` -- the chain's residuals, their exact Jacobian and its segments, one mode at a time with the
  closed-form flows of :mod:`plbar.motion.kernel.closed` (entry point :func:`chain`);
* :mod:`.newton` -- LU, the tangent, the corrector, a continuation step (entry point :func:`step`) and the
  polish (entry point :func:`polish`);
* :mod:`.floquet` -- the monodromy of an evaluated chain (entry point :func:`monodromy`);
* :mod:`.energy` -- its ``Psi`` sums and contact amplitude (entry point :func:`energy`).
"""

from .energy import AMPLITUDE, PSI, energy
from .floquet import monodromy
from .newton import CHORD, CONVERGED, DONE, ENDED, FAILED, FOLLOW, NEWTON, SINGULAR, polish, step
from .walk import chain

__all__ = ["chain", "step", "polish", "monodromy", "energy", "PSI", "AMPLITUDE", "CHORD", "CONVERGED", "DONE",
           "ENDED", "FAILED", "FOLLOW", "NEWTON", "SINGULAR"]
