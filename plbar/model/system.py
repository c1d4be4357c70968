"""The two-state modal system (paper Sec. 2.2, FORMULATION §§2-3).

State I (stuck): the contact DOF ``c`` is held, ``M^I = M_rr``, ``K^I = K_rr``.
State II (free): all DOFs, ``M^II = M``, ``K^II = K``.  Modes are mass
normalised (``V^T M V = I``, Eq. (2)); the switch matrices project between the
modal spaces (Eqs. (8)-(10)), with the plastic impact conserving the
generalised momenta of the DOFs other than ``c``.

Inherent damping (FORMULATION §8) is Rayleigh, ``C = alpha M + beta K`` on the
whole bar: state I takes ``C_rr``, both states stay diagonal in their undamped
modes with ratios ``zeta_j = alpha / (2 w_j) + beta w_j / 2``, and the state I
reaction gains a term in the modal velocities (``r_v``).  Without damping
(the default, the paper) every quantity is the undamped one.
"""


from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as sla

from .bar import Assembled, Bar
from .builders import bar_structure
from .damping import check_rayleigh, rayleigh_ratio
from ..errors import InputError
from .load import Load
from .matrices import check_matrices
from .modes import floats, kept_modes, state_modes
from .statics import Statics, statics
from .structure import Structure, check_restitution, contact_coordinates
from ..util.reprs import build, rng

__all__ = ["TwoStateSystem", "Problem", "two_state", "problem", "with_load_vector", "check_restitution"]

@dataclass(frozen=True)
class TwoStateSystem:
    """Modal data of both states and the switch maps.

    Attributes
    ----------
    M, K : ndarray, shape (n, n)
        Free-DOF matrices (contact DOF last).
    x : ndarray, shape (n,)
        DOF positions.
    w1, V1 : ndarray, shapes (m1,), (n-1, m1)
        State I circular frequencies and modes (``m1 = n - 1`` unless the
        modes are truncated, see :func:`two_state`).
    w2, V2 : ndarray, shapes (m2,), (n, m2)
        State II circular frequencies and modes (``m2 = n`` unless truncated).
    P12 : ndarray, shape (m2, m1)
        I -> II modal switch (gap opens), positions and velocities alike.
    P21, Q21 : ndarray, shape (m1, m2)
        II -> I modal switch of positions and velocities (plastic impact).
    r_eta : ndarray, shape (m1,)
        Contact reaction in state I per modal coordinate (without the load
        term), ``R = r_eta . eta + r_q cos(w t - phi)``.
    MV1_c : ndarray, shape (m1,)
        ``M_cr V1``, used for the load term of the reaction.
    gap_row : ndarray, shape (m2,)
        ``x_c = gap_row . eta^II`` (row ``c`` of ``V2``).
    lumped : bool
        True if ``M`` is diagonal over the DOFs other than ``c`` and uncoupled from ``c``.
    alpha, beta : float
        Rayleigh damping ``C = alpha M + beta K`` of the whole bar (FORMULATION §8);
        0, 0 (the default): undamped, as in the paper.
    zeta1, zeta2 : ndarray, shapes (m1,), (m2,)
        Modal damping ratios of states I and II, ``zeta_j = alpha / (2 w_j) + beta w_j / 2``
        (zeros without damping); each mode obeys
        ``eta'' + 2 zeta_j w_j eta' + w_j^2 eta = f_j cos(W t - phi)``.
    r_v : ndarray, shape (m1,)
        Contact reaction in state I per modal *velocity*: with ``x_c = x_c' = 0``,
        ``R = (M x'' + C x' + K x - q)_c = r_eta . eta + r_v . eta' + r_q cos(W t - phi)``,
        ``r_v = C_cr V1 - 2 M_cr V1 diag(zeta1 w1)`` (the damper's share of the
        reaction; ``beta r_eta`` for a lumped mass); zeros without damping.
    """

    M: np.ndarray
    K: np.ndarray
    x: np.ndarray
    w1: np.ndarray
    V1: np.ndarray
    w2: np.ndarray
    V2: np.ndarray
    P12: np.ndarray
    P21: np.ndarray
    Q21: np.ndarray
    r_eta: np.ndarray
    MV1_c: np.ndarray
    gap_row: np.ndarray
    lumped: bool
    alpha: float = 0.0
    beta: float = 0.0
    zeta1: np.ndarray | None = None
    zeta2: np.ndarray | None = None
    r_v: np.ndarray | None = None

    def __post_init__(self):
        ab = check_rayleigh((self.alpha, self.beta))
        a, b = ab if ab is not None else (0.0, 0.0)
        object.__setattr__(self, "alpha", a)
        object.__setattr__(self, "beta", b)
        if a and self.rigid:
            raise InputError(f"Rayleigh damping with alpha = {a:g} > 0 on a structure whose free state moves as a "
                             "rigid body: the mass-proportional part damps the rigid-body motion itself (an "
                             "infinite damping ratio at w = 0), which plbar does not model; use alpha = 0 "
                             "(stiffness-proportional damping only)")
        object.__setattr__(self, "zeta1", rayleigh_ratio(a, b, self.w1))
        object.__setattr__(self, "zeta2", np.where(self.w2 > 0, rayleigh_ratio(a, b, np.where(self.w2 > 0, self.w2,
                                                                                              1.0)), 0.0))
        Mc = self.M[-1, :-1] @ self.V1
        r_v = (a * Mc + b * (self.K[-1, :-1] @ self.V1)) - 2.0 * Mc * self.zeta1 * self.w1
        object.__setattr__(self, "r_v", r_v if ab is not None else np.zeros_like(self.w1))

    @property
    def n(self) -> int:
        return self.x.size

    @property
    def damped(self) -> bool:
        """True with Rayleigh damping (``alpha`` or ``beta`` non-zero)."""
        return self.alpha != 0.0 or self.beta != 0.0

    @property
    def zeta(self) -> tuple[np.ndarray | None, np.ndarray | None]:
        """``(zeta1, zeta2)`` for the flows of :mod:`plbar.response.flow`, or ``(None, None)`` if undamped.

        None selects the undamped code path (bit for bit the paper's flows).
        """
        return (self.zeta1, self.zeta2) if self.damped else (None, None)

    @property
    def C(self) -> np.ndarray:
        """The damping matrix ``alpha M + beta K`` over the free DOFs (zeros without damping)."""
        return self.alpha * self.M + self.beta * self.K

    def rayleigh_ratio(self, W):
        """The Rayleigh damping ratio at circular frequency ``W``: ``alpha / (2 W) + beta W / 2``."""
        return rayleigh_ratio(self.alpha, self.beta, W)

    rigid = property(lambda self: int(np.sum(self.w2 == 0.0)),
                     doc="The number of rigid-body modes of state II (``w = 0``: a free body, a cracked bar's part).")

    floating = property(lambda self: floats(self.w2, self.V2),
                        doc="True if a rigid-body mode of state II moves the contact: no periodic motion has a "
                            "contact then (:func:`plbar.model.modes.floats`).")

    @property
    def truncated(self) -> bool:
        """True if only the lowest modes of a state are kept (rectangular ``V1`` or ``V2``)."""
        return self.w1.size < self.n - 1 or self.w2.size < self.n

    def __repr__(self) -> str:
        T0I, T0II = self.T0
        items = {"n": self.n, "modes": (self.w1.size, self.w2.size), "T0": f"({T0I:.6g}, {T0II:.6g})",
                 "w1": rng(self.w1), "w2": rng(self.w2), "lumped": self.lumped}
        if self.damped:
            items["rayleigh"] = f"({self.alpha:.6g}, {self.beta:.6g})"
        return build("TwoStateSystem", items)

    @property
    def impact_mass(self) -> float:
        """Mass seen by the plastic impact, ``S = M_cc - M_cr M_rr^-1 M_rc`` (FORMULATION §3).

        The impact loss is exactly ``Delta_PL = 1/2 S v_c(T^-)^2`` (Eq. (14)):
        ``M_rr v_r^+ = M_rr v_r^- + M_rc v_c`` gives ``v_r^+ = v_r^- + M_rr^-1 M_rc v_c``, and
        ``v^-T M v^- - v_r^+T M_rr v_r^+ = (M_cc - M_cr M_rr^-1 M_rc) v_c^2`` (the ``v_r^-`` terms cancel).
        For lumped mass ``S = M_cc``.  Exact with all modes; a truncated modal
        impact loses more (see :func:`two_state`).
        """
        Mrc = self.M[:-1, -1]
        return float(self.M[-1, -1] - Mrc @ sla.solve(self.M[:-1, :-1], Mrc, assume_a="pos"))

    @property
    def T0(self) -> tuple[float, float]:
        """Fundamental periods ``(T0^I, T0^II)``; ``T0^I = 0`` where state I has no DOF (a single mass held at the
        stop: infinitely stiff, no period of its own); ``T0^II`` is that of the first elastic mode where state II
        has rigid-body modes (infinite where it has no other)."""
        w2 = self.w2[self.w2 > 0]
        return (2 * np.pi / self.w1[0] if self.w1.size else 0.0), (2 * np.pi / w2[0] if w2.size else np.inf)

    def embed(self, xr: np.ndarray) -> np.ndarray:
        """State I physical vector(s) ``(..., n-1)`` to full DOFs ``(..., n)`` with ``x_c = 0``."""
        out = np.zeros(xr.shape[:-1] + (self.n,))
        out[..., :-1] = xr
        return out


def two_state(M: np.ndarray, K: np.ndarray, x: np.ndarray, modes=None, rayleigh=None) -> TwoStateSystem:
    """Build the two-state modal system from free-DOF matrices (contact last).

    Parameters
    ----------
    M, K : ndarray, shape (n, n)
        Mass and stiffness over the free DOFs, the contact DOF last: finite and symmetric
        (to a relative ``1e-8``), ``M`` positive definite, the stiffness with the contact held (``K_rr``)
        positive definite and that of the free state (``K``) positive semi-definite (a free body: its rigid-body
        modes have ``w = 0``, :func:`plbar.model.modes.state_modes`); else :class:`~plbar.errors.InputError`.
    x : ndarray, shape (n,)
        DOF positions (for output only).
    modes : int or (int, int), optional
        Modal truncation: keep only the lowest ``modes`` modes of each state
        (or ``(m1, m2)`` for states I and II).  ``V1`` is then ``(n-1, m1)``
        and ``V2`` ``(n, m2)``; the switch maps are the Galerkin projections
        of the same formulas (Eqs. (8)-(10)).  Default: all modes (exact).
        Check convergence with :func:`plbar.studies.truncation_check`.
    rayleigh : (float, float), optional
        Rayleigh damping ``(alpha, beta)``, ``C = alpha M + beta K`` (both ``>= 0``);
        default none (the paper).  See :func:`plbar.rayleigh_from_ratio`.
    """
    M, K, x = check_matrices(M, K, x)
    n = M.shape[0]
    if n < 1:
        raise InputError(f"the system needs at least 1 free DOF, got {n}")
    m1, m2 = kept_modes(modes, n)
    Mrr, Krr = M[:-1, :-1], K[:-1, :-1]
    w1, V1 = state_modes(Krr, Mrr, "state I", m1)
    w2, V2 = state_modes(K, M, "state II", m2, rigid=True)
    # I -> II: x^II = E x^I, eta^II = V2^T M E V1 eta^I (Eq. (8) with I, II exchanged)
    P12 = V2.T @ M[:, :-1] @ V1
    # II -> I positions: x_r = R x^II, eta^I = V1^T M_rr R V2 eta^II (Eq. (9))
    P21 = V1.T @ Mrr @ V2[:-1, :]
    # II -> I velocities: M_rr v_r^+ = (M v^-)_r  =>  etadot^I = V1^T (M V2)_r etadot^II
    Q21 = V1.T @ (M @ V2)[:-1, :]
    MV1_c = M[-1, :-1] @ V1
    r_eta = K[-1, :-1] @ V1 - MV1_c * w1**2
    lumped = bool(np.all(M[-1, :-1] == 0) and np.allclose(M[:-1, :-1], np.diag(np.diag(M[:-1, :-1]))))
    a, b = check_rayleigh(rayleigh) or (0.0, 0.0)
    return TwoStateSystem(M, K, x, w1, V1, w2, V2, P12, P21, Q21, r_eta, MV1_c,
                          V2[-1, :].copy(), lumped, a, b)


@dataclass(frozen=True)
class Problem:
    """A structure's two-state modal system with its load: everything the periodic solver needs.

    Attributes
    ----------
    system : TwoStateSystem
        In the structure's contact coordinates (:func:`plbar.model.contact_coordinates`; its DOFs for a bar).
    q : ndarray, shape (n,)
        Load amplitude vector ``q0`` (Eq. (1)) in those coordinates; ``q[:-1]`` acts in state I.
    f1, f2 : ndarray
        Modal forces of states I and II (Eq. (3)).
    r_q : float
        Load term of the state I reaction, ``M_cr V1 f1 - q_c``.
    structure : Structure, optional
        The structure it was built from (None for a system given its load vector directly).
    """

    system: TwoStateSystem
    q: np.ndarray
    f1: np.ndarray
    f2: np.ndarray
    r_q: float
    structure: Structure | None = None

    @property
    def restitution(self) -> float:
        """Coefficient of restitution ``e`` of the contact, ``0 <= e <= 1`` (Newton's impact law): 0 is the
        paper's perfectly plastic impact; only the simulator (:mod:`plbar.motion`) uses ``e > 0``."""
        return self.structure.restitution if self.structure is not None else 0.0

    @property
    def gap(self) -> float:
        """The stop's position ``d`` on the contact coordinate (``u <= d``; 0, the paper)."""
        return self.structure.gap if self.structure is not None else 0.0

    @property
    def q_s(self) -> np.ndarray | None:
        """The constant load (gravity, a prestress) in the system's contact coordinates; None: none."""
        if self.structure is None or self.structure.q_s is None:
            return None
        return self.cached("q_s", lambda p: contact_coordinates(p.structure).q_s)

    @property
    def statics(self) -> Statics:
        """The two states' static equilibria and the constants they add (:mod:`plbar.model.statics`)."""
        return self.cached("statics", lambda p: statics(p.system, p.gap, p.q_s))

    @property
    def affine(self) -> bool:
        """True with a gap or a constant load: the motion has a static part (the paper's scan does not apply)."""
        return not self.statics.zero

    @property
    def static_part(self) -> str:
        """What gives the motion a static part, in words (``"gap = 0.5"``, ``"a constant load"``, both); ``""``
        without."""
        parts = ([f"gap = {self.gap:g}"] if self.gap else []) + (["a constant load"] if self.q_s is not None else [])
        return " and ".join(parts)

    @property
    def origin(self):
        """What built the structure (:class:`plbar.model.BarOrigin` for a bar), or None."""
        return self.structure.origin if self.structure is not None else None

    @property
    def bar(self) -> Bar | None:
        """The bar this problem came from, or None (a structure of other origin)."""
        return getattr(self.origin, "bar", None)

    @property
    def load(self) -> Load | None:
        """The bar's load, or None (a load vector given directly, or a structure of other origin)."""
        return getattr(self.origin, "load", None)

    @property
    def asm(self) -> Assembled | None:
        """The bar's assembly, or None."""
        return getattr(self.origin, "asm", None)

    def __repr__(self) -> str:
        s = self.system
        T0I, T0II = s.T0
        items = {"n": s.n, "modes": (s.w1.size, s.w2.size), "T0": f"({T0I:.6g}, {T0II:.6g})",
                 "q": f"{int(np.count_nonzero(self.q))} non-zero in {rng(self.q)}"}
        if self.bar is not None:
            items["bar"] = repr(self.bar.describe())
        if self.load is not None:
            items["load"] = repr(self.load.describe())
        if self.restitution:
            items["restitution"] = self.restitution
        if self.gap:
            items["gap"] = self.gap
        if self.q_s is not None:
            items["q_s"] = rng(self.q_s)
        return build("Problem", items)

    def under(self, q) -> "Problem":
        """The same system under the load amplitude vector ``q`` (in its coordinates; no eigensolve)."""
        st = self.structure
        if st is not None:
            y = contact_coordinates(st)
            qx = np.asarray(q, float) if y.identity else np.linalg.solve(y.B.T, np.asarray(q, float))
            st = replace(st, q=qx, origin=None if st.origin is None else replace(st.origin, load=None))
        return with_load_vector(self.system, q, st)

    def cached(self, key: str, factory):
        """``factory(self)``, computed once per problem (a private cache of derived constants).

        The entry is keyed on the identity of ``system`` and ``f1``, so it is rebuilt if
        either was swapped on this object.
        """
        k = self.__dict__.get("_cache_" + key)
        if k is None or k[0] is not self.system or k[1] is not self.f1:
            k = (self.system, self.f1, factory(self))
            object.__setattr__(self, "_cache_" + key, k)   # frozen dataclass: a private cache only
        return k[2]


def with_load_vector(sys: TwoStateSystem, q: np.ndarray, structure: Structure | None = None) -> Problem:
    """The problem of ``sys`` under the load amplitude vector ``q`` (modal forces of Eq. (3); no eigensolve).

    ``q`` is in the coordinates of ``sys`` (a bar's DOFs).
    """
    q = np.asarray(q, float)
    f1 = sys.V1.T @ q[:-1]
    f2 = sys.V2.T @ q
    r_q = float(sys.MV1_c @ f1 - q[-1])
    prob = Problem(sys, q, f1, f2, r_q, structure)
    if sys.rigid and structure is not None:
        _ = prob.statics        # a free body's statics refuse a constant load on its rigid motion: now, by name
    return prob


def problem(model, load: Load | None = None, q: np.ndarray | None = None, modes=None,
            rayleigh=None, restitution: float = 0.0, gap: float = 0.0, gravity: float = 0.0) -> Problem:
    """The two-state modal problem of a structure: both states' modes, the switch maps and the load.

    Parameters
    ----------
    model : Structure or Bar
        A :class:`plbar.Structure` (any matrices and contact row; its load, damping and restitution are its
        own), or a :class:`plbar.Bar`, assembled and made one by :func:`plbar.model.bar_structure` with:
    load : Load, optional
        The bar's harmonic load; or give the amplitude vector ``q`` directly.
    rayleigh : (float, float), optional
        The bar's Rayleigh damping ``(alpha, beta)`` (see :func:`two_state`); default none.
    restitution : float
        The bar's coefficient of restitution (:attr:`Problem.restitution`); default 0, the paper's plastic impact.
    gap : float
        The bar's gap at the stop (:attr:`Problem.gap`, :class:`plbar.Structure`); default 0, the paper.
    gravity : float
        A uniform acceleration along the bar towards the stop, the weight of its masses ``g b``
        (:func:`plbar.model.bar_structure`); default 0.
    modes : int or (int, int), optional
        Modal truncation (see :func:`two_state`); default all modes.
    """
    if isinstance(model, Structure):
        if load is not None or q is not None or rayleigh is not None or restitution or gap or gravity:
            raise InputError("a Structure carries its own load, damping, restitution, gap and constant load; give "
                             "them to plbar.Structure(...), not to plbar.problem")
        s = model
    else:
        s = bar_structure(model, load, q, rayleigh, check_restitution(restitution), gap=gap, gravity=gravity)
    y = contact_coordinates(s)
    return with_load_vector(two_state(y.M, y.K, y.x, modes, s.rayleigh), y.q, s)
