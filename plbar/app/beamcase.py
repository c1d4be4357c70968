"""A beam case: the :class:`plbar.Case` of ``model = "beam"`` (issue 41 item 2, the front door).

An Euler-Bernoulli beam against a stop (:mod:`plbar.model.beam`) from the case's fields: ``n`` elements
(default 8), ``length``, ``EI``, ``rhoA``, ``supports``, the stop at ``contact_at`` (default the tip of a
cantilever, mid-span otherwise), point forces ``load_points`` (default a unit force at mid-span of a cantilever, at
a quarter span otherwise), an ``end_mass`` at ``x = L`` (a fraction of the beam's mass ``rhoA L``, or absolute), and
the contact's and loads' options of every model (``gap``, ``gravity``, ``base``, ``rayleigh``, ``restitution``).
The case holds the beam's :class:`plbar.Structure` (built once per process for equal fields, so equal cases are
equal) and every solver takes it as a structure; its dict names the beam's fields, so a survey's tasks rebuild it.
"""

from __future__ import annotations

from dataclasses import fields
from functools import lru_cache

from ..errors import InputError
from ..model import SUPPORTS, beam_structure, uniform_beam
from ..util.check import choice, integer, pairs, positive
from .given import search_dict, search_fields

__all__ = ["beam_fields", "beam_dict", "NOT_FOR_A_BEAM"]

#: the bar's options that mean nothing for a beam (refused where given)
NOT_FOR_A_BEAM = ("element", "mass", "EA", "m", "k", "grading", "mesh_file", "point_masses", "load_nodes",
                  "load_scale", "matrices", "crack_at")
#: elements of a beam when not given
BEAM_ELEMENTS = 8


@lru_cache(maxsize=16)
def _structure(n, length, EI, rhoA, supports, end_mass, points, contact_at, rayleigh, restitution, gap, gravity,
               base):
    beam = uniform_beam(n, length, EI, rhoA, supports, ((length, end_mass),) if end_mass else ())
    return beam_structure(beam, points, contact_at, rayleigh, restitution, gap, gravity, base)


def beam_fields(case) -> dict:
    """The fields of a beam case (module docstring), its structure built; refuses the bar's own options."""
    defaults = {f.name: f.default for f in fields(case)}
    given = [k for k in NOT_FOR_A_BEAM if getattr(case, k) != defaults[k]]
    if given:
        raise InputError(f"{given[0]} does not apply to model = 'beam' (an Euler-Bernoulli beam: n, length, EI, "
                         "rhoA, supports, contact_at, load_points (--load-at S), end_mass)")
    n = integer("n (beam elements)", BEAM_ELEMENTS if case.n is None else case.n, 1)
    length, EI, rhoA = positive("length", case.length), positive("EI", case.EI), positive("rhoA", case.rhoA)
    supports = choice("supports", case.supports, SUPPORTS)
    me = case.end_mass if case.end_mass_absolute else case.end_mass * rhoA * length
    default = () if case.base else (((0.5 if supports == "clamped-free" else 0.25) * length, 1.0),)
    pts = tuple(pairs("load_points", case.load_points, "(s, amplitude)")) or default
    s = (length if supports == "clamped-free" else 0.5 * length) if case.contact_at is None else case.contact_at
    st = _structure(n, length, EI, rhoA, supports, float(me), tuple((float(x), float(a)) for x, a in pts),
                    float(s), case.rayleigh, case.restitution, case.gap, case.gravity, case.base)
    return {"model": "beam", "n": n, "structure": st, "load_points": pts, "contact_at": float(s),
            **search_fields(case, st)}


def beam_dict(case) -> dict:
    """:meth:`plbar.app.Case.to_dict` of a beam case: its fields (``Case(**d)`` rebuilds it)."""
    d = {"model": "beam", "n": case.n, "length": case.length, "EI": case.EI, "rhoA": case.rhoA,
         "supports": case.supports, "contact_at": case.contact_at,
         "load_points": [list(p) for p in case.load_points], **search_dict(case)}
    for k in ("end_mass", "gap", "gravity", "base", "restitution"):
        if getattr(case, k):
            d[k] = getattr(case, k)
    if case.end_mass and case.end_mass_absolute:
        d["end_mass_absolute"] = True
    if case.rayleigh is not None:
        d["rayleigh"] = list(case.rayleigh)
    return d
