"""How the continuum kernels are compiled: :mod:`plbar.util.jit`'s one scheme, with reference counting.

:data:`jit` compiles a kernel function, :data:`inline` one that is inlined where it is called (the accounts' point
evaluation, the end's march over a part of a step: a call that passes arrays would pay numba's reference counting
on every point, every part); neither is cached on its own: they are compiled into the entry points Python calls
(:func:`.march.march`, :func:`.fields.w_out_into`, :func:`.fields.invariants_into`, :func:`.accounts.space_into`,
:func:`.accounts.work_into`), which :data:`KERNEL` caches on disk keyed by :data:`STAMP`, the stamp of every source
of this package (an edit or an upgrade compiles afresh).
"""

from __future__ import annotations

from pathlib import Path

from ...util import jit as policy

__all__ = ["KERNEL", "STAMP", "cached", "inline", "jit"]

jit = policy.jit()
inline = policy.jit(inline=True)
KERNEL = policy.kernel(Path(__file__).resolve().parent.glob("*.py"))
STAMP = KERNEL.key
cached = KERNEL.cached
