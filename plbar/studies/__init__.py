"""Studies: many solves or many evaluations, resumable, locally or on a dask cluster.

One room per study, each with its own front door; the rooms import one way,
``execution < loads < refine < damping < survey < paper`` (checked by
:mod:`plbar.util.layout`), and each from another only through that room's ``__init__``:

* :mod:`.execution` -- study folders, executors, tasks, checkpoints: the machinery every study uses;
* :mod:`.loads` -- every load from one path solve, the worst load (:func:`sweep_loads`,
  :class:`LoadStudy`), and the per-load brute force the tests check it against;
* :mod:`.refine` -- a family followed through N (:func:`run_refine`, :class:`RefineStudy`), observed
  rates and Richardson limits, the check against the scan, modal truncation;
* :mod:`.damping` -- one case for several inherent Rayleigh ratios;
* :mod:`.survey` -- what the bar really does at every forcing period (:func:`run_survey`,
  :class:`Survey`; under mesh refinement :func:`run_survey_refine`, :class:`SurveyRefinement`);
* :mod:`.paper` -- the paper's figures for our numbers.

Every study result is a frozen dataclass with ``files``, ``summary`` and its tables as attributes.
"""

from .damping import RATIOS, DampedRun, ratio_table, with_rayleigh
from .execution import (KINDS, RunOptions, SerialExecutor, Study, StudyError, get_executor, load_results, run_study,
                        solve_task, task_key)
from .loads import (FAMILIES, OTHER, LoadForms, LoadStudy, assign_families, default_positions, load_forms,
                    load_sweep_study, node_pairs, sweep_loads, sweep_tables, write_sweep_tables, xi_along_mesh)
from .paper import FIGURES, make_all
from .refine import Convergence, RefineStudy, TrackSettings, converge, refine_study, run_refine, truncation_check
from .survey import Survey, SurveyRefinement, default_periods, run_survey, run_survey_refine

__all__ = ["KINDS", "RunOptions", "SerialExecutor", "get_executor", "Study", "StudyError", "load_results", "run_study",
           "task_key", "solve_task", "FAMILIES", "OTHER", "assign_families", "sweep_loads", "LoadStudy", "load_forms",
           "LoadForms", "default_positions", "load_sweep_study", "node_pairs", "sweep_tables", "write_sweep_tables",
           "xi_along_mesh", "run_refine", "RefineStudy", "refine_study", "TrackSettings", "converge", "Convergence",
           "truncation_check", "RATIOS", "DampedRun", "ratio_table", "with_rayleigh", "run_survey",
           "run_survey_refine", "Survey", "SurveyRefinement", "default_periods", "FIGURES", "make_all"]
