"""The codes the chain's compiled kernel returns and takes, here so that reading them needs no numba.

:mod:`plbar.periodic.kernel` (numba) uses these; :mod:`plbar.periodic.kernel.newton` returns the corrector's
outcomes and takes the step's mode, :mod:`plbar.periodic.kernel.energy` takes what it computes.
"""

from __future__ import annotations

__all__ = ["FAILED", "CONVERGED", "DONE", "SINGULAR", "ENDED", "FOLLOW", "CHORD", "NEWTON", "PSI", "AMPLITUDE"]

FAILED, CONVERGED, DONE = 0, 1, 2     #: corrector outcomes (converged at its last point, or its last step taken)
SINGULAR = 3                          #: polish: a singular Jacobian
ENDED = 4                             #: step: a duration of the predicted point is not positive
FOLLOW, CHORD, NEWTON = 0, 1, 2       #: step modes: a continuation step; one correction (chord, Newton)
PSI, AMPLITUDE = 0, 1                 #: what the energy kernel computes
