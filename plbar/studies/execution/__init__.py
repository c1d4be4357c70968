"""The execution machinery every study uses: study folders, executors, tasks, checkpoints.

* :mod:`.study` -- a study is a list of JSON-able tasks; :func:`run_study` runs them on any
  executor into a folder, one atomic result file per finished task, so a rerun resumes;
* :mod:`.executor` -- local process pool, serial, or dask (one ``concurrent.futures`` interface);
* :mod:`.tasks` -- the task function that solves one case and returns its branches as JSON;
* :mod:`.reports` -- progress reported from inside a running task (:func:`report`), read by :func:`run_study`;
* :mod:`.options` -- :class:`RunOptions`, the keyword options (executor, progress, overwrite, plot) of every study
  that writes a folder.
"""

from .executor import KINDS, SerialExecutor, get_executor
from .options import RunOptions, run_options
from .reports import report
from .study import Study, StudyError, load_results, run_study, task_key
from .tasks import branch_arrays, solve_task

__all__ = ["KINDS", "SerialExecutor", "get_executor", "Study", "StudyError", "load_results", "run_study", "task_key",
           "branch_arrays", "solve_task", "report", "RunOptions", "run_options"]
