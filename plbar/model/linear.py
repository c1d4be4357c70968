"""The equivalent linear models of a two-state structure: one stiffness, viscous damping, the steady response.

``xi_eq`` exists to be put into a linear model (the paper's Sec. 1): a structure with one stiffness and modal
viscous damping, whose steady response to the harmonic load is in closed form.  Three stiffnesses
(:data:`STIFFNESSES`):

* ``"free"``: state II's (the stop removed: every DOF free), its modes ``w^II_j, V^II``;
* ``"stuck"``: state I's (the contact held: the contact coordinate fixed at 0), its modes ``w^I_j, V^I``;
* ``"bilinear"``: state II's modes with the frequencies of the bilinear oscillator,
  ``w_j = 2 w^I_j w^II_j / (w^I_j + w^II_j)`` for ``j < n`` and ``w^II_n`` for the last.  For one DOF between a
  spring and a stop this is exact: the free vibration of the bilinear oscillator spends half a period in each
  state, ``T_b = pi / w^I + pi / w^II``, so ``w_b = 2 pi / T_b`` is the harmonic mean of the two frequencies; for
  many DOFs it pairs the states' modes by order (the paper's chain: their shapes are close).

Damping (:func:`steady_response`): each mode gets ``c_j = 2 (xi + zeta_j) w_j`` (mass-normalised modes), ``xi``
the ratio given (``xi_eq``) and ``zeta_j`` the structure's own Rayleigh ratio at ``w_j`` (0 undamped):
FORMULATION §5, the ratio of Eq. (22) read as modal damping.  The steady response to ``q cos(W t)`` is, mode by mode,
``eta_j = f_j / (w_j^2 - W^2 + 2 i (xi + zeta_j) w_j W)`` with ``f = V^T q`` and ``x = Re(V eta e^{i W t})``;
over one period the dampers take ``sum_j 2 pi (xi + zeta_j) w_j W |eta_j|^2`` (``= 2 (xi + zeta_j) w_j Psi_j``
with ``Psi_j = int eta_j'^2 dt = pi W |eta_j|^2``: the definition of Eq. (22) holds for the linear model exactly).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .damping import rayleigh_ratio
from .system import Problem

__all__ = ["STIFFNESSES", "LinearModel", "SteadyResponse", "linear_model", "steady_response"]

STIFFNESSES = ("free", "stuck", "bilinear")


@dataclass(frozen=True)
class LinearModel:
    """A linear structure in the problem's coordinates (the contact coordinate last).

    Attributes
    ----------
    stiffness : str
        Which stiffness (:data:`STIFFNESSES`).
    w : ndarray, shape (m,)
        Natural circular frequencies.
    V : ndarray, shape (n, m)
        Mass-normalised modes over all ``n`` coordinates (the stuck model's are zero on the contact coordinate).
    zeta : ndarray, shape (m,)
        The structure's own (Rayleigh) damping ratio of each mode at its frequency; zeros undamped.
    q : ndarray, shape (n,)
        The load amplitude vector.
    """

    stiffness: str
    w: np.ndarray
    V: np.ndarray
    zeta: np.ndarray
    q: np.ndarray


@dataclass(frozen=True)
class SteadyResponse:
    """The steady response of a :class:`LinearModel` to ``q cos(W t)`` with viscous ratio ``xi``.

    Attributes
    ----------
    T, xi : float
    eta : ndarray of complex, shape (m,)
        Modal amplitudes (``eta_j(t) = Re(eta_j e^{i W t})``).
    x : ndarray of complex, shape (n,)
        The coordinates' amplitudes (``x(t) = Re(x e^{i W t})``): ``|x|`` the amplitude of each, ``x[-1]`` the
        contact coordinate's.
    dissipated : float
        Energy the dampers take over one period (``xi`` and the structure's own ``zeta``).
    dissipated_xi : float
        Its part taken by the ratio ``xi`` (what stands for the impact when ``xi = xi_eq``).
    work : float
        Work of the load over one period (equal to ``dissipated``: the balance of a steady response).
    """

    T: float
    xi: float
    eta: np.ndarray
    x: np.ndarray
    dissipated: float
    dissipated_xi: float
    work: float

    @property
    def amplitude_contact(self) -> float:
        """``|x_c|``: the contact coordinate's amplitude."""
        return float(abs(self.x[-1]))


def linear_model(prob: Problem, stiffness: str = "bilinear") -> LinearModel:
    """The equivalent linear model of ``prob`` with the stiffness ``stiffness`` (:data:`STIFFNESSES`; see the
    module docstring)."""
    if stiffness not in STIFFNESSES:
        raise InputError(f"stiffness = {stiffness!r} is not one of {', '.join(STIFFNESSES)}")
    s = prob.system
    if s.truncated:
        raise InputError("a linear model needs every mode of both states (the problem is truncated: modes=)")
    n = s.n
    if stiffness == "stuck":
        w, V = s.w1, np.vstack([s.V1, np.zeros((1, s.w1.size))])
    else:
        w, V = s.w2.copy(), s.V2
        if stiffness == "bilinear":
            w[:-1] = 2 * s.w1 * s.w2[:-1] / (s.w1 + s.w2[:-1])
    zeta = rayleigh_ratio(float(s.alpha), float(s.beta), w) if s.damped else np.zeros(w.size)
    assert V.shape == (n, w.size)
    return LinearModel(stiffness, w, V, np.asarray(zeta, float), np.asarray(prob.q, float))


def steady_response(model: LinearModel, T: float, xi: float) -> SteadyResponse:
    """The steady response of ``model`` to ``q cos(2 pi t / T)`` with the viscous ratio ``xi`` added to every mode
    (see the module docstring).  ``xi`` may be 0 where the structure has its own damping."""
    T, xi = float(T), float(xi)
    if not (np.isfinite(T) and T > 0) or not (np.isfinite(xi) and xi >= 0):
        raise InputError(f"T = {T!r} must be > 0 and xi = {xi!r} >= 0")
    W = 2 * np.pi / T
    z = xi + model.zeta
    if np.any((z == 0) & (np.abs(model.w - W) <= 1e-14 * W)):
        raise InputError(f"T = {T:g} is a natural period of the undamped {model.stiffness} model: no steady response")
    f = model.V.T @ model.q
    eta = f / (model.w ** 2 - W ** 2 + 2j * z * model.w * W)
    psi_w = 2 * np.pi * model.w * W * np.abs(eta) ** 2          # 2 w_j Psi_j of each mode
    diss = float(np.sum(z * psi_w))
    work = float(np.pi * (model.q @ (model.V @ (1j * eta)).conj()).real) if eta.size else 0.0
    return SteadyResponse(T, xi, eta, model.V @ eta, diss, float(xi * np.sum(psi_w)), work)
