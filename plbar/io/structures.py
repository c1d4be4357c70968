"""A two-state structure from another FE program: its matrices in a ``.npz`` file, read and written.

The file holds numpy arrays by name (``numpy.savez``):

* ``M``, ``K`` (required): mass and stiffness over the free DOFs, dense ``(n, n)``;
* the contact: ``r``, the contact row (``u = r . x <= 0``, FORMULATION §9), or ``contact``, one integer DOF
  (0-based; ``r = e_contact``); one of the two;
* ``q`` (required): the harmonic load's amplitude vector (the force ``q cos(W t - phi)``);
* optional: ``C`` (inherent damping; it must be of Rayleigh form, ``C = alpha M + beta K``, the form plbar's
  modal solvers take), or ``rayleigh = [alpha, beta]``; ``restitution`` (Newton's ``e``); ``gap`` (the stop at
  ``u = gap``: ``> 0`` a clearance, ``< 0`` an interference; FORMULATION §9); ``q_s``, a constant load beside the
  harmonic one (gravity, a prestress; not scaled by ``--amplitude``); ``x``, a position per DOF (for tables and
  plots).

What plbar does not model yet is refused by name rather than ignored: a support's influence vector ``t``, a start
``x0``, ``v0``.
"""

from __future__ import annotations

import hashlib
import os
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..model import Structure
from ..util.files import atomic_path

__all__ = ["read_structure", "write_structure", "file_digest", "KEYS", "NOT_YET"]

#: the arrays a structure file may hold
KEYS = ("M", "K", "r", "contact", "q", "C", "rayleigh", "restitution", "gap", "q_s", "x")
#: arrays of structures plbar does not solve yet (a constant load, base excitation, a given start)
NOT_YET = {"t": "base excitation (a support's influence vector)", "x0": "a given start",
           "v0": "a given start"}
#: the largest relative misfit of C by alpha M + beta K taken as Rayleigh damping
RAYLEIGH_FIT = 1e-10


def file_digest(path) -> str:
    """The sha256 of a file's bytes (hex, 16 digits): what identifies a structure file's content (read once per
    process while the file's time and size stay: every case of the file asks for it, each study task too)."""
    p = Path(os.fspath(path)).expanduser().resolve()
    st = p.stat()
    return _digest(str(p), st.st_mtime_ns, st.st_size)


@lru_cache(maxsize=8)
def _digest(path: str, _mtime: int, _size: int) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:16]


def read_structure(path, rayleigh=None, restitution: float | None = None, scale: float = 1.0,
                   gap: float | None = None) -> Structure:
    """The :class:`plbar.Structure` of a ``.npz`` file (see the module docstring), read once per process for the
    same file, content and overrides.

    Parameters
    ----------
    path : str or Path
    rayleigh : (float, float), optional
        Rayleigh damping that replaces the file's (``C`` or ``rayleigh``).
    restitution : float, optional
        A coefficient of restitution that replaces the file's.
    scale : float
        A factor on the file's load ``q`` (the response is linear in it at zero gap; with a gap it is not).
    gap : float, optional
        A gap that replaces the file's.

    Raises
    ------
    InputError
        If the file is missing or unreadable, lacks a required array, holds an unknown one or one plbar does not
        solve yet, or the matrices are not a two-state structure (:class:`plbar.Structure`'s checks).
    """
    p = Path(os.fspath(path)).expanduser().resolve()
    if not p.is_file():
        raise InputError(f"structure file {str(path)!r} does not exist (a .npz of M, K, r or contact, q)")
    st = p.stat()
    return _read(str(p), st.st_mtime_ns, st.st_size, None if rayleigh is None else tuple(map(float, rayleigh)),
                 None if restitution is None else float(restitution), float(scale), None if gap is None else float(gap))


@lru_cache(maxsize=8)
def _read(path: str, _mtime: int, _size: int, rayleigh, restitution, scale: float, gap) -> Structure:
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: np.asarray(z[k]) for k in z.files}
    except (OSError, ValueError) as exc:
        raise InputError(f"structure file {path!r} is not a readable .npz of arrays ({exc})") from None
    where = f"structure file {path!r}"
    for k, what in NOT_YET.items():
        if k in arrays:
            raise InputError(f"{where} holds {k!r} ({what}): plbar does not solve that yet; drop it")
    unknown = sorted(set(arrays) - set(KEYS))
    if unknown:
        raise InputError(f"{where} holds {unknown[0]!r}, not an array plbar reads (it takes {', '.join(KEYS)})")
    for k in ("M", "K", "q"):
        if k not in arrays:
            raise InputError(f"{where} has no {k!r} (it needs M, K, q and the contact: r or contact)")
    r = _contact(where, arrays)
    q = np.asarray(arrays["q"], float)
    if q.size and not np.any(q):     # a file is a case's structure, whose answers are forced responses
        raise InputError(f"{where}: q = 0: the load amplitude vector must not be zero (a case's answers are "
                         "forced responses)")
    damping = _damping(where, arrays) if rayleigh is None else rayleigh
    e = float(arrays["restitution"]) if restitution is None and "restitution" in arrays else (restitution or 0.0)
    d = float(arrays["gap"]) if gap is None and "gap" in arrays else (gap or 0.0)
    try:
        return Structure(arrays["M"], arrays["K"], r, scale * np.asarray(arrays["q"], float), damping, e,
                         arrays.get("x"), gap=d, q_s=arrays.get("q_s"))
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None


def _contact(where: str, arrays: dict) -> np.ndarray:
    """The contact row: ``r``, or ``e_contact`` of an integer ``contact`` (one of the two)."""
    if ("r" in arrays) == ("contact" in arrays):
        raise InputError(f"{where} must hold the contact as one of r (the contact row) or contact (a DOF)")
    if "r" in arrays:
        return arrays["r"]
    c = arrays["contact"]
    n = np.shape(arrays["M"])[0] if np.ndim(arrays["M"]) == 2 else 0
    if c.shape != () or not np.issubdtype(c.dtype, np.integer) or not 0 <= int(c) < n:
        raise InputError(f"{where}: contact = {c!r} must be one integer DOF in [0, {n - 1}] (0-based)")
    r = np.zeros(n)
    r[int(c)] = 1.0
    return r


def _damping(where: str, arrays: dict):
    """``(alpha, beta)`` of ``rayleigh`` or of a Rayleigh-form ``C`` (least squares; misfit <= RAYLEIGH_FIT)."""
    if "C" in arrays and "rayleigh" in arrays:
        raise InputError(f"{where} holds both C and rayleigh; keep one")
    if "rayleigh" in arrays:
        return tuple(float(v) for v in np.ravel(arrays["rayleigh"]))
    if "C" not in arrays:
        return None
    M, K, C = (np.asarray(arrays[k], float) for k in ("M", "K", "C"))
    if not (M.shape == K.shape == C.shape and M.ndim == 2):
        raise InputError(f"{where}: C must have the shape of M and K")
    A = np.stack([M.ravel(), K.ravel()], axis=1)
    ab, *_ = np.linalg.lstsq(A, C.ravel(), rcond=None)
    misfit = np.linalg.norm(A @ ab - C.ravel()) / max(np.linalg.norm(C), 1e-300)
    if misfit > RAYLEIGH_FIT:
        raise InputError(f"{where}: C is not of Rayleigh form alpha M + beta K (relative misfit {misfit:.1e}); "
                         "plbar's modal solvers take Rayleigh damping: give rayleigh = [alpha, beta]")
    return (float(ab[0]), float(ab[1])) if np.any(ab) else None


def write_structure(path, structure: Structure) -> Path:
    """Write ``structure`` as a structure file (``M, K, r, q, x``; ``rayleigh``, ``restitution``, ``gap``, ``q_s``
    where set),
    atomically: what :func:`read_structure` reads back exactly."""
    arrays = {"M": structure.M, "K": structure.K, "r": structure.contact, "q": structure.q, "x": structure.x}
    if structure.rayleigh is not None:
        arrays["rayleigh"] = np.array(structure.rayleigh, float)
    if structure.restitution:
        arrays["restitution"] = np.array(structure.restitution)
    if structure.gap:
        arrays["gap"] = np.array(structure.gap)
    if structure.q_s is not None:
        arrays["q_s"] = structure.q_s
    p = Path(path)
    with atomic_path(p) as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)
    return p
