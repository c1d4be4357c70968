"""The compiled chain's first compile: whether it is due, and doing it on an orbit of the paper's class.

The chain's kernel (:mod:`plbar.periodic.kernel`) compiles on its first use after an install (or an upgrade of
plbar or numba), undamped and damped apart, and is cached on disk.  :func:`prepare` runs each of its entry points
once -- the chain, the polish, the continuation step, the monodromy, the energy sums -- on one response of the
paper's class, so that a caller can compile it while another process compiles the simulator
(:func:`plbar.motion.compile_elsewhere`).
"""

from __future__ import annotations

import numpy as np

from ..model import Problem
from .chain import compiled as kernel
from .chain import model
from .floquet import monodromy, multipliers
from .follow import FollowSettings, follow
from .signature import PAPER
from .solve import NotConverged, Orbit, orbit_at, polish

__all__ = ["compiled", "prepare"]


def _kind(prob: Problem) -> str:
    return "chain-undamped" if model(prob).damping is None else "chain-damped"


def compiled(prob: Problem) -> bool:
    """Whether the chain's kernel for ``prob`` (undamped or damped) is in the on-disk cache."""
    from ..motion.kernel import jit

    from .kernel.stamp import STAMP

    return jit.is_compiled(kernel().step, _kind(prob), STAMP)


def prepare(prob: Problem, seed: Orbit | None) -> None:
    """Compile (or load) every entry point of the chain's kernel for ``prob`` on ``seed``, an orbit of the paper's
    class (nothing where there is none: the search compiles them as it goes)."""
    from ..motion.kernel import jit

    from .kernel.stamp import STAMP

    if seed is None:
        return
    T, X = seed.T, seed.X
    orb = orbit_at(prob, PAPER, T, X)
    _ = orb.xi, orb.amplitude
    multipliers(monodromy(prob, PAPER, T, orb.phi, orb.chain))
    follow(prob, PAPER, orb, (0.0, np.inf), settings=FollowSettings(max_points=2))
    try:
        polish(prob, PAPER, T, X)
    except NotConverged:
        pass
    jit.mark_compiled(kernel().step, _kind(prob), STAMP)

