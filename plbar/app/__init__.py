"""The application: a :class:`Case` (the one validator of a run's inputs), TOML case files, solving and results.

``Case`` -> :func:`solve` -> :class:`Result` -> :func:`write_results` (``paths.csv``,
``summary.json``); :mod:`.export` picks one response for ParaView and pictures;
:mod:`.job` does everything a case file's ``[output]`` asks.
"""

from .case import Case
from .cost import Cost, cost_note, estimate_cost
from .casefile import OutputSettings, dump_case, load_case, loads_case
from .start import case_start
from .run import CSV_HEADER, TEXT_COLUMNS, Result, case_fingerprint, check_output, read_paths, solve, write_results

#: the names of :mod:`.export` and :mod:`.job`, imported on first use (a run that exports nothing does not import
#: the writers of ParaView's files)
_LATER = {"case_of_run": "export", "from_run": "export", "render_response": "export", "select": "export",
          "write_response": "export", "write_response_data": "export", "files_of": "job", "run_case_file": "job"}


def __getattr__(name: str):
    if name in _LATER:
        import importlib

        return getattr(importlib.import_module(f".{_LATER[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

__all__ = ["Case", "Cost", "cost_note", "estimate_cost", "OutputSettings", "dump_case", "load_case", "loads_case",
           "from_run", "case_of_run", "render_response", "select", "write_response", "write_response_data", "files_of",
           "run_case_file", "CSV_HEADER", "TEXT_COLUMNS", "Result", "case_fingerprint", "check_output", "read_paths",
           "solve", "write_results", "case_start"]
