"""Cases of a structure given by its matrices: a :class:`plbar.Structure`, or a structure file (``model =
"matrices"``, :func:`plbar.io.read_structure`).

The case's validator (:class:`plbar.app.Case`) sets the fields these functions return: the structure and the
search options checked, every option of a bar refused (the structure holds its own load; a file's damping and
restitution and gap may be replaced by the case's).
"""

from __future__ import annotations

import os
from dataclasses import fields
from pathlib import Path

from ..errors import InputError
from ..model import Structure, check_gap, check_rayleigh, check_restitution
from ..util.check import choice, integer, interval, positive, show
from ..util.check import grid as check_grid

__all__ = ["BAR_OPTIONS", "SIGNATURES", "bar_options", "structure_fields", "matrices_fields", "structure_dict",
           "search_dict", "search_fields"]

SIGNATURES = ("default", "paper", "all")    #: which periodic responses a solve finds (see Case.signatures)
#: the options of a bar (and its load, damping, restitution, gap, gravity): none applies to a structure given by its
#: matrices
BAR_OPTIONS = ("n", "element", "mass", "length", "EA", "rhoA", "m", "k", "grading", "mesh_file", "point_masses",
               "end_mass", "end_mass_absolute", "load_nodes", "load_points", "rayleigh", "restitution", "load_scale",
               "gap", "gravity", "base", "crack_at", "supports")
#: the options a structure holds itself (a case built from one carries the structure's values)
OWN = ("rayleigh", "restitution", "gap")


def bar_options(case, allowed=()) -> list:
    """The bar's options ``case`` gives a value other than their default (but those ``allowed``)."""
    defaults = {f.name: f.default for f in fields(case)}
    return [k for k in BAR_OPTIONS if k not in allowed and getattr(case, k) != defaults[k]]


def structure_fields(case) -> dict:
    """The fields of a case of a :class:`plbar.Structure` (``case.structure``)."""
    if not isinstance(case.structure, Structure):
        raise InputError(f"structure = {show(case.structure)} must be a plbar.Structure (model = 'structure' "
                         "is set by giving one)")
    if case.model not in ("chain", "structure"):
        raise InputError(f"model = {case.model!r} conflicts with a structure given by its matrices; drop model")
    own = [k for k in OWN if getattr(case, k) == getattr(case.structure, k)]   # its own values: a replace()
    bar = bar_options(case, own)
    if bar:
        raise InputError(f"{bar[0]} does not apply to a structure given by its matrices (plbar.Structure: "
                         "its load, damping, restitution and gap are its own)")
    return {"model": "structure", **search_fields(case, case.structure)}


def matrices_fields(case) -> dict:
    """The fields of a case of a structure file: the file read (the case's ``rayleigh`` and ``restitution``, where
    given, replace the file's), its digest (a digest given must match: the file has not changed)."""
    from ..io import file_digest, read_structure

    if case.model not in ("chain", "matrices"):
        raise InputError(f"model = {case.model!r} conflicts with matrices = {case.matrices!r} (a structure "
                         "file); use model = 'matrices' (--model matrices)")
    if case.matrices is None:
        raise InputError("model = 'matrices' needs a structure file: matrices = FILE.npz (--matrices FILE.npz)")
    if not isinstance(case.matrices, (str, os.PathLike)):
        raise InputError(f"matrices = {show(case.matrices)} must be a path (a string)")
    bar = bar_options(case, ("rayleigh", "restitution", "load_scale", "gap"))
    if bar:
        raise InputError(f"{bar[0]} does not apply to model = 'matrices' (the structure file holds the "
                         "structure and its load)")
    path = str(Path(os.fspath(case.matrices)).expanduser().resolve())
    own = read_structure(path)
    ab, e = check_rayleigh(case.rayleigh), check_restitution(case.restitution)
    scale = positive("load_scale", case.load_scale)
    d = check_gap(case.gap)
    st = read_structure(path, ab if case.rayleigh is not None and ab != own.rayleigh else None,
                        e if case.restitution != 0.0 and e != own.restitution else None, scale,
                        d if d != 0.0 and d != own.gap else None)
    digest = file_digest(path)
    if case.matrices_digest is not None and case.matrices_digest != digest:
        raise InputError(f"structure file {path!r} changed (digest {digest}, expected {case.matrices_digest}): "
                         "a study begun on the old content cannot go on; rerun it with --overwrite")
    return {"model": "matrices", "matrices": path, "matrices_digest": digest, "structure": st, "load_scale": scale,
            **search_fields(case, st)}


def search_fields(case, st: Structure) -> dict:
    """The search options checked, the structure's damping and restitution."""
    choice("method", case.method, ("continuation", "grid"))
    choice("signatures", case.signatures, SIGNATURES)
    out = {"rayleigh": st.rayleigh, "restitution": st.restitution, "gap": st.gap,
           "grid": check_grid(case.grid, warn=False)}
    if case.modes is not None:
        out["modes"] = integer("modes", case.modes, 1, st.n)
    for nm in ("T1", "T2"):
        if getattr(case, nm) is not None:
            out[nm] = interval(f"search domain {nm}", getattr(case, nm))
    return out


def search_dict(case) -> dict:
    """The search options of a case as plain data (in a structure's, a file's or a beam's ``to_dict``)."""
    return {"grid": list(case.grid), "T1": case.T1, "T2": case.T2, "method": case.method,
            "signatures": case.signatures, "modes": case.modes}


def structure_dict(case) -> dict:
    """:meth:`plbar.app.Case.to_dict` of a structure: a file's case rebuilds from it (path and digest); a given
    structure is named by its fingerprint."""
    search = search_dict(case)
    if case.model == "matrices":
        d = {"model": "matrices", "matrices": case.matrices, "matrices_digest": case.matrices_digest, **search}
        if case.rayleigh is not None:
            d["rayleigh"] = list(case.rayleigh)
        if case.restitution:
            d["restitution"] = case.restitution
        if case.load_scale != 1.0:
            d["load_scale"] = case.load_scale
        if case.gap:
            d["gap"] = case.gap
        return d
    st = case.structure
    return {"model": "structure", "dofs": st.n, "structure": st.fingerprint, **search,
            "restitution": st.restitution, "rayleigh": st.rayleigh, **({"gap": st.gap} if st.gap else {})}
