"""The long-run motion: a batched, certified event-driven simulator and the accounts of every period.

* :mod:`.model` -- the two-state system padded for a batch in either state;
* :mod:`.margin` -- the admissibility margin, its derivatives and certified bounds;
* :mod:`.events` -- the certified step and the decision at a zero of the margin;
* :mod:`.integrate` -- one batched round: step, switch (opening, plastic impact), period boundary;
* :mod:`.accounting` -- per-piece ``Psi`` sums, work, time stuck, contact amplitude;
* :mod:`.run` -- :func:`run`, many forcing periods at once, and its record :class:`Run`;
* :mod:`.steady` -- :func:`steady`: periodic (stroboscopic period ``m``) or not, loss, ``xi_eq``, ``xi_w``.
"""

from .accounting import Accounts, Pieces, account, piece_amplitude
from .integrate import CHATTER, OK, STALLED
from .model import FREE, STUCK, Padded, padded
from .run import Run, Start, rest, run
from .steady import KINDS, M_MAX, PERIODIC_TOL, Steady, periodicity, steady

__all__ = ["Accounts", "Pieces", "account", "piece_amplitude", "CHATTER", "OK", "STALLED", "FREE", "STUCK", "Padded",
           "padded", "Run", "Start", "rest", "run", "KINDS", "M_MAX", "PERIODIC_TOL", "Steady",
           "periodicity", "steady"]
