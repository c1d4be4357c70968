"""The simulator's damped modal flow: steady state plus transient (independent of :mod:`plbar.response`).

With Rayleigh damping each mode obeys ``eta'' + 2 zeta w eta' + w^2 eta = f cos(W u + theta)``
(FORMULATION §8).  Here the solution is written the textbook way, on purpose
differently from :mod:`plbar.response.damped` (divided differences of the
Duhamel kernels):

* the steady harmonic response ``eta_p = Re(f H e^{i(W u + theta)})`` with the
  receptance ``H = 1 / (w^2 - W^2 + 2 i zeta w W)`` (amplitude ``|f H|``, phase lag
  ``arg(w^2 - W^2 + 2 i zeta w W)``);
* plus the free decay of the difference, ``exp(A u) (z0 - z_p(0))`` with the
  2 x 2 block ``A = [[0, 1], [-w^2, -2 zeta w]]`` by Cayley-Hamilton in complex
  arithmetic: ``exp(A u) = e^{-a u} (cosh(mu u) I + sinh(mu u) / mu (A + a I))``,
  ``a = zeta w``, ``mu = sqrt(a^2 - w^2)`` (imaginary when under-damped),
  evaluated as exponentials of ``(+-mu - a) u`` (no overflow) and by the series of
  ``sinh(x) / x`` where ``|mu u|`` is small (the critical neighbourhood).

The steady-state split is exact, but near resonance with very little damping
``|H|`` is large and the two parts cancel: about ``eps / (2 zeta)`` of the
amplitude is lost (1e-12 at ``zeta = 1e-4``); the simulator is a check for
realistic damping ratios.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["damped_flow", "modal_ratios", "flow_rate"]


def modal_ratios(C: np.ndarray, V: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Modal damping ratios ``diag(V^T C V) / (2 w)`` of a damping matrix in mass-normalised modes ``V``."""
    return np.einsum("ij,ik,kj->j", V, C, V) / (2.0 * w)


def flow_rate(w: np.ndarray, zeta: np.ndarray) -> float:
    """The fastest rate of the damped modes, ``max |lambda|`` (for step sizes and quadrature pieces)."""
    a = zeta * w
    mu = np.sqrt(np.maximum(a * a - w * w, 0.0))
    return float(np.max(np.where(a > w, a + mu, w)))


def _shc(x):
    """``sinh(x) / x`` for complex ``x`` with ``|x| < 1`` (series, 1 at 0)."""
    out = np.ones_like(x)
    for k in range(22, 0, -2):
        out = 1.0 + out * x * x / (k * (k + 1))
    return out


def _decay(w, zeta, u):
    """``e^{-a u} cosh(mu u)`` and ``e^{-a u} sinh(mu u) / mu`` (real), for ``u >= 0``."""
    a = zeta * w
    mu = np.sqrt((a * a - w * w).astype(complex))
    x = mu * u
    ep, em = np.exp((mu - a) * u), np.exp((-mu - a) * u)
    ch = 0.5 * (ep + em)
    small = np.abs(x) < 1.0
    mus = np.where(small, 1.0, mu)
    sh = np.where(small, np.exp(-a * u) * u * _shc(np.where(small, x, 0.0)), 0.5 * (ep - em) / mus)
    return ch.real, sh.real


def damped_flow(w, zeta, f, W, theta, tau, eta, v):
    """Exact modal state at ``tau`` of damped modes forced by ``f cos(W u + theta)`` from ``eta, v``.

    Parameters
    ----------
    w, zeta, f : ndarray, shape (m,)
    W, theta : float
    tau : float or ndarray, shape (K,)
    eta, v : ndarray, shape (m,)

    Returns
    -------
    eta, v : ndarray, shape (m,) or (K, m)
    """
    tau = np.asarray(tau, float)
    u = tau[..., None] if tau.ndim else tau
    a = zeta * w
    den = w * w - W * W + 2j * a * W
    if np.any(den == 0):
        raise InputError(f"an undamped mode (zeta = 0) is forced at its resonance W = {W!r}: the steady state does "
                         "not exist; integrate it without damping (zeta=None)")
    P = f / den                                     # steady state: eta_p(u) = Re(P e^{i(W u + theta)})
    ph0 = np.exp(1j * theta)
    ph = ph0 * np.exp(1j * W * u)
    e0, d0 = eta - (P * ph0).real, v - (1j * W * P * ph0).real
    ch, sh = _decay(w, zeta, u)
    # exp(A u) = e^{-a u} [cosh I + sinh/mu (A + a I)],  A + a I = [[a, 1], [-w^2, -a]]
    e = ch * e0 + sh * (a * e0 + d0) + (P * ph).real
    dv = ch * d0 + sh * (-w * w * e0 - a * d0) + (1j * W * P * ph).real
    return e, dv
