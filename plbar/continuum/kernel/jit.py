"""How the continuum kernels are compiled: numba with an on-disk cache, numpy's error model, no GIL.

:data:`jit` compiles a kernel function (cached in ``__pycache__``: only the first call after an install or an
edit compiles); :data:`inline` one that is inlined where it is called (the accounts' point evaluation: a call
that passes arrays would pay numba's reference counting on every point).  numba keys a cached function by its
own file only: a kernel calling an edited function of another file would load a stale compilation.  So the cache
is stamped with a hash of every source of this package (:data:`STAMP`): when any of them changed (an edit, an
upgrade), :func:`clear_stale` empties the package's cache before anything is loaded from it.
"""

from __future__ import annotations

import contextlib
import hashlib
from pathlib import Path

import numba

__all__ = ["jit", "inline", "STAMP", "clear_stale"]

_HERE = Path(__file__).resolve().parent


def _stamp() -> str:
    h = hashlib.sha256(numba.__version__.encode())
    for path in sorted(_HERE.glob("*.py")):
        h.update(path.name.encode() + path.read_bytes())
    return h.hexdigest()[:16]


STAMP = _stamp()   #: hash of this package's sources and numba's version


def clear_stale(folder: Path = _HERE / "__pycache__") -> bool:
    """Empty the kernels' on-disk cache in ``folder`` if it was compiled from other sources (True if it did)."""
    mark = folder / f"plbar-continuum-{STAMP}.stamp"
    if mark.exists() or not folder.is_dir():
        with contextlib.suppress(OSError):
            folder.mkdir(exist_ok=True)
            mark.touch()
        return False
    with contextlib.suppress(OSError):
        for f in [*folder.glob("*.nbi"), *folder.glob("*.nbc"), *folder.glob("plbar-continuum-*.stamp")]:
            f.unlink()
        mark.touch()
    return True


clear_stale()
jit = numba.njit(cache=True, error_model="numpy", nogil=True)
inline = numba.njit(cache=True, error_model="numpy", nogil=True, inline="always")
