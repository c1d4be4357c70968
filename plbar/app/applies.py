"""Which options of a :class:`plbar.Case` apply to which model: the one rule, so that an option that would be
ignored is refused with the flag that sets it."""

from __future__ import annotations

from ..errors import InputError
from ..util.check import show

__all__ = ["FE_ONLY", "FLAGS", "STATIC_PARTS", "check_applies", "refuse_static_part", "refuse_zero"]

#: the options of an FE bar and their defaults: on a chain, any other value is refused (it would be ignored)
FE_ONLY = {"element": "P1", "mass": "lumped", "EA": 1.0, "rhoA": 1.0, "grading": 1.0, "mesh_file": None,
           "point_masses": (), "crack_at": None, "supports": "clamped-free"}
#: the command-line spelling of the Case fields named in messages
FLAGS = {"n": "-N", "element": "--element", "mass": "--mass", "grading": "--grading", "mesh_file": "--mesh-file",
         "length": "--length", "EA": "--EA", "rhoA": "--rhoA", "point_masses": "no CLI option",
         "crack_at": "--crack-at", "supports": "--supports"}


#: what gives a case's motion a static part: (field, in words, its flag); the paper's scan is written for neither
STATIC_PARTS = (("gap", "gap at the stop", "--gap D"), ("gravity", "constant load", "--gravity G"))


def refuse_zero(ld) -> None:
    """A case answers forced responses (xi_eq, the survey): a load of zero amplitude has none (a
    :class:`plbar.Load` takes it, for a free motion from a given start)."""
    if all(a == 0.0 for _, a in ld.points + ld.nodes) and not ld.base:
        raise InputError("every load amplitude is 0.0; give a non-zero amplitude (a case's answers are forced "
                         "responses)")


def refuse_static_part(case, what: str, instead: str) -> None:
    """Refuse a gap or a constant load where ``what`` (a study of the paper's scan) is written for neither:
    ``"gap = 0.5: <what>, written for no gap and no constant load; <instead> --gap D"``."""
    for name, _, flag in STATIC_PARTS:
        if getattr(case, name):
            raise InputError(f"{name} = {getattr(case, name):g}: {what}, written for no gap and no constant load; "
                             f"{instead} {flag}")


def _flag(name: str) -> str:
    return FLAGS.get(name, "no CLI option")


def check_applies(case) -> None:
    """The one rule of which options apply to which model: one that would be ignored is refused."""
    if case.model == "chain":
        fe_only = [(k, getattr(case, k)) for k, v in FE_ONLY.items() if getattr(case, k) != v]
        if case.length not in (1.0, float(case.n_eff)):
            fe_only.insert(0, ("length", case.length))
        if fe_only:
            k, v = fe_only[0]
            raise InputError(f"{k} = {show(v)} does not apply to model = 'chain' (a P1 lumped chain of N "
                             f"masses m and springs k, L = N); use model = 'fe' (--model fe) or drop {k} "
                             f"({_flag(k)})")
    elif (case.m, case.k) != (1.0, 1.0):
        k = "m" if case.m != 1.0 else "k"
        raise InputError(f"{k} = {show(getattr(case, k))} does not apply to model = 'fe'; give the section "
                         "with EA and rhoA, or use model = 'chain'")
    if case.mesh_file is not None:
        given = [(k, getattr(case, k)) for k, v in (("n", None), ("grading", 1.0), ("length", 1.0))
                 if getattr(case, k) != v]
        if given:
            k, v = given[0]
            raise InputError(f"{k} = {show(v)} conflicts with mesh_file = {case.mesh_file!r}, which fixes the "
                             f"mesh (its elements, grading and length); drop {k} ({_flag(k)}) or the mesh file")
    if case.load_scale != 1.0:
        raise InputError(f"load_scale = {show(case.load_scale)} applies to model = 'matrices' only (the factor on "
                         "its file's load); a bar's load is its forces' amplitudes (--amplitude, [[load]] amplitude)")
    if case.model == "continuum":
        _check_continuum(case)
    if case.end_mass_absolute and case.end_mass == 0:
        raise InputError("end_mass_absolute = True needs an end mass: give end_mass > 0 (--end-mass M), or drop "
                         "end_mass_absolute (--end-mass-absolute)")


def _check_continuum(case) -> None:
    """What the continuum solver takes (:mod:`plbar.continuum`): a uniform undamped bar, plastic contact, one
    point load; an option it would ignore is refused."""
    fe = [(k, getattr(case, k)) for k in ("element", "mass", "grading", "mesh_file", "point_masses", "crack_at",
                                          "supports")
          if getattr(case, k) != FE_ONLY[k]]
    if fe:
        k, v = fe[0]
        raise InputError(f"{k} = {show(v)} does not apply to model = 'continuum' (the exact uniform bar, no mesh); "
                         f"drop {k} ({_flag(k)}) or use model = 'fe'")
    if case.modes is not None and case.rayleigh is None:
        raise InputError("modes does not apply to the undamped model = 'continuum' (characteristics: it has every "
                         "mode); drop --modes. With Rayleigh damping it sets the exact modes kept per contact "
                         "state (default 1024)")
    if case.restitution:
        raise InputError(f"model = 'continuum' has a plastic contact (restitution 0), got {case.restitution:g}; "
                         "use model = 'fe' for e > 0")
    for name, words, _ in STATIC_PARTS + (("base", "base excitation", "--base A"),):
        if getattr(case, name):
            raise InputError(f"model = 'continuum' has no {words} yet, got {name} = {getattr(case, name):g}; use "
                             "model = 'fe' (or 'chain')")
    if case.load_nodes or len(case.load_points) > 1:
        raise InputError("model = 'continuum' takes one point load (--load-at S), not DOF loads (--load-node) "
                         "nor several points")
