"""Studies: many solves or many evaluations, resumable, locally or on a dask cluster.

* :mod:`.study` -- resumable task lists (one atomic file per finished task);
* :mod:`.executor` -- local process pool, serial, or dask (``concurrent.futures`` interface);
* :mod:`.tasks` -- the task function (solve one case);
* :mod:`.families` -- branch families across cases;
* :mod:`.loads` -- load-position sweeps (paper Sec. 4.2);
* :mod:`.anchors`, :mod:`.track`, :mod:`.refinement`, :mod:`.refine_tables` -- mesh refinement (paper Sec. 4.3):
  families followed through N with the full model;
* :mod:`.convergence` -- observed rates, Richardson limits, decay laws;
* :mod:`.truncation` -- modal truncation against a finer model;
* :mod:`.figures` -- the paper's figures for our numbers;
* :mod:`.inherent` -- one case for several inherent Rayleigh ratios (issue 21).
"""

from .executor import KINDS, SerialExecutor, get_executor
from .families import FAMILIES, OTHER, assign_families
from .inherent import RATIOS, DampedRun, ratio_table, with_rayleigh
from .loadcases import (default_positions, load_sweep_study, node_pairs, sweep_tables, write_sweep_tables,
                    xi_along_mesh)
from .refinement import refine_study, run_refine
from .study import Study, StudyError, load_results, run_study, task_key
from .tasks import solve_task
from .truncation import truncation_check

__all__ = ["KINDS", "SerialExecutor", "get_executor", "FAMILIES", "OTHER", "assign_families", "default_positions",
           "load_sweep_study", "node_pairs", "sweep_tables", "write_sweep_tables", "xi_along_mesh", "refine_study",
           "run_refine", "Study", "StudyError", "load_results", "run_study", "task_key",
           "solve_task", "truncation_check", "RATIOS", "DampedRun", "ratio_table", "with_rayleigh"]
