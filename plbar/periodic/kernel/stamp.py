"""How the chain's kernel is compiled: :mod:`plbar.util.jit`'s policy, cached on disk, keyed by every source.

Each entry point (:func:`.walk.chain`, :func:`.newton.step`, :func:`.newton.polish`) closes over :data:`STAMP`, a
hash of this subpackage's sources and of the motion kernel's stamp (its closed-form flows are compiled in): any
change of any of them compiles afresh.  The helpers (:data:`jit`) are compiled into the entry points, not cached
on their own.
"""

from __future__ import annotations

from pathlib import Path

from ...motion.kernel.jit import STAMP as KERNEL_STAMP
from ...util import jit as policy

__all__ = ["SOURCES", "STAMP", "cached", "jit"]

jit = policy.jit()   #: the helpers (compiled into the entry points)
SOURCES = tuple(sorted(Path(__file__).resolve().parent.glob("*.py")))   #: this subpackage's modules
STAMP = policy.stamp(SOURCES, salt=str(KERNEL_STAMP))   #: hash of :data:`SOURCES` and of the motion kernel's stamp


def cached(factory):
    """Compile ``factory(STAMP)`` with the on-disk cache keyed by :data:`STAMP` (:func:`plbar.util.jit.cached`)."""
    return policy.cached(factory, STAMP)
