"""The elastic bar: geometry, section properties and finite-element assembly.

A :class:`Bar` is clamped at ``x = 0``; its last node ``x = L`` is the contact
node (FORMULATION §1).  :func:`assemble` builds the stiffness ``K`` and mass
``M`` over the free DOFs with scikit-fem, ordered by position so that free DOF
``k`` (1-based, as in the paper) is the ``k``-th DOF from the clamp and the
contact DOF is the last one.

A cracked bar (``crack_at = s``, issue 41 item 3) has no stop: its node at ``s`` is two coincident nodes, the
crack's faces (the inner one ends the elements on ``[0, s]``, the outer one starts those on ``[s, L]``: the
mesh is split there, so no element couples them), and the contact is their relative displacement, which closes
the crack (:meth:`Assembled.contact_row`); the end ``x = L`` is free.  Held, the faces move together and the bar
is whole; open, the outer part floats (a rigid-body mode, FORMULATION §9); so does a bar with no support at all.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..util.check import choice, finite, integer, pairs, positive, show
from ..util.reprs import build, rng
from ..errors import InputError
from .crack import split_mesh, supported_crack

__all__ = ["BAR_SUPPORTS", "Bar", "Assembled", "assemble", "chain", "uniform_bar", "graded_nodes", "uniform_nodes",
           "redistributed_block"]

ELEMENTS = ("P1", "P2")
#: a bar's supports: clamped at x = 0, and at x = L free (the stop there, or a crack's free end) or clamped; or no
#: support at all (a free body: the bar dropped or thrown at the stop at x = L)
BAR_SUPPORTS = ("clamped-free", "clamped-clamped", "free-free")
MASSES = ("lumped", "consistent", "redistributed")


#: smallest allowed element length, relative to the bar length
MIN_ELEMENT = 1e-5
#: largest allowed grading ratio (last / first element length) of :func:`graded_nodes`, and smallest 1 / it
MAX_GRADING = 1e3
#: largest allowed ratio of the largest to the smallest EA (or rhoA) of the elements
MAX_CONTRAST = 1e4


def _nodes(nodes) -> np.ndarray:
    """Vertex coordinates as a read-only float array, validated (FORMULATION §1)."""
    if isinstance(nodes, (str, bytes, dict)) or nodes is None:
        raise InputError(f"nodes = {show(nodes)} must be an array of vertex coordinates starting at 0")
    try:
        x = np.array(nodes)
    except (TypeError, ValueError):
        raise InputError(f"nodes = {show(nodes)} must be an array of vertex coordinates starting at 0") from None
    if x.dtype.kind not in "iuf":
        raise InputError(f"nodes = {show(nodes)} must be an array of numbers (got dtype {x.dtype})")
    x = x.astype(float)
    if x.ndim != 1 or x.size < 3:
        raise InputError(f"a bar needs at least 2 elements (3 nodes), got nodes of shape {x.shape}")
    if not np.all(np.isfinite(x)):
        i = int(np.flatnonzero(~np.isfinite(x))[0])
        raise InputError(f"node {i} at x = {show(x[i])} is not allowed; node coordinates must be finite")
    if x[0] != 0.0:
        raise InputError(f"the first node must be the clamp at x = 0, got x = {show(x[0])}")
    d = np.diff(x)
    if np.any(d <= 0):
        i = int(np.flatnonzero(d <= 0)[0])
        kind = "duplicate" if d[i] == 0 else "unsorted"
        raise InputError(f"nodes must be strictly increasing; {kind} nodes at x = {show(x[i])}, "
                         f"{show(x[i + 1])}")
    if d.min() < MIN_ELEMENT * x[-1]:
        i = int(np.argmin(d))
        raise InputError(f"element {i + 1} from x = {show(x[i])} to {show(x[i + 1])} is too short; every element "
                         f"must be at least {MIN_ELEMENT:g} L = {MIN_ELEMENT * x[-1]:g} long")
    x.setflags(write=False)
    return x


def _contrast(name: str, v: np.ndarray) -> None:
    if v.max() > MAX_CONTRAST * v.min():
        raise InputError(f"{name} per element ranges from {show(v.min())} to {show(v.max())}; the ratio "
                         f"{v.max() / v.min():.3g} must be at most {MAX_CONTRAST:g}")


def uniform_nodes(n_elements: int, length: float = 1.0) -> np.ndarray:
    """Vertex coordinates of a uniform mesh, shape ``(n_elements + 1,)``."""
    n = _n_elements(n_elements)
    return np.linspace(0.0, positive("length", length), n + 1)


def graded_nodes(n_elements: int, length: float = 1.0, ratio: float = 1.0) -> np.ndarray:
    """Vertex coordinates graded geometrically.

    Parameters
    ----------
    n_elements : int
        Number of elements (>= 2).
    length : float
        Bar length ``L``.
    ratio : float
        Ratio of the last element's length to the first's (``1`` is uniform,
        ``> 1`` refines towards the clamp, ``< 1`` towards the contact).
    """
    n = _n_elements(n_elements)
    length = positive("length", length)
    ratio = positive("ratio", ratio)
    if not 1.0 / MAX_GRADING <= ratio <= MAX_GRADING:
        raise InputError(f"grading ratio = {show(ratio)} is not allowed; it must lie in "
                         f"[{1 / MAX_GRADING:g}, {MAX_GRADING:g}]")
    if n == 1 or ratio == 1.0:
        return np.linspace(0.0, length, n + 1)
    q = ratio ** (1.0 / (n - 1))
    h = q ** np.arange(n)
    x = np.concatenate([[0.0], np.cumsum(h)])
    return x * (length / x[-1])


def _n_elements(n) -> int:
    n = integer("number of elements", n, 2)
    most = int(np.floor((1.0 - 1e-9) / MIN_ELEMENT))
    if n > most:
        raise InputError(f"number of elements N = {n} is too large: its elements would be shorter than the "
                         f"shortest allowed, {MIN_ELEMENT:g} L; give N <= {most}")
    return n


@dataclass(frozen=True)
class Bar:
    """A 1D bar clamped at ``x = 0`` with a unilateral contact at ``x = L``.

    Parameters
    ----------
    nodes : ndarray, shape (n_vertices,)
        Strictly increasing vertex coordinates starting at 0.
    element : {"P1", "P2"}
        Lagrange element order.
    mass : {"lumped", "consistent", "redistributed"}
        Mass matrix type (lumped = row sum, equal to nodal quadrature; redistributed = consistent, with the
        contact element's mass moved off the contact node, see :func:`redistributed_block`: it needs a
        point mass on the contact node, the end mass, so that the contact DOF keeps an inertia).
    EA, rhoA : float or ndarray, shape (n_elements,)
        Axial stiffness and mass per length, constant or per element.
    point_masses : tuple of (x, m)
        Concentrated masses at vertices.
    name : str
        A label for reports.
    crack_at : float, optional
        A breathing crack at the interior vertex ``s`` (module docstring): the contact is the crack, the end
        ``x = L`` is free.  None (the default): no crack, the stop at ``x = L``.
    supports : {"clamped-free", "clamped-clamped", "free-free"}
        The end ``x = L`` free (the default) or clamped too (a cracked bar only: its contact is the crack); or
        ``"free-free"``, no clamp at all: a free body (its free state moves as a rigid body), the stop at ``x = L``
        (Doyen, Ern and Piperno's falling bar, with ``gravity``).
    """

    nodes: np.ndarray
    element: str = "P1"
    mass: str = "lumped"
    EA: float | np.ndarray = 1.0
    rhoA: float | np.ndarray = 1.0
    point_masses: tuple[tuple[float, float], ...] = ()
    name: str = "bar"
    paper_chain: bool = field(default=False, compare=False)
    crack_at: float | None = None
    supports: str = "clamped-free"

    def __post_init__(self):
        x = _nodes(self.nodes)
        choice("element", self.element, ELEMENTS)
        choice("mass", self.mass, MASSES)
        ne = x.size - 1
        for nm in ("EA", "rhoA"):
            v = positive(nm, getattr(self, nm), allow_array=True)
            if isinstance(v, np.ndarray):
                if v.shape != (ne,):
                    raise InputError(f"{nm} per element must have {ne} values (one per element), got shape {v.shape}")
                _contrast(nm, v)
            object.__setattr__(self, nm, v)
        pm = []
        for item in pairs("point_masses", self.point_masses, "(x, m)"):
            xp, mp = item
            xp = finite("point mass position x", xp, f"a free vertex of the mesh in (0, {x[-1]:g}]")
            mp = positive("point mass", mp)
            j = np.flatnonzero(np.isclose(x, xp, rtol=0, atol=1e-12 * x[-1]))
            if j.size != 1 or (j[0] == 0 and self.supports != "free-free"):
                raise InputError(f"point mass position x = {show(xp)} is not allowed; it must be a free vertex "
                                 f"of the mesh in (0, {x[-1]:g}]")
            pm.append((float(x[j[0]]), mp))
        object.__setattr__(self, "point_masses", tuple(pm))
        choice("supports", self.supports, BAR_SUPPORTS)
        object.__setattr__(self, "crack_at", supported_crack(x, self.crack_at, self.mass, pm, self.supports))
        if self.mass == "redistributed" and not any(xp == x[-1] for xp, _ in pm):
            raise InputError("mass = 'redistributed' leaves the contact node without the bar's inertia, so it "
                             "needs an end mass there: give end_mass > 0 (--end-mass M, or a point mass at "
                             f"x = L = {x[-1]:g}), or use mass = 'consistent' or 'lumped'")
        x.setflags(write=False)
        object.__setattr__(self, "nodes", x)

    length = property(lambda self: float(self.nodes[-1]), doc="Bar length ``L``.")

    @property
    def transit(self) -> float:
        """The waves' transit time ``sum_e h_e / c_e`` (``c_e = sqrt(EA_e / rhoA_e)``; ``L / c`` for a uniform bar,
        ``N`` for the chain): forcing periods in units of it, ``T c / L``, are dimensionless in any units."""
        return float(np.sum(np.diff(self.nodes) / np.sqrt(np.asarray(self.EA, float) / np.asarray(self.rhoA, float))))

    n_elements = property(lambda self: self.nodes.size - 1, doc="Number of elements.")

    @property
    def bar_mass(self) -> float:
        """Mass of the bar itself, ``sum_e rhoA_e h_e`` (without the point masses; ``N m`` for the chain)."""
        return float(np.sum(self.rhoA * np.diff(self.nodes)))

    @property
    def n_dofs(self) -> int:
        """Free DOFs (every node but the clamp; P2 adds a midside node per element; a crack adds its second face)."""
        return (self.n_elements * (1 if self.element == "P1" else 2) + (self.crack_at is not None)
                - (self.supports == "clamped-clamped") + (self.supports == "free-free"))

    def default_load(self) -> float:
        """Where a unit force acts unless told: mid-bar (a fixed position, whatever the mesh), or mid-way along the
        outer part of a bar cracked at mid-bar."""
        s = 0.5 * self.length
        return s if s != self.crack_at else 0.5 * (self.crack_at + self.length)

    def describe(self) -> str:
        return (f"{self.name}: {self.n_elements} {self.element} elements, {self.mass} mass, L = {self.length:g}"
                + (f", point masses {list(self.point_masses)}" if self.point_masses else "")
                + (f", a crack at x = {self.crack_at:g}" if self.crack_at is not None else "")
                + (", clamped at both ends" if self.supports == "clamped-clamped" else "")
                + (", free at both ends (no support)" if self.supports == "free-free" else ""))



def uniform_bar(n_elements: int, *, length: float = 1.0, element: str = "P1", mass: str = "lumped",
                EA: float = 1.0, rhoA: float = 1.0, point_masses=(), name: str | None = None) -> Bar:
    """A bar on a uniform mesh (default: unit length, unit EA and rhoA)."""
    return Bar(uniform_nodes(n_elements, length), element, mass, EA, rhoA, tuple(point_masses),
               name or f"fe-{element}-{mass}-{n_elements}")


def chain(n: int, m: float = 1.0, k: float = 1.0) -> Bar:
    """The paper's chain of ``n`` equal masses ``m`` and ``n`` springs ``k``.

    Built through the FE path (FORMULATION §1): a P1 bar of ``n`` elements of
    unit length with ``EA = k``, ``rhoA = m`` and lumped mass, plus a point
    mass ``m/2`` on the contact node.  Its matrices are Eqs. (23)-(24).
    """
    n = integer("chain size N", n, 2)
    m = positive("m", m)
    k = positive("k", k)
    x = np.arange(n + 1, dtype=float)
    return Bar(x, "P1", "lumped", k, m, ((float(n), m / 2.0),), f"chain-{n}", paper_chain=True)


def redistributed_block(element: str, h: float, rhoA: float) -> np.ndarray:
    """Mass of the contact element over its other nodes, by the mass redistribution method.

    Khenous, Laborde & Renard (2008, Eur. J. Mech. A/Solids 27, 918-932): the contact node carries no
    inertia of the element; the element's mass goes to its other nodes so that its total mass, its centre
    of mass and (where the nodes allow) its moment of inertia are kept.  P1 (one other node, the vertex at
    ``xi = 0``): ``rhoA h``, the total mass only.  P2 (the vertex ``xi = 0`` and the midside node
    ``xi = h/2``): the one symmetric block with ``1^T B 1 = rhoA h``, ``1^T B xi = rhoA h^2 / 2`` and
    ``xi^T B xi = rhoA h^3 / 3``, ``B = rhoA h / 3 [[1, -1], [-1, 4]]`` (positive definite).

    Parameters
    ----------
    element : {"P1", "P2"}
    h, rhoA : float
        The contact element's length and mass per length.

    Returns
    -------
    ndarray, shape (1, 1) or (2, 2)
        Over the element's nodes other than the contact node, sorted from the clamp.
    """
    if element == "P1":
        return np.array([[rhoA * h]])
    return rhoA * h / 3.0 * np.array([[1.0, -1.0], [-1.0, 4.0]])


def _redistribute(M: np.ndarray, bar: Bar, basis, e: int, contact_mass: np.ndarray) -> np.ndarray:
    """``M`` (consistent, all DOFs) with the mass of element ``e``, the contact element, redistributed.

    ``contact_mass`` is the consistent mass of element ``e`` alone (all DOFs, as ``M``); it is replaced by
    :func:`redistributed_block`, and the contact node's row and column are exactly zero.
    """
    xd = basis.doflocs[0]
    dofs = np.asarray(basis.element_dofs[:, e])
    dofs = dofs[np.argsort(xd[dofs], kind="stable")]
    rhoA = bar.rhoA[e] if np.ndim(bar.rhoA) else bar.rhoA
    M = M - contact_mass
    M[dofs[-1], :] = 0.0
    M[:, dofs[-1]] = 0.0
    M[np.ix_(dofs[:-1], dofs[:-1])] += redistributed_block(bar.element, float(np.diff(bar.nodes)[e]), float(rhoA))
    return M


@dataclass(frozen=True)
class Assembled:
    """Matrices over the free DOFs, sorted by position.

    Attributes
    ----------
    K, M : ndarray, shape (n, n)
        Stiffness and mass; the last DOF is the contact node.
    x : ndarray, shape (n,)
        Position of each free DOF.
    basis : skfem.Basis
        The scikit-fem basis (all DOFs, including the clamped one).
    free : ndarray, shape (n,)
        Basis DOF index of each sorted free DOF.
    body : ndarray, shape (n,)
        The load of a unit uniform acceleration along the bar (gravity ``g = 1``; a support's rigid motion): the
        whole mass matrix, the clamped DOF's columns included, times ones, over the free DOFs.  For a consistent
        mass it is the body force's load vector (the shape functions sum to 1); for a lumped one its row sums.
    crack : int, optional
        A cracked bar's inner face: the index of its sorted free DOF (the outer face is the next one); None:
        no crack.
    """

    K: np.ndarray
    M: np.ndarray
    x: np.ndarray
    basis: object
    free: np.ndarray
    body: np.ndarray
    crack: int | None = None

    @property
    def n(self) -> int:
        return self.x.size

    def __repr__(self) -> str:
        elem = type(getattr(self.basis, "elem", None)).__name__
        return build("Assembled", {"n": self.n, "x": rng(self.x), "K": f"{self.K.shape}",
                                   "M": f"{self.M.shape}", "basis": f"{type(self.basis).__name__} ({elem})"})

    def contact_row(self) -> np.ndarray:
        """The contact row ``r`` (FORMULATION §9): the last DOF ``e_{n-1}`` against the stop, or the crack's
        ``e_i - e_o`` (inner face ``i``, outer ``o``: ``r . x`` grows as the faces close)."""
        r = np.zeros(self.n)
        if self.crack is None:
            r[-1] = 1.0
        else:
            r[self.crack], r[self.crack + 1] = 1.0, -1.0
        return r

    def load_vector(self, s: float) -> np.ndarray:
        """Consistent load vector of a unit point force at ``s`` (shape functions)."""
        full = np.asarray(self.basis.point_source(np.array([s])), dtype=float).ravel()
        return full[self.free]


def assemble(bar: Bar) -> Assembled:
    """Assemble ``K`` and ``M`` of ``bar`` with scikit-fem (dense, free DOFs).

    Returns
    -------
    Assembled
        Sorted free-DOF matrices; for the chain they are Eqs. (23)-(24).
    """
    import skfem
    from skfem import BilinearForm, asm

    mesh = skfem.MeshLine(np.asarray(bar.nodes)) if bar.crack_at is None else split_mesh(bar.nodes, bar.crack_at)
    elem = skfem.ElementLineP1() if bar.element == "P1" else skfem.ElementLineP2()
    basis = skfem.Basis(mesh, elem)
    nq = basis.X.shape[-1]

    def per_elem(v):
        v = np.asarray(v, dtype=float)
        return np.broadcast_to(v[:, None] if v.ndim else v, (mesh.t.shape[1], nq))

    @BilinearForm
    def stiffness(u, v, w):
        return w["ea"] * u.grad[0] * v.grad[0]

    @BilinearForm
    def mass(u, v, w):
        return w["ra"] * u * v

    K = asm(stiffness, basis, ea=per_elem(bar.EA)).toarray()
    M = asm(mass, basis, ra=per_elem(bar.rhoA)).toarray()
    if bar.mass == "lumped":
        M = np.diag(M.sum(axis=1))
    elif bar.mass == "redistributed":
        e = int(np.argmax(mesh.p[0, mesh.t].max(axis=0)))          # the contact element, by position
        only = np.zeros(mesh.t.shape[1])
        only[e] = 1.0
        M = _redistribute(M, bar, basis, e, asm(mass, basis, ra=per_elem(only * bar.rhoA)).toarray())
    xd = basis.doflocs[0]
    for xp, mp in bar.point_masses:
        j = int(np.argmin(np.abs(xd - xp)))
        M[j, j] += mp
    free = np.flatnonzero(((xd > 0.0) | (bar.supports == "free-free"))
                          & ((xd < bar.length) if bar.supports == "clamped-clamped" else True))
    free = free[np.argsort(xd[free], kind="stable")]     # a crack's inner face (a lower DOF index) before its outer
    xf = xd[free]
    crack = None if bar.crack_at is None else int(np.flatnonzero(xf == bar.crack_at)[0])
    return Assembled(K[np.ix_(free, free)], M[np.ix_(free, free)], xf, basis, free, M.sum(axis=1)[free], crack)

