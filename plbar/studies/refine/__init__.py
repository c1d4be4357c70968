"""Mesh refinement (paper Sec. 4.3): a family followed through N with the full model, and its checks.

* :mod:`.study` -- :func:`run_refine` (``plbar refine``): one resumable task per series and family,
  checkpointed per mesh (:class:`RefineStudy`);
* :mod:`.anchors` -- where a family lives: an anchor period and a window around it;
* :mod:`.track` -- the family seeded on the coarsest mesh and carried to the next one;
* :mod:`.track_check` -- the followed family against the full scan of its window;
* :mod:`.tables` -- one row per family and mesh, continuum periods, rates;
* :mod:`.convergence`, :mod:`.decay` -- observed orders, Richardson limits, decay laws, and the
  reasons where there are none (used by the survey's refinement too);
* :mod:`.truncation` -- modal truncation against a finer model.
"""

from .anchors import Anchor, parse_anchor, window_band
from .convergence import (AT_LIMIT, MIN_MESHES, NO_CHANGE, NON_FINITE, NOT_CONVERGING, OSCILLATORY, Convergence,
                          caution, converge, known_limit, pair_rates, richardson, triple_rates)
from .decay import DecayFit, decay_fit
from .study import PLOTTED, REFINE_OWNED, RefineStudy, parse_series, refine_study, run_refine, track_family
from .tables import continuum_periods
from .track import TrackSettings, carry_level, mark_merges, seed_levels
from .track_check import compare_with_scan, on_curves
from .truncation import truncation_check

__all__ = ["run_refine", "RefineStudy", "refine_study", "track_family", "parse_series", "REFINE_OWNED", "PLOTTED",
           "Anchor", "parse_anchor", "window_band", "TrackSettings", "seed_levels", "carry_level", "mark_merges",
           "compare_with_scan", "on_curves", "continuum_periods", "AT_LIMIT", "NON_FINITE", "NOT_CONVERGING",
           "NO_CHANGE", "OSCILLATORY", "Convergence", "converge", "known_limit", "pair_rates", "richardson",
           "triple_rates", "caution", "MIN_MESHES", "DecayFit", "decay_fit", "truncation_check"]
