"""The outgoing invariant at the end, ``w_out(t) = v(L) + c u_x(L)``, stored piece by piece (the delay line).

Every piece ``[t0, t1)`` holds ``w_out = lin + C cos(omega t) + D sin(omega t)`` with ``lin`` linear from ``a0`` (at
``t0``) to ``a1`` (at ``t1``); jumps sit between pieces.  The bar's whole state at time ``t`` is this record over
``[t - 2L/c, t]`` (d'Alembert: every invariant in the bar left the end, or the clamp, less than ``2L/c`` ago).
"""

from __future__ import annotations

import numpy as np

__all__ = ["History"]


class History:
    """Growing record of the pieces of ``w_out`` (a state holder; the math is in :mod:`.end` and :mod:`.fields`).

    ``step_first[k]`` is the index of the first piece of grid step ``k`` (offset by the steps before ``t = 0``).
    """

    def __init__(self, dt: float, offset: int):
        self.dt, self.offset = dt, offset
        self.k, self.tau0, self.tau1, self.a0, self.a1, self.C, self.D = ([] for _ in range(7))
        self.step_first: list[int] = []

    def begin(self, k: int) -> None:
        self.step_first.append(len(self.k))

    def add(self, k, tau0, tau1, a0, a1, C, D) -> None:
        if tau1 > tau0:
            for lst, v in zip((self.k, self.tau0, self.tau1, self.a0, self.a1, self.C, self.D),
                              (k, tau0, tau1, a0, a1, C, D)):
                lst.append(v)

    def of_step(self, k: int) -> range:
        i = k + self.offset
        end = self.step_first[i + 1] if i + 1 < len(self.step_first) else len(self.k)
        return range(self.step_first[i], end)

    def arrays(self) -> dict[str, np.ndarray]:
        """The pieces as arrays, with absolute times ``t0, t1``."""
        k = np.asarray(self.k, float)
        out = {n: np.asarray(getattr(self, n), float) for n in ("a0", "a1", "C", "D")}
        out["t0"] = k * self.dt + np.asarray(self.tau0)
        out["t1"] = k * self.dt + np.asarray(self.tau1)
        return out
