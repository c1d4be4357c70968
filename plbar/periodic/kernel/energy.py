"""The energy of an evaluated chain's orbit in compiled code: ``Psi`` sums (Eqs. (20)-(22)) and the contact amplitude.

Over the segments :func:`.walk.chain` recorded (``times``, ``zs``), mode by mode: ``Psi = int eta'^2`` by
:func:`plbar.motion.kernel.integrals.psi` (the closed form, or Gauss-Legendre quadrature exact to round-off
where it cancels), summed as ``sum_j w_j Psi_j`` (the denominator of ``xi_eq``), ``sum_j Psi_j`` (that of
``xi_w``) and ``sum_j 2 zeta_j w_j Psi_j`` (the viscous loss); and ``max |x_c|`` over equally spaced samples
of every free phase (:func:`plbar.motion.kernel.closed.mode_flow`).
"""

from __future__ import annotations

from math import cos, pi, sin

from ...motion.kernel.closed import half, mode_flow
from ...motion.kernel.data import Forcing, Mode, ModeState
from ...motion.kernel.integrals import psi
from ..packed import AMPLITUDE, PSI, C, LOAD, W, ZETA
from .stamp import cached

__all__ = ["energy", "PSI", "AMPLITUDE"]


def _energy(stamp):
    def energy(md, dwell, T, phi, times, zs, what, samples):
        """With ``what`` :data:`PSI`: ``(sum w Psi, sum Psi, sum 2 zeta w Psi)`` over every segment; with
        :data:`AMPLITUDE`: ``(max |x_c|, 0, 0)`` over ``samples`` equally spaced points of every free phase."""
        Om, cphi, sphi, damping = 2.0 * pi / T, cos(phi), sin(phi), md.damping
        a, b, c, col = 0.0, 0.0, 0.0, 0
        for i in range(dwell.size if stamp >= 0 else 0):       # (the stamp keys the on-disk cache)
            for s in range(2 if dwell[i] == 1 else 1):
                tab = md.tab1 if s == 0 and dwell[i] == 1 else md.tab2
                m, t0, tau = tab.shape[1], times[col, 0], times[col, 1]
                ld = Forcing(Om, cos(Om * t0), sin(Om * t0), cphi, sphi)
                z = zs[col, 0]
                col += 1
                if what == PSI:
                    hf = half(Om, tau)
                    for j in range(m):
                        w, zeta = tab[W, j], tab[ZETA, j]
                        p = psi(Mode(w, tab[LOAD, j], zeta, 0.0), ld, tau, ModeState(z[j], z[m + j]), damping, hf)
                        a, b, c = a + w * p, b + p, c + 2.0 * zeta * w * p
                elif s == 1 or dwell[i] != 1:
                    for k in range(samples):
                        u = tau if k == samples - 1 else k * (tau / (samples - 1))
                        hf = half(Om, u)
                        g = 0.0
                        for j in range(m):
                            g += tab[C, j] * mode_flow(Mode(tab[W, j], tab[LOAD, j], tab[ZETA, j], 0.0), ld, u,
                                                       ModeState(z[j], z[m + j]), hf, damping)[0]
                        a = max(a, abs(g))
        return a, b, c

    return energy


energy = cached(_energy)   #: the entry point (:func:`_energy`)
