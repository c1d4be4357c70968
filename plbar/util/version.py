"""The version of plbar (one definition: ``plbar.__version__``, recorded in every result and owner marker) and the
hash of its code (what a study's task key covers besides the task, :func:`code_hash`)."""

import hashlib
from functools import lru_cache
from pathlib import Path

__all__ = ["__version__", "code_hash"]

__version__ = "0.1.0"


@lru_cache(maxsize=1)
def code_hash() -> str:
    """16 hex digits of the SHA-256 of plbar's Python sources (paths and contents): a finished study task is
    reused only by the code that computed it (:func:`plbar.studies.task_key`)."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for f in sorted(root.rglob("*.py")):
        h.update(f.relative_to(root).as_posix().encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()[:16]
