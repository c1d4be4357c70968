"""How the kernel is compiled: numba, no GIL, numpy's error model; one cached entry point keyed by every source.

* :data:`jit` compiles the kernel's functions (``nogil=True`` lets :func:`plbar.util.threads.map_chunks` run
  trajectories on every core; ``error_model="numpy"`` makes a division by zero ``inf``/``nan`` as in numpy: the
  closed forms test for it).  They are not cached on their own: they are compiled into the entry point.
  They are compiled without numba's reference counting (``_nrt=False``): every array view and every array taken
  from a tuple would otherwise cost an atomic increment and decrement, measured (perf) at 42 % of the kernel's
  time.  So they allocate nothing: every array they use comes from the entry point (compiled with it), which
  keeps it alive for the whole call.
* :func:`cached` compiles the entry point with an on-disk cache (``__pycache__``), so only the first call after an
  install compiles.  numba keys a cached function by its own file only: a change in a function it calls from
  another file would not be seen (a stale kernel after an edit or an upgrade).  The entry point therefore closes
  over :data:`STAMP`, a hash of every source the kernel is built from, and numba's cache key includes the
  closure's contents: any change of any of them compiles afresh.
"""

from __future__ import annotations

import contextlib
import hashlib
from pathlib import Path

import numba

__all__ = ["SOURCES", "STAMP", "cached", "inline", "is_compiled", "jit", "mark_compiled"]

jit = numba.njit(nogil=True, error_model="numpy", _nrt=False)
#: inlined where called (constants propagate)
inline = numba.njit(nogil=True, error_model="numpy", inline="always", _nrt=False)

_HERE = Path(__file__).resolve().parent
#: the files the compiled kernel is built from (its own modules, and the constants it imports)
SOURCES = tuple(sorted(_HERE.glob("*.py"))) + (_HERE.parent / "model.py", _HERE.parents[1] / "response" / "flow.py")


def _stamp() -> int:
    h = hashlib.sha256()
    for path in SOURCES:
        h.update(path.read_bytes())
    return int(h.hexdigest()[:15], 16)


STAMP = _stamp()   #: 60 bits of the hash of :data:`SOURCES`


def cached(factory):
    """Compile ``factory(STAMP)`` -- a function whose body uses its argument, so that it is in its closure -- with an
    on-disk cache keyed by every kernel source."""
    return numba.njit(cache=True, nogil=True, error_model="numpy")(factory(STAMP))


def _marker(entry, stamp: int, kind: str) -> Path | None:
    """The file that says ``entry`` is compiled for ``kind`` in its on-disk cache (None where numba has none)."""
    folder = getattr(getattr(entry, "_cache", None), "_cache_path", None)
    return Path(folder) / f"plbar-{stamp:x}-numba{numba.__version__}-{kind}.ok" if folder else None


def is_compiled(entry, kind: str, stamp: int = STAMP) -> bool:
    """Whether ``entry`` has been compiled for ``kind`` (one specialisation: a name the caller chooses) with these
    sources and this numba, so that a call loads it from the cache in a fraction of a second: a caller can say
    beforehand that the first call compiles.  Where it cannot tell, True."""
    m = _marker(entry, stamp, kind)
    return m is None or m.exists()


def mark_compiled(entry, kind: str, stamp: int = STAMP) -> None:
    """Record that ``entry`` is compiled for ``kind`` (:func:`is_compiled`); a read-only cache is left alone."""
    m = _marker(entry, stamp, kind)
    if m is not None:
        with contextlib.suppress(OSError):
            m.parent.mkdir(parents=True, exist_ok=True)
            m.touch()
