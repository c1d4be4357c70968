"""How the motion kernel is compiled: :mod:`plbar.util.jit`'s policy, without reference counting, one cached entry.

* :data:`jit` compiles the kernel's functions.  They are not cached on their own: they are compiled into the entry
  point.  They are compiled without numba's reference counting (``nrt=False``): every array view and every array
  taken from a tuple would otherwise cost an atomic increment and decrement, measured (perf) at 42 % of the
  kernel's time.  So they allocate nothing: every array they use comes from the entry point (compiled with it),
  which keeps it alive for the whole call.
* :func:`cached` compiles the entry point with the on-disk cache, keyed by :data:`STAMP`, the stamp of every source
  the kernel is built from (its own modules, and the constants it imports).
"""

from __future__ import annotations

from pathlib import Path

from ...util import jit as policy

__all__ = ["SOURCES", "STAMP", "cached", "inline", "is_compiled", "jit", "mark_compiled"]

jit = policy.jit(nrt=False)
inline = policy.jit(inline=True, nrt=False)   #: inlined where called (constants propagate)

_HERE = Path(__file__).resolve().parent
#: the files the compiled kernel is built from (its own modules, the constants it imports, the policy)
SOURCES = tuple(sorted(_HERE.glob("*.py"))) + (_HERE.parent / "model.py", _HERE.parents[1] / "response" / "flow.py",
                                               Path(policy.__file__).resolve())
STAMP = policy.stamp(SOURCES)   #: 60 bits of the hash of :data:`SOURCES`


def cached(factory):
    """Compile ``factory(STAMP)`` with the on-disk cache keyed by every kernel source
    (:func:`plbar.util.jit.cached`)."""
    return policy.cached(factory, STAMP)


def is_compiled(entry, kind: str, stamp: int = STAMP) -> bool:
    """Whether ``entry`` is compiled for ``kind`` from these sources (:func:`plbar.util.jit.is_compiled`)."""
    return policy.is_compiled(entry, kind, stamp)


def mark_compiled(entry, kind: str, stamp: int = STAMP) -> None:
    """Record that ``entry`` is compiled for ``kind`` (:func:`plbar.util.jit.mark_compiled`)."""
    policy.mark_compiled(entry, kind, stamp)
