"""Floquet multipliers of a periodic response of any signature: the whole ``m``-period orbit, saltation at every switch.

The stroboscopic map over ``m`` forcing periods, taken in state I modal
coordinates just after the last impact, is linearised exactly
(FORMULATION §7; the one Floquet of plbar, the paper's class included):

``Phi = prod_i  S_imp,i  Phi_II(tau^II_i)  S_open,i  Phi_I(tau^I_i)``

* ``Phi_I``, ``Phi_II``: the closed-form modal flows (the load does not enter the linearisation);
* ``S_open = E + (f_II(E z) - E f_I(z)) dh^T / hdot`` at an opening after a positive dwell
  (``h = -R``, time dependent through the load);
* ``S_imp = Dg + (f^+(g(y)) - Dg f_II(y)) e^T / v_c`` at an impact (``h = x_c``, reset ``g``):
  ``f^+`` is the state I field after a positive-dwell impact, and for a zero dwell (the
  opening follows at once, whatever the perturbation, since the reaction pulls strictly)
  the reset is ``E g`` and ``f^+`` the state II field at ``E g(y)``.
"""

from __future__ import annotations

import numpy as np

from ..model import Problem
from .chain import Chain, compiled, dwell_of, model
from .signature import Signature

__all__ = ["monodromy", "multipliers"]


def monodromy(prob: Problem, sig: Signature, T: float, phi: float, ch: Chain) -> np.ndarray:
    """Jacobian of the ``m``-period map of an evaluated chain's orbit (compiled:
    :mod:`plbar.periodic.kernel.floquet`).

    The section is at ``t = 0+``, in the state the motion continues in: state I
    (``2 m1`` square) when the first pair has a positive dwell, state II after the
    immediate opening (``2 m2``; the impact removes a direction, so two extra zero
    multipliers appear) when it has a zero dwell, and state II when it begins with a rebound (Newton's
    law keeps the dimension: no zero multiplier from the impact, ``e^T`` of the velocity reversed).  With
    inherent damping the vector
    fields take the damper and the opening's event function its share of the reaction.
    """
    md = model(prob)
    n = 2 * (md.tab1 if sig.dwell[0] else md.tab2).shape[1]        # a first rebound: state II too
    M = np.empty((n, n))
    compiled().monodromy(md, dwell_of(sig), float(T), float(phi), ch.times, ch.states, M)
    return M


def multipliers(M: np.ndarray) -> np.ndarray:
    """Eigenvalues of a monodromy matrix (or of each of a stack), by decreasing modulus."""
    mu = np.linalg.eigvals(M)
    return np.take_along_axis(mu, np.argsort(-np.abs(mu), axis=-1), axis=-1)
