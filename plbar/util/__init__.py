"""Base layer: validation, atomic file writers, thread pools, BLAS threads, the root finder, a simulation's record.

Nothing here imports another plbar subpackage (only :mod:`plbar.errors`).
"""

from .blas import single_thread_blas
from .record import EVENT, STATUS, Record
from .files import atomic_path, check_finite, write_csv, write_json, write_text
from .roots import Roots, bracketed
from .roots import solve as solve_brackets
from .threads import map_chunks, n_threads

__all__ = ["single_thread_blas", "atomic_path", "check_finite", "write_csv", "write_json", "write_text",
           "Roots", "bracketed", "solve_brackets", "map_chunks", "n_threads", "Record", "EVENT", "STATUS"]
