"""A case: which bar, which load, where to search.  What ``plbar run`` solves.

The default :class:`Case` is the paper's Sec. 4.1 example: the chain with
``N = 5``, ``m = k = 1`` and a unit force on DOF 1.
"""

from __future__ import annotations

import math
import os
from dataclasses import asdict, dataclass, field, fields, replace
from functools import lru_cache

import numpy as np

from ..errors import InputError
from ..model import (ELEMENTS, MASSES, Bar, Load, Problem, Structure, chain, check_gap, check_rayleigh,
                     check_restitution, graded_nodes, problem)
from ..paths import Domain, default_domain
from ..util.check import choice, finite, integer, interval, number, pairs, positive, show
from ..util.check import grid as check_grid
from .applies import FE_ONLY, check_applies, refuse_zero
from .beamcase import beam_dict, beam_fields
from .given import SIGNATURES, matrices_fields, structure_dict, structure_fields
from .start import start_dict, start_fields

__all__ = ["Case", "MODELS", "SIGNATURES"]

MODELS = ("chain", "fe", "continuum", "beam", "matrices", "structure")
#: grid steps per travel time L / c of the continuum's characteristics (its ``n``) when not given
CONTINUUM_STEPS = 32


@dataclass(frozen=True)
class Case:
    """Everything that defines a run.

    Parameters
    ----------
    model : {"chain", "fe", "continuum", "matrices", "structure"}
        The paper's mass-spring chain, a finite-element bar, or the uniform continuum bar solved exactly by
        characteristics (:mod:`plbar.continuum`: the N = infinity limit of the FE bar; a survey and its motions
        only, plastic, one point load, no FE options); with Rayleigh damping (a Kelvin-Voigt bar) by the exact
        modes of each contact state, ``modes`` of them (default 1024; a survey only).  ``"matrices"``: another FE
        program's structure, read from the file ``matrices``; ``"structure"``: the matrices of ``structure`` (set
        by giving it).
    n : int, optional
        Masses of the chain / elements of the FE bar / grid steps per travel time ``L / c`` of the continuum (its
        fields are sampled on ``n + 1`` points) (default 5 / 8 / 32).
    element, mass : str
        FE element (``P1``/``P2``) and mass (``lumped``/``consistent``/``redistributed``, the last with
        ``end_mass > 0``, see :class:`plbar.Bar`); the chain is P1 lumped.
    length, EA, rhoA : float
        FE bar length and section properties (the chain has ``L = N``).
    m, k : float
        Chain mass and spring stiffness.
    grading : float
        Ratio of last to first element length of the FE mesh (1 = uniform).
    mesh_file : str, optional
        A meshio-readable 1D line mesh for the FE bar (overrides ``n``, ``length``, ``grading``).
    point_masses : tuple of (x, m)
        Extra concentrated masses on FE vertices.
    end_mass : float
        A rigid point mass on the contact node ``x = L``, as a fraction of the
        bar's own mass (``sum_e rhoA_e h_e``; ``N m`` for the chain), added to
        the point masses already there (the chain keeps its ``m / 2``).  0: none.
    end_mass_absolute : bool
        Take ``end_mass`` as the mass itself, not a fraction (see :attr:`end_mass_value`).
    load_nodes : tuple of (k, amplitude)
        Forces on free DOFs (1-based from the clamp).
    load_points : tuple of (s, amplitude)
        Point forces at positions ``s`` in ``(0, L]``.  Without any load: a unit
        force on DOF 1 for the chain (the paper's case), a unit point force at
        ``s = L / 2`` for an FE bar (a fixed physical position, whatever the mesh; :meth:`plbar.Bar.default_load`).
    grid : (int, int)
        Scan grid over ``(T^I, T^II)``.
    T1, T2 : (float, float), optional
        Search domain; default ``(0, T0^alpha / 2]``.
    method : {"continuation", "grid"}
        How branches are built from the scan (:func:`plbar.find_paths`).
    signatures : {"default", "paper", "all"}
        Which periodic responses to find.  ``"default"``: the paper's class and every signature found
        without the user (the zero-dwell class, period doublings up to ``m = 4``, the neighbouring
        signatures where a branch stops being admissible, and the periodic motions of a simulation from
        rest at 81 forcing periods, 600 periods each: :func:`plbar.periodic.find_branches`); ``"paper"``:
        the paper's class only (one stuck phase, one impact per period: the fastest, no compiled
        simulator); ``"all"``: the default with the survey's simulation (161 periods, 1,000 each) and
        orbits up to ``m = 8``.
    modes : int, optional
        Keep only the lowest ``modes`` modes of each state (modal truncation,
        for fine meshes; check it with :func:`plbar.system.truncation_check`).
        Default: all.
    rayleigh : (float, float), optional
        Inherent Rayleigh damping ``(alpha, beta)`` of the whole bar, ``C = alpha M
        + beta K`` (FORMULATION §8; :func:`plbar.rayleigh_from_ratio` gives it from
        one ratio at two periods).  Default None: undamped, the paper;
        ``(0, 0)`` is taken as None.
    restitution : float
        Coefficient of restitution ``e`` of the contact, in ``[0, 1]`` (Newton's impact law: the contact
        leaves the wall at ``e`` times the speed it hit it with, losing ``1 - e^2`` of the plastic impact's
        loss).  Default 0: the paper's perfectly plastic impact.  Every command takes any ``e``: the
        periodic responses (``run``) then have rebounds (``R`` in their signatures) and chattering sequences
        (``R...RP``); the studies of the paper's class (``sweep-loads``, ``refine``) need ``e = 0``.
    structure : plbar.Structure, optional
        Any two-state structure by its matrices (:class:`plbar.Structure`: another FE code's, a beam, two bodies
        and a joint): ``run`` solves it as it solves a bar.  It carries its own load, damping and restitution
        (the case's ``rayleigh`` and ``restitution`` are taken from it); the bar's options do not apply.
    matrices : str, optional
        ``model = "matrices"``: a structure file (``.npz`` of ``M``, ``K``, the contact ``r`` or ``contact``, the
        load ``q``, optional ``C`` of Rayleigh form or ``rayleigh``, ``restitution``, ``x``:
        :func:`plbar.io.read_structure`); the case's ``rayleigh`` and ``restitution``, where given, replace the
        file's (a restitution of 0, the default, keeps the file's).  Every command that needs no bar geometry
        takes it (``run``, ``survey``).
    load_scale : float
        ``model = "matrices"``: a factor on the file's load ``q`` (``--amplitude``) [1].
    matrices_digest : str, optional
        The file's content digest (:func:`plbar.io.file_digest`): filled in when the case is made; given (a
        study's task), the file must still hold that content.
    gap : float
        The stop's distance from the contact at rest, ``d`` (the contact coordinate stays ``<= d``; FORMULATION
        §9): ``> 0`` a clearance (the structure starts free), ``< 0`` an interference (it starts held, in its
        static equilibrium against the stop).  Default 0: the paper.  With a gap the response is no longer
        proportional to the load: what matters is the amplitude over the gap (``--amplitude``).  The simulator
        and its studies (``survey``) and the periodic responses of the signature search (``run``) take it; the
        paper's scan of ``(T1, T2)`` does not (``run`` finds the paper's class by the search then).
    gravity : float
        A uniform acceleration along the bar, towards the stop (``> 0``) or away from it: the constant load
        ``q_s``, the weight of its masses under ``g``, beside the harmonic one (:func:`plbar.model.bar_structure`);
        the structure starts in its static equilibrium (free, or held against the stop).  Default 0.  Like a gap,
        it makes the response depend on the amplitude, and the same commands take it.  A structure file gives its
        own constant load (``q_s``).
    EI, supports, contact_at
        ``model = "beam"`` (:mod:`plbar.app.beamcase`): the beam's bending stiffness [1], its supports
        (``clamped-free``, ``pinned-pinned``, ``clamped-clamped``) and the stop's position on it (default the tip
        of a cantilever, mid-span otherwise).
    base : float
        A base excitation: the support's acceleration amplitude ``a_g`` along the bar (towards the stop > 0), the
        effective load ``-M t a_g cos(W t - phi)`` in coordinates relative to the support
        (:func:`plbar.base_excitation`), beside any forces; the stop moves with the support and every response is
        relative to it.  Default 0: none (with no force either, the default load acts).
    crack_at : float, optional
        ``model = "fe"``: a breathing crack at this interior vertex (:mod:`plbar.model.crack`): the contact is the
        crack's faces (open in tension, the outer part floating), the end ``x = L`` is free.  Default None: no crack,
        the stop at ``x = L``.  With ``supports = "clamped-clamped"`` the end ``x = L`` is clamped too.
    start_x, start_v : float or sequence of float, optional
        The motion's start (:mod:`plbar.app.start`): a number (every DOF) or one per DOF.  Default None: at rest.
    """

    model: str = "chain"
    n: int | None = None
    element: str = "P1"
    mass: str = "lumped"
    length: float = 1.0
    EA: float = 1.0
    rhoA: float = 1.0
    m: float = 1.0
    k: float = 1.0
    grading: float = 1.0
    mesh_file: str | None = None
    point_masses: tuple = ()
    end_mass: float = 0.0
    end_mass_absolute: bool = False
    load_nodes: tuple = ()
    load_points: tuple = ()
    grid: tuple[int, int] = (200, 200)
    T1: tuple[float, float] | None = None
    T2: tuple[float, float] | None = None
    method: str = "continuation"
    signatures: str = "default"
    modes: int | None = None
    label: str = field(default="", compare=False)
    rayleigh: tuple[float, float] | None = None
    restitution: float = 0.0
    structure: Structure | None = None
    matrices: str | None = None
    load_scale: float = 1.0
    matrices_digest: str | None = None
    gap: float = 0.0
    gravity: float = 0.0
    base: float = 0.0
    EI: float = 1.0
    supports: str = "clamped-free"
    contact_at: float | None = None
    crack_at: float | None = None
    start_x: float | tuple | None = None
    start_v: float | tuple | None = None

    def __post_init__(self):
        self._validate()
        self._set(start_fields(self))

    def _validate(self):
        if self.model == "beam":
            return self._set(beam_fields(self))
        if self.model == "matrices" or self.matrices is not None:
            return self._set(matrices_fields(self))
        if self.structure is not None or self.model == "structure":
            return self._set(structure_fields(self))
        choice("model", self.model, MODELS[:-1])
        choice("element", self.element, ELEMENTS)
        choice("mass", self.mass, MASSES)
        choice("method", self.method, ("continuation", "grid"))
        choice("signatures", self.signatures, SIGNATURES)
        if self.modes is not None:
            object.__setattr__(self, "modes", integer("modes", self.modes, 1))
        object.__setattr__(self, "rayleigh", check_rayleigh(self.rayleigh))
        object.__setattr__(self, "restitution", check_restitution(self.restitution))
        object.__setattr__(self, "gap", check_gap(self.gap))
        object.__setattr__(self, "base", finite("base", self.base, "a finite number (the support's acceleration "
                                                "amplitude along the bar)"))
        object.__setattr__(self, "gravity", finite("gravity", self.gravity,
                                                   "a finite number (an acceleration along the bar, > 0 towards "
                                                   "the stop)"))
        if self.n is not None:
            what = {"fe": "n", "chain": "chain size N", "continuum": "continuum steps per L/c n"}[self.model]
            object.__setattr__(self, "n", integer(what, self.n, 2))
        for nm in ("length", "EA", "rhoA", "m", "k", "grading"):
            object.__setattr__(self, nm, positive(nm, getattr(self, nm)))
        if self.mesh_file is not None and not isinstance(self.mesh_file, (str, os.PathLike)):
            raise InputError(f"mesh_file = {show(self.mesh_file)} must be a path (a string)")
        if self.mesh_file is not None:
            object.__setattr__(self, "mesh_file", os.fspath(self.mesh_file))
        if not isinstance(self.label, str):
            raise InputError(f"label = {show(self.label)} must be a string")
        for nm, what in (("load_nodes", "(k, amplitude)"), ("load_points", "(s, amplitude)"),
                         ("point_masses", "(x, m)")):
            v = getattr(self, nm)
            object.__setattr__(self, nm, () if v is None else pairs(nm, v, what))
        self._check_end_mass()
        check_applies(self)
        object.__setattr__(self, "grid", check_grid(self.grid, warn=False))
        for nm in ("T1", "T2"):
            if getattr(self, nm) is not None:
                object.__setattr__(self, nm, interval(f"search domain {nm}", getattr(self, nm)))
        bar = self._make_bar()                 # fail now on the mesh (file), point masses, section and load
        if self.modes is not None and self.modes > bar.n_dofs and self.model != "continuum":
            raise InputError(f"modes = {self.modes} is more than the {bar.n_dofs} degrees of freedom of this bar; "
                             f"give at most {bar.n_dofs} (--modes M), or none for the full model")
        if not self.load_nodes and not self.load_points and not self.base:   # the default load: a fixed position
            if self.model == "chain":
                object.__setattr__(self, "load_nodes", ((1, 1.0),))
            else:
                object.__setattr__(self, "load_points", ((bar.default_load(), 1.0),))
        ld = Load(points=self.load_points, nodes=self.load_nodes, base=self.base)   # validates types and signs
        refuse_zero(ld)
        ld.check(bar)
        object.__setattr__(self, "load_nodes", ld.nodes)
        object.__setattr__(self, "load_points", ld.points)

    def __repr__(self) -> str:
        """The model and the fields that differ from their defaults (what makes this case this case)."""
        items = [f"{f.name}={getattr(self, f.name)!r}" for f in fields(self)
                 if f.name == "model" or (f.repr and f.compare and getattr(self, f.name) != f.default)]
        return f"Case({', '.join(items)})"

    def _set(self, values: dict) -> None:
        for name, v in values.items():
            object.__setattr__(self, name, v)      # the validated, converted inputs

    dofs = property(lambda self: self.structure.n if self.structure is not None else self.bar().n_dofs,
                    doc="Free DOFs of the structure.")

    @property
    def n_eff(self) -> int:
        """Masses of the chain / elements of the FE bar (a mesh file's own count; default 5 / 8)."""
        if self.structure is not None:
            return self.n if self.model == "beam" else self.structure.n
        if self.mesh_file is not None and self.model != "chain":
            return self.bar().n_elements
        return self.n if self.n is not None else {"chain": 5, "fe": 8, "continuum": CONTINUUM_STEPS}[self.model]

    def bar(self) -> Bar:
        """The bar of this case (built once per process for equal cases)."""
        if self.structure is not None:
            raise InputError("this case is a plbar.Structure given by its matrices: it has no bar (the bar's "
                             "studies and exports need model = 'chain' or 'fe')")
        try:
            return _bar(self)
        except TypeError:                      # a field that cannot be hashed: built afresh
            return self._make_bar()

    def _check_end_mass(self) -> None:
        must = ">= 0 (a fraction of the bar's mass, or an absolute mass with end_mass_absolute)"
        v = number("end_mass", self.end_mass, f"a finite number {must}")
        if not (math.isfinite(v) and v >= 0):
            raise InputError(f"end_mass = {show(v)} is not allowed; it must be finite and {must}")
        object.__setattr__(self, "end_mass", v)
        if not isinstance(self.end_mass_absolute, (bool, np.bool_)):
            raise InputError(f"end_mass_absolute = {show(self.end_mass_absolute)} must be True or False "
                             "(end_mass is an absolute mass, or a fraction of the bar's mass)")
        object.__setattr__(self, "end_mass_absolute", bool(self.end_mass_absolute))

    @property
    def end_mass_value(self) -> float:
        """The end mass itself: ``end_mass`` times the bar's mass, or ``end_mass`` if absolute."""
        return self.end_mass if self.end_mass_absolute else self.end_mass * self.bar().bar_mass

    def _make_bar(self) -> Bar:
        """The bar of the case with its end mass (a point mass on the contact node, added to any there).

        A redistributed mass needs the end mass on the bar (:class:`plbar.Bar`), so the bar is first built
        with a consistent mass and the end mass is added with the case's mass.
        """
        bar = self._base_bar()
        me = self.end_mass if self.end_mass_absolute else self.end_mass * bar.bar_mass
        if me == 0 and bar.mass == self.mass:
            return bar
        return replace(bar, mass=self.mass, point_masses=bar.point_masses + (((bar.length, me),) if me else ()))

    def _base_bar(self) -> Bar:
        mass = "consistent" if self.mass == "redistributed" else self.mass
        if self.model == "chain":
            return chain(self.n_eff, self.m, self.k)
        kw = dict(crack_at=self.crack_at, supports=self.supports)
        if self.mesh_file:
            from ..io.meshfile import read_nodes

            nodes = read_nodes(self.mesh_file)
            try:
                return Bar(nodes, self.element, mass, self.EA, self.rhoA, self.point_masses,
                           f"fe-{self.element}-{self.mass}-{len(nodes) - 1}", **kw)
            except InputError as exc:
                raise InputError(f"mesh file {self.mesh_file!r}: {exc}") from None
        nodes = graded_nodes(self.n_eff, self.length, self.grading)
        return Bar(nodes, self.element, mass, self.EA, self.rhoA, self.point_masses,
                   f"fe-{self.element}-{self.mass}-{len(nodes) - 1}", **kw)

    def load(self) -> Load:
        """The load of this case (validated when the case was made)."""
        self.bar()
        return Load(points=self.load_points, nodes=self.load_nodes, base=self.base)

    def problem(self) -> Problem:
        """Assemble the bar, solve both eigenproblems and attach the load (the expensive step: call once)."""
        if self.model == "continuum":
            raise InputError("model = 'continuum' has no matrices: it is simulated by characteristics, in a survey "
                             "(plbar survey --model continuum, and export/render of its motions); periodic "
                             "responses (run, refine, sweep-loads) need model = 'chain' or 'fe'")
        try:
            return _problem(self)
        except TypeError:                      # a field that cannot be hashed: built afresh
            return _problem.__wrapped__(self)

    def continuum(self):
        """The :class:`plbar.continuum.ContinuumBar` of a uniform FE or continuum case (one point load, end mass)."""
        from ..continuum import from_case

        return from_case(replace(self, model="fe", modes=None) if self.model == "continuum" else self)

    def domain(self, prob: Problem) -> Domain:
        """The search domain: ``T1``, ``T2`` if given, else the paper's ``(0, T0^alpha / 2]``."""
        d = default_domain(prob)
        return Domain(self.T1 or d.T1, self.T2 or d.T2)

    def to_dict(self) -> dict:
        """The fields that apply to the model, as plain data (what ``summary.json`` records; ``Case(**d)`` rebuilds it).

        ``n`` is filled in and ``length`` is the bar's (``N`` for the chain); a chain has no FE fields, an FE bar
        no ``m, k``, and a mesh file stands for ``n``, ``grading`` and ``length``; ``rayleigh`` appears only for a
        damped case, ``restitution`` only where it is not 0.
        """
        if self.model == "beam" or self.structure is not None:
            return (beam_dict(self) if self.model == "beam" else structure_dict(self)) | start_dict(self)
        d = asdict(self)
        d.pop("structure")
        d["n"] = self.n_eff
        d["length"] = self.bar().length
        d.pop("label")
        drop = tuple(k for k in FE_ONLY if k != "supports") if self.model == "chain" else ("m", "k")
        if self.model == "continuum":
            drop += ("element", "mass", "grading", "mesh_file", "point_masses")
        if self.mesh_file is not None:
            drop += ("n", "grading", "length")
        drop += tuple(k for k in ("restitution", "gap", "gravity", "base") if not d[k])
        drop += ("crack_at",) if d["crack_at"] is None else ()
        drop += ("start_x", "start_v")
        if d["rayleigh"] is None:
            drop += ("rayleigh",)
        else:
            d["rayleigh"] = list(d["rayleigh"])
        return {k: v for k, v in d.items() if k not in drop} | start_dict(self)


@lru_cache(maxsize=8)
def _bar(case: Case) -> Bar:
    """:meth:`Case.bar`: the mesh (file) read and the end mass placed once per equal case."""
    return case._make_bar()


@lru_cache(maxsize=2)
def _problem(case: Case) -> Problem:
    """:meth:`Case.problem`, built once per process for equal cases (the two eigenproblems of an FE bar take seconds
    to minutes at N = 512: a survey's tasks, its compile check and its preparation each asked for it; forked
    workers inherit it from the parent)."""
    if case.structure is not None:
        return problem(case.structure, modes=case.modes)
    return problem(case.bar(), case.load(), modes=case.modes, rayleigh=case.rayleigh, restitution=case.restitution,
                   gap=case.gap, gravity=case.gravity)
