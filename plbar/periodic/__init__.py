"""Periodic responses of every contact sequence: signatures, exact orbits, stability, continuation, seeds.

* :mod:`.signature` -- ``m`` periods, ``k`` stuck/free pairs, zero dwells (``"1P"`` is the paper's class);
* :mod:`.chain` -- the segment chain, its switching residuals and their exact Jacobian;
* :mod:`.solve` -- Newton (:func:`polish`) and the orbit's energy (:class:`Orbit`);
* :mod:`.floquet` -- multipliers of the ``m``-period orbit, saltation at every switch;
* :mod:`.verify` -- admissibility, replayed by the certified simulator of :mod:`plbar.motion`;
* :mod:`.follow` -- pseudo-arclength continuation in ``T``;
* :mod:`.seeds` -- the zero-dwell class in closed form, period doublings, simulated motions;
* :mod:`.branches` -- :func:`find_branches`: every branch, the paper's class first (:func:`from_paths`);
* :mod:`.prepare` -- the compiled chain's first compile, due or not, done ahead;
* :mod:`.series` -- one orbit as a time series (export, render), its canonical rotation, rebuilt from a row.
"""

from .branches import KINDS, Branch, find_branches, from_paths
from .chain import Chain, evaluate
from .floquet import monodromy, multipliers
from .follow import FollowSettings, follow
from .prepare import compiled, prepare
from .seeds import doubled, from_motion, zero_dwell
from .series import canonical, from_row, orbit_series
from .signature import ONE_REBOUND, PAPER, ZERO_DWELL, Signature, signature
from .solve import Orbit, NotConverged, orbit_at, polish
from .verify import admissible, expected_events

__all__ = ["KINDS", "Branch", "find_branches", "from_paths",
           "Chain", "evaluate", "monodromy", "multipliers", "FollowSettings",
           "follow", "doubled", "from_motion", "zero_dwell", "PAPER", "ZERO_DWELL", "ONE_REBOUND", "Signature",
           "signature",
           "orbit_series", "canonical", "from_row", "Orbit", "NotConverged", "orbit_at", "polish", "admissible",
           "expected_events", "compiled", "prepare"]
