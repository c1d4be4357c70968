"""Periodic paths: the scan of ``G`` over ``(T^I, T^II)``, continuation, branches.

* :mod:`.scan` -- grid scan and refinement of sign changes (the one root finder of :mod:`plbar.util.roots`);
* :mod:`.contour` -- marching-squares linking of the crossings;
* :mod:`.continuation` -- pseudo-arclength walkers along the zero curves;
* :mod:`.evaluate` -- true zeros, periodicity, admissible phase of candidate points;
* :mod:`.branches` -- :class:`Branch`, :class:`Paths`, events;
* :mod:`.find` -- :func:`find_paths` (orchestration);
* :mod:`.follow` -- scan-free following of zero curves inside a period window (mesh refinement).
"""

from .branches import FOLD_MU, FOLD_T, GRAZING, NEIMARK_SACKER, PERIOD_DOUBLING, Branch, Domain, Paths, default_domain
from .continuation import Seed, Trace, trace, trace_many
from .evaluate import Evaluated, evaluate
from .follow import Band, correct_onto, follow, follow_one
from .find import find_paths
from .scan import Scan, scan, scan_field

__all__ = ["FOLD_MU", "FOLD_T", "GRAZING", "NEIMARK_SACKER", "PERIOD_DOUBLING", "Branch", "Domain", "Paths",
           "default_domain", "Seed", "Trace", "trace", "trace_many", "Evaluated", "evaluate", "Band", "correct_onto",
           "follow", "follow_one", "find_paths", "Scan", "scan", "scan_field"]
