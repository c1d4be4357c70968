"""How the continuum kernels are compiled: numba with an on-disk cache, numpy's error model, no GIL.

:data:`jit` compiles a kernel function (cached in ``__pycache__``: only the first call after an install or an
edit compiles); :data:`inline` one that is inlined where it is called (the accounts' point evaluation: a call
that passes arrays would pay numba's reference counting on every point).  numba keys a cached function by its
own file; a kernel calling an edited function of another file is recompiled only if its own file changed, so
the kernels live in this small package and are edited together (after an edit of a callee, clear the cache:
``find plbar/continuum/kernel -name '*.nbi' -delete``).
"""

from __future__ import annotations

import numba

__all__ = ["jit", "inline"]

jit = numba.njit(cache=True, error_model="numpy", nogil=True)
inline = numba.njit(cache=True, error_model="numpy", nogil=True, inline="always")
