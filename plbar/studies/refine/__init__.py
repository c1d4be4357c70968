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

from .anchors import DEFAULT_WINDOW, Anchor, family_label, family_title, parse_anchor, slug, window_band
from .convergence import (AT_LIMIT, MIN_MESHES, NO_CHANGE, NON_FINITE, NOT_CONVERGING, OSCILLATORY, Convergence,
                          caution, converge, known_limit, pair_rates, richardson, triple_rates)
from .decay import DecayFit, decay_fit
from .study import (PLOTTED, REFINE_OWNED, RefineStudy, case_at, parse_series, refine_fingerprint, refine_study,
                    refine_task, run_refine, series_name, track_family)
from .tables import REFINE_HEADER, continuum_periods, convergence_of, family_rows, refine_rows, write_refine
from .track import PICKS, TrackSettings, admissible_runs_of, carry_level, level_points, mark_merges, seed_levels
from .track_check import compare_with_scan, on_curves
from .truncation import truncation_check

__all__ = ["run_refine", "RefineStudy", "refine_study", "refine_task", "track_family", "parse_series",
           "series_name", "case_at", "refine_fingerprint", "REFINE_OWNED", "PLOTTED", "Anchor", "parse_anchor",
           "window_band", "DEFAULT_WINDOW", "slug", "family_label", "family_title", "TrackSettings", "PICKS",
           "seed_levels", "carry_level", "level_points", "admissible_runs_of", "mark_merges", "compare_with_scan",
           "on_curves", "REFINE_HEADER", "family_rows", "refine_rows", "convergence_of", "continuum_periods",
           "write_refine", "AT_LIMIT", "NON_FINITE", "NOT_CONVERGING", "NO_CHANGE", "OSCILLATORY", "Convergence",
           "converge", "known_limit", "pair_rates", "richardson", "triple_rates", "caution", "MIN_MESHES",
           "DecayFit", "decay_fit", "truncation_check"]
