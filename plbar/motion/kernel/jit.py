"""The one compiler setting of the kernel: ``numba.njit`` with an on-disk cache, no GIL, numpy's error model.

``cache=True`` keeps the machine code beside the sources (``__pycache__``), so only the first call after an
install compiles; ``nogil=True`` lets :func:`plbar.util.threads.map_chunks` run trajectories on every core;
``error_model="numpy"`` makes a division by zero ``inf``/``nan`` as in numpy (the closed forms test for it).
"""

from __future__ import annotations

import numba

__all__ = ["jit"]

jit = numba.njit(cache=True, nogil=True, error_model="numpy")
