"""How the continuum kernels are compiled: :mod:`plbar.util.jit`'s policy, every function cached on its own.

:data:`jit` compiles a kernel function (cached on disk: only the first call after an install or an edit compiles);
:data:`inline` one that is inlined where it is called (the accounts' point evaluation: a call that passes arrays
would pay numba's reference counting on every point).  numba keys a cached function by its own file only: a kernel
calling an edited function of another file would load a stale compilation.  So the cache is stamped with a hash of
every source of this package (:data:`STAMP`): when any of them changed (an edit, an upgrade), :func:`clear_stale`
empties the package's cache folder before anything is loaded from it.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

from ...util import jit as policy

__all__ = ["jit", "inline", "STAMP", "clear_stale"]

_HERE = Path(__file__).resolve().parent
#: hash of this package's sources, the policy's and numba's version
STAMP = policy.stamp([*sorted(_HERE.glob("*.py")), Path(policy.__file__)])


def clear_stale(folder: Path | None = None) -> bool:
    """Empty the kernels' on-disk cache in ``folder`` (this package's, by default) if it was compiled from other
    sources (True if it did)."""
    folder = policy.cache_folder(Path(__file__)) if folder is None else folder
    mark = folder / f"plbar-continuum-{STAMP:x}.stamp"
    if mark.exists() or not folder.is_dir():
        with contextlib.suppress(OSError):
            folder.mkdir(parents=True, exist_ok=True)
            mark.touch()
        return False
    with contextlib.suppress(OSError):
        for f in [*folder.glob("*.nbi"), *folder.glob("*.nbc"), *folder.glob("plbar-continuum-*.stamp")]:
            f.unlink()
        mark.touch()
    return True


clear_stale()
jit = policy.jit(cache=True)
inline = policy.jit(cache=True, inline=True)
