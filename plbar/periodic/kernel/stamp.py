"""How the chain's kernel is compiled: :mod:`plbar.util.jit`'s one scheme, with reference counting.

Each entry point (:func:`.walk.chain`, :func:`.newton.step`, :func:`.newton.polish`, :func:`.floquet.monodromy`,
:func:`.energy.energy`) is cached on disk by :data:`KERNEL`, keyed by :data:`STAMP`, a hash of this subpackage's
sources, of the records and codes it takes (:mod:`plbar.periodic.packed`) and of the motion kernel's stamp (its
closed-form flows are compiled in).  The helpers (:data:`jit`) are compiled into the entry points, not cached on
their own.
"""

from __future__ import annotations

from pathlib import Path

from ...motion.kernel.jit import STAMP as MOTION_STAMP
from ...util import jit as policy

__all__ = ["KERNEL", "SOURCES", "STAMP", "cached", "jit"]

jit = policy.jit()   #: the helpers (compiled into the entry points)
_HERE = Path(__file__).resolve().parent
KERNEL = policy.kernel([*_HERE.glob("*.py"), _HERE.parent / "packed.py"], salt=str(MOTION_STAMP))
SOURCES, STAMP = KERNEL.sources, KERNEL.key
cached = KERNEL.cached
