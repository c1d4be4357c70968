"""Atomic output: a file appears under its final name only when complete."""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["atomic_path", "write_text", "write_json", "write_csv"]


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; rename it to ``path`` on success.

    The temporary name keeps the suffix (writers that pick a format from it
    still work) and starts with ``.`` so it never looks like a result.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".part{path.suffix}", dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)


def write_text(path, text: str) -> Path:
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text)
    return Path(path)


def _jsonable(o):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"not JSON serialisable: {type(o)}")


def write_json(path, data) -> Path:
    return write_text(path, json.dumps(data, indent=2, default=_jsonable, allow_nan=False) + "\n")


def write_csv(path, header: list[str], columns: list[np.ndarray], fmts: list[str]) -> Path:
    """Write columns as CSV; ``fmts`` are %-formats per column."""
    rows = [",".join(header)]
    for vals in zip(*columns):
        rows.append(",".join(f % v for f, v in zip(fmts, vals)))
    return write_text(path, "\n".join(rows) + "\n")
