"""What the chain's compiled kernel takes and returns, named, here so that reading it needs no numba.

* :class:`ChainModel` -- the problem as the kernel walks it (built by :func:`plbar.periodic.chain.model`);
* :class:`Pairs` -- the signature as the kernel walks it (its pairs' kinds, its periods);
* :class:`Walk` -- what one walk of the chain fills (:func:`plbar.periodic.kernel.walk.chain`), and :class:`Jet`,
  the state it carries with its derivative;
* :class:`Control` -- one call of the continuation's step (:func:`plbar.periodic.kernel.newton.step`);
* the codes: the corrector's outcomes and the step's modes (:mod:`plbar.periodic.kernel.newton`), what the energy
  kernel computes (:mod:`plbar.periodic.kernel.energy`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["ChainModel", "Control", "Jet", "Pairs", "Walk", "W", "LOAD", "C", "ZETA", "CV", "FAILED", "CONVERGED",
           "DONE", "SINGULAR", "ENDED", "FOLLOW", "CHORD", "NEWTON", "PSI", "AMPLITUDE"]

W, LOAD, C, ZETA, CV = 0, 1, 2, 3, 4  #: rows of a state's table (:class:`ChainModel`)
FAILED, CONVERGED, DONE = 0, 1, 2     #: corrector outcomes (converged at its last point, or its last step taken)
SINGULAR = 3                          #: polish: a singular Jacobian
ENDED = 4                             #: step: a duration of the predicted point is not positive
FOLLOW, CHORD, NEWTON = 0, 1, 2       #: step modes: a continuation step; one correction (chord, Newton)
PSI, AMPLITUDE = 0, 1                 #: what the energy kernel computes


class ChainModel(NamedTuple):
    """The two-state problem as the compiled chain takes it: per state a table, the switch maps, the margin's load.

    Attributes
    ----------
    tab1, tab2 : ndarray, shape (5, m1), (5, m2)
        ``tab[W | LOAD | C | ZETA | CV, j]`` of state I, II: frequencies, modal loads, the weights of the margin
        (``-r_eta`` in state I, ``-gap_row`` in state II), damping ratios and the damper's share of the reaction
        (zero where there is none).
    E : ndarray, shape (2 m2, 2 m1)
        The opening (``diag(P12, P12)`` on ``(eta, eta')``).
    G : ndarray, shape (2 m1, 2 m2)
        The plastic impact (``diag(P21, Q21)``).
    rq1 : float
        The margin's load term in state I (``-r_q``).
    B : ndarray, shape (2 m2, 2 m2)
        The rebound (Newton's law with the coefficient of restitution).
    damping : ndarray or None
        None undamped (the undamped flows are compiled), else a marker array (the damped ones).
    g0 : ndarray, shape (2,)
        The margins' constants (a gap's, :class:`plbar.model.Statics`: ``-R_I`` in state I, ``d`` in state II).
    offE, offG : ndarray, shapes (2 m2,), (2 m1,)
        What the opening and the impact add to the mapped state (a gap's static equilibria, on the positions).
    """

    tab1: np.ndarray
    tab2: np.ndarray
    E: np.ndarray
    G: np.ndarray
    rq1: float
    B: np.ndarray
    damping: np.ndarray | None
    g0: np.ndarray
    offE: np.ndarray
    offG: np.ndarray


class Pairs(NamedTuple):
    """A signature as the compiled chain walks it: its pairs' kinds ``dwell`` (int64:
    :func:`plbar.periodic.chain.dwell_of`) and its forcing periods ``m``."""

    dwell: np.ndarray
    m: int


class Control(NamedTuple):
    """One call of the continuation's step (:func:`plbar.periodic.kernel.newton.step`): the step ``h`` (scaled
    arclength), the smallest ``h_min`` it may be halved to, Newton's iterations ``newton`` and the ``mode``
    (:data:`FOLLOW`, :data:`CHORD`, :data:`NEWTON`)."""

    h: float
    h_min: float
    newton: int
    mode: int


class Jet(NamedTuple):
    """A state the walk carries and its derivative in the unknowns: ``z`` (``2 m`` modal coordinates, padded) and
    ``D = dz/dX`` (``(2 m, nX)``; a dummy where no Jacobian is computed)."""

    z: np.ndarray
    D: np.ndarray


class Walk(NamedTuple):
    """What a walk of the chain fills (:func:`plbar.periodic.kernel.walk.chain`).

    Attributes
    ----------
    F : ndarray, shape (nX,)
        The residuals.
    J : ndarray, shape (nX, nX), or (0, 0)
        Their Jacobian (not computed where empty).
    times : ndarray, shape (segments, 2)
        Each segment's start time and length.
    zs : ndarray, shape (segments, 2, 2 max(m1, m2))
        Each segment's start and end state (padded).
    zero : ndarray
        The margins just after every impact followed by a zero dwell.
    scale : ndarray, shape (q,)
        The size of the terms of every switching residual.
    vimp : ndarray, shape (pairs,)
        The contact velocity before every impact.
    """

    F: np.ndarray
    J: np.ndarray
    times: np.ndarray
    zs: np.ndarray
    zero: np.ndarray
    scale: np.ndarray
    vimp: np.ndarray
