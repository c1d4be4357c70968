"""How the chain's kernel is compiled: the motion kernel's settings, cached on disk, keyed by every source.

As :func:`plbar.motion.kernel.jit.cached`: numba keys a cached function by its own file only, so each entry
point (:func:`.walk.chain`, :func:`.newton.step`, :func:`.newton.polish`) closes over :data:`STAMP`, a hash of
this subpackage's sources and of the motion kernel's stamp (its closed-form flows are compiled in): any change
of any of them compiles afresh.  The helpers (:data:`plbar.motion.kernel.jit.jit`) are compiled into the entry
points, not cached on their own.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numba

from ...motion.kernel.jit import STAMP as KERNEL_STAMP

__all__ = ["SOURCES", "STAMP", "cached", "jit"]

jit = numba.njit(nogil=True, error_model="numpy")   #: the helpers (compiled into the entry points)
SOURCES = tuple(sorted(Path(__file__).resolve().parent.glob("*.py")))   #: this subpackage's modules


def _stamp() -> int:
    h = hashlib.sha256(str(KERNEL_STAMP).encode())
    for path in SOURCES:
        h.update(path.read_bytes())
    return int(h.hexdigest()[:15], 16)


STAMP = _stamp()   #: 60 bits of the hash of :data:`SOURCES` and of the motion kernel's stamp


def cached(factory):
    """Compile ``factory(STAMP)`` (a function whose body uses its argument, so that it is in its closure) with an
    on-disk cache keyed by :data:`STAMP`."""
    return numba.njit(cache=True, nogil=True, error_model="numpy")(factory(STAMP))
