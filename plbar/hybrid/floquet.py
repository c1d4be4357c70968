"""Floquet multipliers of a periodic response of any signature: the whole ``m``-period orbit, saltation at every switch.

The stroboscopic map over ``m`` forcing periods, taken in state I modal
coordinates just after the last impact, is linearised exactly
(FORMULATION §7, generalising :func:`plbar.response.monodromy_modal`):

``Phi = prod_i  S_imp,i  Phi_II(tau^II_i)  S_open,i  Phi_I(tau^I_i)``

* ``Phi_I``, ``Phi_II``: the closed-form modal flows;
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
from .chain import Chain, flow_matrix, switch_maps, vector_field
from .signature import Signature

__all__ = ["monodromy", "multipliers"]




def monodromy(prob: Problem, sig: Signature, T: float, phi: float, ch: Chain) -> np.ndarray:
    """Jacobian of the ``m``-period map of an evaluated chain's orbit.

    The section is at ``t = 0+``, in the state the motion continues in: state I
    (``2 m1`` square) when the first pair has a positive dwell, state II after the
    immediate opening (``2 m2``; the impact removes a direction, so two extra zero
    multipliers appear) when it has a zero dwell.
    """
    sy = prob.system
    W = 2 * np.pi / T
    E, G = switch_maps(prob)
    m1, m2 = sy.w1.size, sy.w2.size
    f1, f2 = np.asarray(prob.f1, float), np.asarray(prob.f2, float)
    Phi = np.eye(2 * (m1 if sig.dwell[0] else m2))
    segs = iter(ch.segments)
    dh = np.concatenate([-np.asarray(sy.r_eta, float), np.zeros(m1)])
    e = np.concatenate([np.asarray(sy.gap_row, float), np.zeros(m2)])
    for i, positive in enumerate(sig.dwell):
        if positive:
            s = next(segs)
            t = s.t0 + s.tau
            fI = vector_field(sy.w1, f1, W, t, phi, s.z1)
            hdot = dh @ fI + prob.r_q * W * np.sin(W * t - phi)
            jump = vector_field(sy.w2, f2, W, t, phi, E @ s.z1) - E @ fI
            Phi = (E + np.outer(jump, dh) / hdot) @ flow_matrix(sy.w1, s.tau) @ Phi
        s = next(segs)
        t = s.t0 + s.tau
        Phi = flow_matrix(sy.w2, s.tau) @ Phi
        fII = vector_field(sy.w2, f2, W, t, phi, s.z1)
        vc = float(sy.gap_row @ s.z1[m2:])
        if sig.dwell[(i + 1) % sig.k]:
            R = G
            fplus = vector_field(sy.w1, f1, W, t, phi, G @ s.z1)
        else:                                     # zero dwell next: impact and opening at once
            R = E @ G
            fplus = vector_field(sy.w2, f2, W, t, phi, R @ s.z1)
        Phi = (R + np.outer(fplus - R @ fII, e) / vc) @ Phi
    return Phi


def multipliers(M: np.ndarray) -> np.ndarray:
    """Eigenvalues of a monodromy matrix, by decreasing modulus."""
    mu = np.linalg.eigvals(M)
    return mu[np.argsort(-np.abs(mu))]
