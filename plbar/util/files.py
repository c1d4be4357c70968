"""Atomic output: a file appears under its final name only when complete.

Writers refuse non-finite numbers (:class:`plbar.errors.NonFiniteError`)
before anything is written, so a nan or inf never reaches a result file.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np

from ..errors import InputError, NonFiniteError

__all__ = ["atomic_path", "write_text", "write_json", "write_csv", "check_finite"]


def _umask() -> int:
    """The process umask (read from /proc where possible: ``os.umask`` is not thread-safe)."""
    with contextlib.suppress(OSError, ValueError):
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _folder(path: Path) -> None:
    """Create the parent folder of ``path``; a plain file in the way is a clear error."""
    parent = path.parent
    for p in (parent, *parent.parents):
        if p.exists() and not p.is_dir():
            raise InputError(f"output folder {str(parent)!r} cannot be created: {str(p)!r} is a file")
        if p.is_dir():
            break
    parent.mkdir(parents=True, exist_ok=True)


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; rename it to ``path`` on success.

    The temporary name keeps the suffix (writers that pick a format from it
    still work) and starts with ``.`` so it never looks like a result.  The
    file gets the usual permissions (``0o666 & ~umask``), not ``mkstemp``'s
    private ``0o600``, and is flushed to disk before the rename.
    """
    path = Path(path)
    _folder(path)
    if path.is_dir():
        raise InputError(f"cannot write {str(path)!r}: it is a folder")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".part{path.suffix}", dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o666 & ~_umask())
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


def _non_finite(data, where: str = ""):
    """The first ``(key path, value)`` in ``data`` that is a non-finite number, or None."""
    if isinstance(data, dict):
        for k, v in data.items():
            hit = _non_finite(v, f"{where}.{k}" if where else str(k))
            if hit:
                return hit
    elif isinstance(data, (list, tuple)):
        for i, v in enumerate(data):
            hit = _non_finite(v, f"{where}[{i}]")
            if hit:
                return hit
    elif isinstance(data, np.ndarray):
        if data.dtype.kind in "fc" and not np.all(np.isfinite(data)):
            i = int(np.flatnonzero(~np.isfinite(data.ravel()))[0])
            return f"{where}[{i}]", data.ravel()[i].item()
    elif isinstance(data, (float, np.floating)) and not math.isfinite(data):
        return where, float(data)
    return None


def check_finite(what: str, data) -> None:
    """Raise :class:`NonFiniteError` naming the first nan/inf in ``data`` (nested dicts/lists/arrays)."""
    hit = _non_finite(data)
    if hit:
        raise NonFiniteError(f"{what}: {hit[0] or 'value'} = {hit[1]!r} is not finite; refusing to write it "
                             "(this is a solver failure: please report the case)")


def write_json(path, data) -> Path:
    """Write ``data`` as JSON (atomically); nan and inf are refused (:class:`NonFiniteError`)."""
    check_finite(Path(path).name, data)
    return write_text(path, json.dumps(data, indent=2, default=_jsonable, allow_nan=False) + "\n")


def write_csv(path, header: list[str], columns: list[np.ndarray], fmts: list[str], *,
              allow_nan: bool = True) -> Path:
    """Write columns as CSV (atomically); ``fmts`` are %-formats per column.

    Infinite values are always refused, and nan too unless ``allow_nan``
    (tables that mark a missing entry, such as a second load position of a
    single-load row, by nan, which is written as an empty field: "nan" never
    appears in a file); :class:`NonFiniteError` names the column and row.
    """
    if len(header) != len(columns) or len(header) != len(fmts):
        raise ValueError(f"write_csv: {len(header)} names, {len(columns)} columns, {len(fmts)} formats")
    if len({len(c) for c in columns}) > 1:
        raise ValueError(f"write_csv: columns of unequal lengths {[len(c) for c in columns]}")
    for name, col in zip(header, columns):
        arr = np.asarray(col)
        if arr.dtype.kind not in "fc":
            continue
        bad = np.isinf(arr) if allow_nan else ~np.isfinite(arr)
        if np.any(bad):
            i = int(np.flatnonzero(bad.ravel())[0])
            raise NonFiniteError(f"{Path(path).name}: column {name!r} row {i + 1} = {arr.ravel()[i].item()!r} is "
                                 "not finite; refusing to write it (this is a solver failure: please report the case)")
    rows = [",".join(header)]
    for vals in zip(*columns):
        rows.append(",".join("" if isinstance(v, (float, np.floating)) and v != v else f % v
                             for f, v in zip(fmts, vals)))
    return write_text(path, "\n".join(rows) + "\n")
