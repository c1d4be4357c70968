"""How the motion kernel is compiled: :mod:`plbar.util.jit`'s one scheme, without reference counting.

* :data:`jit` compiles the kernel's functions.  They are not cached on their own: they are compiled into the entry
  point.  They are compiled without numba's reference counting (``nrt=False``): every array view and every array
  taken from a tuple would otherwise cost an atomic increment and decrement, measured (perf) at 42 % of the
  kernel's time.  So they allocate nothing: every array they use comes from the entry point (compiled with it),
  which keeps it alive for the whole call (:data:`alloc`: the one function that allocates it).
* :data:`KERNEL` (:class:`plbar.util.jit.Kernel`) compiles the entry point with the on-disk cache, keyed by
  :data:`STAMP`, the stamp of every source the kernel is built from (its own modules, the constants it imports).
"""

from __future__ import annotations

from pathlib import Path

from ...util import jit as policy

__all__ = ["KERNEL", "SOURCES", "STAMP", "alloc", "cached", "inline", "is_compiled", "jit", "mark_compiled"]

jit = policy.jit(nrt=False)
inline = policy.jit(inline=True, nrt=False)   #: inlined where called (constants propagate)
alloc = policy.jit()   #: a function that allocates (reference counted): the entry point's work space

_HERE = Path(__file__).resolve().parent
#: the kernel's sources: its own modules and the constants it imports (the policy's file is added)
KERNEL = policy.kernel([*_HERE.glob("*.py"), _HERE.parent / "model.py", _HERE.parents[1] / "response" / "flow.py"])
SOURCES, STAMP = KERNEL.sources, KERNEL.key
cached, is_compiled, mark_compiled = KERNEL.cached, KERNEL.is_compiled, KERNEL.mark_compiled
