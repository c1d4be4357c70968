"""Impact loss and the equivalent viscous damping ratio (paper Sec. 3).

``Delta_PL`` is the kinetic energy lost at the plastic impact (Eq. (14), in
the momentum-conserving form of FORMULATION §3), evaluated as ``S v_c^2 / 2``
(exact with all modes; no difference of two kinetic energies, so no digits are
lost near grazing); ``Psi_j^alpha`` is the
integral of the squared modal velocity over the state's interval (Eq. (20),
closed form of Appendix 2); ``xi_eq`` solves ``Delta_d = Delta_PL``
(Eqs. (21)-(22)).

With Rayleigh damping (FORMULATION §8) the velocities are the damped ones, the
dampers dissipate ``Delta_v = sum_alpha sum_j 2 zeta_j w_j Psi_j^alpha`` per period,
and the work of the load over a period equals ``Delta_PL + Delta_v``.  ``xi_eq``
(Eq. (22) on the damped velocities) is then the impact's own equivalent ratio;
added to the Rayleigh ratio at the forcing frequency it gives the total.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import TruncationWarning

from ..util.batch import Batch
from ..util.reprs import build, count, rng

from .flow import gauss, psi
from .orbit import Orbits
from .records import Forcing, Modes

__all__ = ["Damping", "damping", "impact_loss", "kinetic_energy_loss", "work_quadrature", "psi_sums", "psi_modes"]


@dataclass(frozen=True)
class Damping(Batch):
    """Energy results for a batch of orbits, each of shape ``(P,)``.

    Attributes
    ----------
    dPL : ndarray
        Impact loss ``Delta_PL`` (Eq. (14)).
    denom : ndarray
        ``sum_j Psi_j^I w_j^I + sum_j Psi_j^II w_j^II`` (Eq. (21) without ``2 xi``).
    xi : ndarray
        ``xi_eq`` (Eq. (22)); ``nan`` never appears: where the denominator is
        zero (a trivial orbit) ``xi`` is 0 and ``closed_form`` tells.
    closed_form : ndarray of bool
        True where every ``Psi_j`` came from the closed form (False near
        resonance, where Gauss quadrature of the exact velocity is used).
    kinetic : ndarray
        ``sum_alpha sum_j Psi_j^alpha = int v^T M v dt`` over the period (mass-normalised modes).
    xi_w : ndarray
        ``xi_w = Delta_PL / (2 W int v^T M v dt)``: the same energy balance with one
        frequency for all modes, the forcing's (viscous damping ``c = 2 xi W M``,
        FORMULATION §8).  Eq. (22) weights mode ``j`` by ``w_j``, a half-derivative
        norm of the velocity that grows like ``ln N`` for the velocity jump an
        impact leaves; ``xi_w``'s denominator is the time integral of twice the
        kinetic energy, finite in the continuum.
    viscous : ndarray
        Energy dissipated by the Rayleigh dampers over the period,
        ``sum_alpha sum_j 2 zeta_j^alpha w_j^alpha Psi_j^alpha`` (0 without damping).
        On a periodic orbit the work of the load is ``dPL + viscous``.
    zeta_rayleigh : ndarray
        Rayleigh damping ratio at the forcing frequency, ``alpha / (2 W) + beta W / 2``.
    xi_total : ndarray
        ``zeta_rayleigh + xi``: the equivalent viscous ratio of the structure with
        its impact, for a linear analysis at this forcing frequency (README,
        "Inherent damping").
    """

    dPL: np.ndarray
    denom: np.ndarray
    xi: np.ndarray
    closed_form: np.ndarray
    kinetic: np.ndarray
    xi_w: np.ndarray
    viscous: np.ndarray
    zeta_rayleigh: np.ndarray
    xi_total: np.ndarray

    def __repr__(self) -> str:
        items = {"P": self.xi.size, "xi": rng(self.xi), "xi_w": rng(self.xi_w), "dPL": rng(self.dPL),
                 "closed_form": count(self.closed_form)}
        if np.any(self.viscous):
            items.update(viscous=rng(self.viscous), zeta_rayleigh=rng(self.zeta_rayleigh))
        return build("Damping", items)


def impact_loss(orb: Orbits) -> np.ndarray:
    """``Delta_PL`` of every orbit (Eq. (14)): ``1/2 S v_c(T^-)^2`` with ``S`` the impact mass.

    With all modes Eq. (14), ``1/2 v^-T M v^- - 1/2 v^+T M_rr v^+``, equals ``1/2 S v_c^2`` exactly
    (:attr:`plbar.TwoStateSystem.impact_mass`, FORMULATION §3), and the product keeps every digit where the
    difference of two kinetic energies loses them (near grazing, ``Delta_PL << E_K``).  A modally truncated
    impact loses more than ``1/2 S v_c^2`` (the energy outside the kept modes): there
    :func:`kinetic_energy_loss`, the difference itself, is returned (and :func:`damping` warns).
    """
    s = orb.prob.system
    if s.truncated:
        return kinetic_energy_loss(orb)
    vc = orb.contact_velocity(orb.T2[:, None])[:, 0]
    return 0.5 * s.impact_mass * vc * vc


def kinetic_energy_loss(orb: Orbits) -> np.ndarray:
    """``1/2 v^-T M v^- - 1/2 v^+T M_rr v^+`` in modal form (Eq. (14) as written: the check of :func:`impact_loss`)."""
    _, v_end = orb.end()
    _, v_plus = orb.after_impact()
    return 0.5 * np.sum(v_end ** 2, axis=1) - 0.5 * np.sum(v_plus ** 2, axis=1)


def psi_modes(orb: Orbits) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``Psi_j^I`` (P, m1) and ``Psi_j^II`` (P, m2) of every mode (Eq. (20)), and the closed-form flag (P,)."""
    s, p = orb.prob.system, orb.prob
    z1, z2 = s.zeta
    W = orb.W[:, None]
    c, sn = np.cos(orb.phi)[:, None], np.sin(orb.phi)[:, None]
    fc = Forcing(W, c, sn)
    psi1, ok1 = psi(Modes(s.w1[None], p.f1[None], z1), fc, 0.0, orb.T1[:, None], orb.eta0, orb.v0)
    psi2, ok2 = psi(Modes(s.w2[None], p.f2[None], z2), fc, orb.T1[:, None], orb.T2[:, None], orb.eta_s, orb.v_s)
    return psi1, psi2, ok1.all(axis=1) & ok2.all(axis=1)


def psi_sums(orb: Orbits, weighted: bool = True):
    """``sum_j Psi_j^alpha w_j^alpha`` for both states and the closed-form flag (``weighted=False``: plain sums too).

    Returns ``(s1, s2, ok)``, or ``(s1, s2, ok, k1, k2)`` with the plain sums ``sum_j Psi_j^alpha``.
    """
    s = orb.prob.system
    psi1, psi2, ok = psi_modes(orb)
    out = (psi1 @ s.w1, psi2 @ s.w2, ok)
    return out if weighted else out + (psi1.sum(axis=1), psi2.sum(axis=1))


def damping(orb: Orbits) -> Damping:
    """``Delta_PL`` and ``xi_eq`` (Eq. (22)) for every orbit.

    Warns (:class:`plbar.errors.TruncationWarning`) for a modally truncated
    system: the impact then projects the velocities onto the kept state I modes
    and counts the kinetic energy outside them as lost, so ``Delta_PL`` and
    ``xi_eq`` are too large (6x at N = 100 with 20 modes); truncation locates
    paths, the full model gives ``xi_eq``.
    """
    s = orb.prob.system
    if s.truncated and len(orb):
        warnings.warn(f"Delta_PL and xi_eq of a modally truncated model ({s.w1.size} + {s.w2.size} of {s.n - 1} + "
                      f"{s.n} modes) count the kinetic energy outside the kept modes as lost at the impact: too "
                      "large; use them to locate paths only and the full model (no modes=) for xi_eq",
                      TruncationWarning, stacklevel=2)
    dpl = impact_loss(orb)
    psi1, psi2, ok = psi_modes(orb)
    denom = psi1 @ s.w1 + psi2 @ s.w2
    xi = np.divide(dpl, 2 * denom, out=np.zeros_like(dpl), where=denom > 0)
    kin = psi1.sum(axis=1) + psi2.sum(axis=1)
    xi_w = np.divide(dpl, 2 * orb.W * kin, out=np.zeros_like(dpl), where=kin > 0)
    if s.damped:
        viscous = 2 * (psi1 @ (s.zeta1 * s.w1) + psi2 @ (s.zeta2 * s.w2))
        zr = s.rayleigh_ratio(orb.W)
    else:
        viscous, zr = np.zeros_like(dpl), np.zeros_like(dpl)
    return Damping(dpl, denom, xi, ok, kin, xi_w, viscous, zr, zr + xi)


def work_quadrature(orb: Orbits, n: int | None = None) -> np.ndarray:
    """Work of the load over one period, ``int q(t) . v(t) dt``, by Gauss-Legendre.

    Independent of :func:`impact_loss`; on a periodic orbit the two agree
    (the impact is the only loss); with damping the work is ``dPL + viscous``.
    """
    p = orb.prob
    if n is None:
        k = (max(p.system.w2.max(), p.system.w1.max()) + orb.W.max()) * orb.T.max()
        n = 20 * int(np.ceil((0.6 * k + 60) / 20))
    x, w = gauss(n)
    out = np.zeros(len(orb))
    for seg, T0, Tl in ((1, 0.0 * orb.T1, orb.T1), (2, orb.T1, orb.T2)):
        tau = 0.5 * Tl[:, None] * (x + 1)
        if seg == 1:
            _, v = orb.state_I(tau)
            f = p.f1
        else:
            _, v = orb.state_II(tau)
            f = p.f2
        force = np.cos(orb.W[:, None] * (T0[:, None] + tau) - orb.phi[:, None])
        out += 0.5 * Tl * np.sum(w * force * (v @ f), axis=1)
    return out
