"""An Euler-Bernoulli beam against a stop: Hermite elements assembled by scikit-fem (issue 41 item 2).

The classic impacting structure of the experiments and the peers' examples: a cantilever whose tip (or any point)
meets a stop (Moon & Shaw 1983, Wagg & Bishop 2002, Siconos' ``ImpactingEulerBernouilliBeam``, NLvib's beam with a
unilateral spring).  The beam's transverse deflection ``w(x)`` and slope ``w'(x)`` at the nodes are its DOFs
(scikit-fem's ``ElementLineHermite``: cubic, exact for the static deflection under point loads and, with the
consistent load vector, under uniform ones):

* stiffness ``K = int EI w'' v'' dx``, consistent mass ``M = int rhoA w v dx`` (plus point masses on the deflection
  of their node; no rotary inertia);
* supports: ``clamped-free`` (a cantilever: ``w = w' = 0`` at ``x = 0``), ``pinned-pinned`` (``w = 0`` at both ends),
  ``clamped-clamped`` (``w = w' = 0`` at both ends);
* the stop on the deflection at ``x = s`` (default the tip of a cantilever, mid-span otherwise): the contact row
  ``r`` is the shape functions at ``s`` (``u = w(s) = r . x``: a general row; at a node, that node's deflection);
* point forces anywhere (the same shape functions), gravity and a shaking support along the deflection (the load of a
  unit transverse acceleration, ``Assembled.body``: the whole mass matrix times the rigid translation ``t``, ones on
  the deflections, zeros on the slopes).

:func:`beam_structure` makes it a :class:`plbar.Structure`: every solver takes it as it takes any structure.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..util.check import choice, finite, pairs, positive
from .structure import Structure

__all__ = ["SUPPORTS", "Beam", "BeamAssembled", "BeamOrigin", "uniform_beam", "assemble_beam", "beam_structure"]

#: the supports a beam can have (its left end first)
SUPPORTS = ("clamped-free", "pinned-pinned", "clamped-clamped")


@dataclass(frozen=True, eq=False)
class Beam:
    """An Euler-Bernoulli beam: its nodes, section and supports.

    Attributes
    ----------
    nodes : ndarray, shape (n + 1,)
        Node positions, increasing from ``x = 0``.
    EI, rhoA : float
        Bending stiffness and mass per unit length (> 0).
    supports : str
        One of :data:`SUPPORTS`.
    point_masses : tuple of (x, m)
        Masses on the deflection of the node at ``x``.
    """

    nodes: np.ndarray
    EI: float = 1.0
    rhoA: float = 1.0
    supports: str = "clamped-free"
    point_masses: tuple = ()

    def __post_init__(self):
        x = np.asarray(self.nodes, float)
        if x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)) or x[0] != 0.0 or np.any(np.diff(x) <= 0):
            raise InputError(f"beam nodes must increase from x = 0 (at least one element), got {self.nodes!r}")
        choice("supports", self.supports, SUPPORTS)
        pm = tuple((finite("point mass position", a), positive("point mass", m))
                   for a, m in pairs("point_masses", self.point_masses, "(x, m)"))
        for a, _ in pm:
            if not np.any(np.isclose(x, a, rtol=0, atol=1e-12 * x[-1])):
                raise InputError(f"a point mass at x = {a:g} is not on a node of the beam")
        for name, v in (("nodes", x), ("EI", positive("EI", self.EI)), ("rhoA", positive("rhoA", self.rhoA)),
                        ("point_masses", pm)):
            object.__setattr__(self, name, v)

    @property
    def length(self) -> float:
        return float(self.nodes[-1])

    def default_contact(self) -> float:
        """Where the stop is unless told: the tip of a cantilever, mid-span otherwise."""
        return self.length if self.supports == "clamped-free" else 0.5 * self.length


def uniform_beam(n: int, length: float = 1.0, EI: float = 1.0, rhoA: float = 1.0, supports: str = "clamped-free",
                 point_masses=()) -> Beam:
    """A beam of ``n`` equal elements."""
    if int(n) != n or n < 1:
        raise InputError(f"a beam needs a positive number of elements, got {n!r}")
    return Beam(np.linspace(0.0, positive("length", length), int(n) + 1), EI, rhoA, supports, point_masses)


@dataclass(frozen=True, eq=False)
class BeamAssembled:
    """The beam's matrices over its free DOFs (sorted by position, the deflection before the slope of a node).

    Attributes
    ----------
    K, M : ndarray, shape (n, n)
    x : ndarray, shape (n,)
        The position of each free DOF.
    slope : ndarray of bool, shape (n,)
        True for a slope DOF ``w'``, False for a deflection ``w``.
    basis : skfem.Basis
        Every DOF, the supported ones included.
    free : ndarray, shape (n,)
        The basis index of each free DOF.
    body : ndarray, shape (n,)
        The load of a unit transverse acceleration (module docstring).
    """

    K: np.ndarray
    M: np.ndarray
    x: np.ndarray
    slope: np.ndarray
    basis: object
    free: np.ndarray
    body: np.ndarray

    @property
    def n(self) -> int:
        return self.x.size

    def row(self, s: float) -> np.ndarray:
        """The shape functions at ``s`` over the free DOFs: ``w(s) = row . x``, and a unit force's load vector; at a
        node (to 1e-12 of the length), that node's deflection exactly (the probe's round-off on its neighbours
        dropped)."""
        xn = self.basis.mesh.p[0]
        k = int(np.argmin(np.abs(xn - s)))
        if abs(xn[k] - s) <= 1e-12 * (xn.max() - xn.min()):
            full = np.zeros(self.basis.N)
            full[self.basis.nodal_dofs[0, k]] = 1.0
            return full[self.free]
        return np.asarray(self.basis.probes(np.array([[float(s)]])).toarray()).ravel()[self.free]


def assemble_beam(beam: Beam) -> BeamAssembled:
    """Assemble ``K`` and ``M`` of ``beam`` with scikit-fem's Hermite element (dense, free DOFs)."""
    from skfem import Basis, BilinearForm, ElementLineHermite, MeshLine, asm
    from skfem.helpers import dd, ddot

    basis = Basis(MeshLine(np.asarray(beam.nodes, float)), ElementLineHermite())
    EI, rhoA = beam.EI, beam.rhoA
    K = asm(BilinearForm(lambda u, v, w: EI * ddot(dd(u), dd(v))), basis).toarray()
    M = asm(BilinearForm(lambda u, v, w: rhoA * u * v), basis).toarray()
    nodal = basis.nodal_dofs                                   # (2, nodes): row 0 the deflection, row 1 the slope
    xn = basis.mesh.p[0]
    for a, m in beam.point_masses:
        M[nodal[0, int(np.argmin(np.abs(xn - a)))], nodal[0, int(np.argmin(np.abs(xn - a)))]] += m
    ends = {"left": int(np.argmin(xn)), "right": int(np.argmax(xn))}
    held = {"clamped-free": [nodal[0, ends["left"]], nodal[1, ends["left"]]],
            "pinned-pinned": [nodal[0, ends["left"]], nodal[0, ends["right"]]],
            "clamped-clamped": [nodal[0, ends["left"]], nodal[1, ends["left"]], nodal[0, ends["right"]],
                                nodal[1, ends["right"]]]}[beam.supports]
    slope = np.zeros(basis.N, bool)
    slope[nodal[1]] = True
    pos = np.zeros(basis.N)
    pos[nodal[0]], pos[nodal[1]] = xn, xn
    free = np.setdiff1d(np.arange(basis.N), held)
    free = free[np.lexsort((slope[free], pos[free]))]
    t = (~slope).astype(float)                                  # a rigid transverse translation
    return BeamAssembled(K[np.ix_(free, free)], M[np.ix_(free, free)], pos[free], slope[free], basis, free,
                         (M @ t)[free])


@dataclass(frozen=True, eq=False)
class BeamOrigin:
    """What built a beam's structure (descriptions; no solver reads it)."""

    beam: Beam
    contact_at: float
    asm: BeamAssembled


def beam_structure(beam: Beam, forces=(), contact_at: float | None = None, rayleigh=None, restitution: float = 0.0,
                   gap: float = 0.0, gravity: float = 0.0, base: float = 0.0,
                   asm: BeamAssembled | None = None) -> Structure:
    """The :class:`plbar.Structure` of ``beam`` against a stop on its deflection at ``contact_at``.

    Parameters
    ----------
    forces : sequence of (s, amplitude)
        Harmonic point forces on the deflection at ``s`` in ``[0, L]``.
    contact_at : float, optional
        The stop's position (default :meth:`Beam.default_contact`); not on a support.
    rayleigh, restitution, gap
        As :class:`plbar.Structure` (the gap on the deflection at ``contact_at``: ``w(s) <= gap``).
    gravity, base : float
        A uniform transverse acceleration (a constant load ``gravity`` times ``body``) and a shaking support (the
        harmonic load ``-base`` times ``body``), towards the stop when positive.
    """
    a = assemble_beam(beam) if asm is None else asm
    s = beam.default_contact() if contact_at is None else finite("contact_at", contact_at)
    if not 0.0 <= s <= beam.length:
        raise InputError(f"contact_at = {s:g} is not on the beam [0, {beam.length:g}]")
    r = a.row(s)
    if not np.any(np.abs(r) > 1e-12):
        raise InputError(f"contact_at = {s:g} is on a support: the deflection there is held already")
    q = -finite("base", base) * a.body
    for x, amp in pairs("forces", forces, "(s, amplitude)"):
        if not 0.0 <= float(x) <= beam.length:
            raise InputError(f"a force at s = {float(x):g} is not on the beam [0, {beam.length:g}]")
        q = q + finite("force amplitude", amp) * a.row(float(x))
    g = finite("gravity", gravity)
    return Structure(a.M, a.K, r, q, rayleigh, restitution, a.x, BeamOrigin(beam, s, a), gap,
                     g * a.body if g else None)
