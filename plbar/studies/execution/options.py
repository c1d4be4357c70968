"""How a study runs and what it writes besides its tables: :class:`RunOptions`, the keyword options of every study
that writes a folder (:func:`plbar.studies.survey.run_survey`, :func:`plbar.studies.refine.run_refine`, ...)."""

from __future__ import annotations

import concurrent.futures as cf
from dataclasses import dataclass

from ...util.options import collect

__all__ = ["RunOptions", "run_options"]


@dataclass(frozen=True)
class RunOptions:
    """The run options of a study.

    Attributes
    ----------
    executor : concurrent.futures.Executor, optional
        Where the tasks run (:func:`plbar.studies.get_executor`); default serial, in this process.  Not shut down.
    progress : bool
        Show the progress on stderr.
    overwrite : bool
        Allow a folder that holds another study or command's files (:func:`plbar.util.outputs.claim_folder`).
    plot : bool
        Also write the study's figure (needs matplotlib).
    """

    executor: cf.Executor | None = None
    progress: bool = False
    overwrite: bool = False
    plot: bool = True


def run_options(options: dict, func: str, executor: bool = True) -> RunOptions:
    """The keyword ``options`` of the study ``func`` as its :class:`RunOptions`; ``executor=False``: a study that
    runs in this process only (an executor is refused)."""
    opts = collect(RunOptions, options, func)
    if not executor and opts.executor is not None:
        raise TypeError(f"{func}() runs in this process: it takes no executor (its options: progress, overwrite, "
                        "plot)")
    return opts
