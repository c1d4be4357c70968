"""The application: a :class:`Case` (the one validator of a run's inputs), TOML case files, solving and results.

``Case`` -> :func:`solve` -> :class:`Result` -> :func:`write_results` (``paths.csv``,
``summary.json``); :mod:`.export` picks one response for ParaView and pictures;
:mod:`.job` does everything a case file's ``[output]`` asks.
"""

from .case import Case
from .cost import Cost, cost_note, estimate_cost
from .casefile import OutputSettings, dump_case, load_case, loads_case
from .export import case_of_run, from_run, render_response, select, write_response, write_response_data
from .job import files_of, run_case_file
from .run import CSV_HEADER, TEXT_COLUMNS, Result, case_fingerprint, check_output, read_paths, solve, write_results

__all__ = ["Case", "Cost", "cost_note", "estimate_cost", "OutputSettings", "dump_case", "load_case", "loads_case",
           "from_run", "case_of_run", "render_response", "select", "write_response", "write_response_data", "files_of",
           "run_case_file", "CSV_HEADER", "TEXT_COLUMNS", "Result", "case_fingerprint", "check_output", "read_paths",
           "solve", "write_results"]
