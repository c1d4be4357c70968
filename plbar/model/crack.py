"""A breathing crack in a finite-element bar: the split node (issue 41 item 3).

The crack at the interior vertex ``s`` is two coincident nodes, its faces: the inner one ends the elements on
``[0, s]``, the outer one starts those on ``[s, L]``, so no element couples them (the mesh is split there, by
:func:`split_mesh`; the stiffness and the mass are then assembled by scikit-fem as for any bar).  The contact is
the faces' relative displacement ``u_i - u_o``, which grows as the crack closes (FORMULATION §9's ``r = e_i - e_o``,
:meth:`plbar.model.Assembled.contact_row`), held at ``<= d``: ``d = 0`` a closed crack at rest, ``d > 0`` an open
one, ``d < 0`` one squeezed shut.  Held, the faces move together and the bar is whole (clamped-free); open, the outer
part floats: a rigid-body mode of the free state (:func:`plbar.model.modes.state_modes`, ``rigid=True``).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..util.check import finite, show

__all__ = ["crack_position", "split_mesh", "supported_crack"]


def supported_crack(x: np.ndarray, s, mass: str, point_masses, supports: str) -> float | None:
    """A bar's crack (None: none) checked with its supports (:data:`plbar.model.bar.BAR_SUPPORTS`): a crack needs
    the clamp at ``x = 0`` (with none both parts would float), and a bar clamped at both ends needs a crack (it has
    no stop otherwise)."""
    if s is not None:
        if supports == "free-free":
            raise InputError("a crack in a bar with no support: both parts would float; clamp it at x = 0 "
                             "(supports = 'clamped-free' or 'clamped-clamped')")
        return crack_position(x, s, mass, point_masses, supports)
    if supports == "clamped-clamped":
        raise InputError(f"supports = {supports!r}: a bar clamped at both ends has no stop; its contact "
                         "can only be a crack (crack_at = S, --crack-at S)")
    return None


def crack_position(x: np.ndarray, s, mass: str, point_masses, supports: str = "clamped-free") -> float:
    """The crack's position ``s`` on the vertices ``x``, validated: an interior vertex (to ``1e-12 L``, snapped to
    it), no redistributed mass (it moves the mass off a stop's node) and no point mass on it (which face would carry
    it?) nor, with ``supports = "clamped-clamped"``, on the clamp at ``x = L``."""
    s = finite("crack_at", s, f"an interior vertex of the mesh in (0, {x[-1]:g})")
    j = np.flatnonzero(np.isclose(x, s, rtol=0, atol=1e-12 * x[-1]))
    if j.size != 1 or j[0] in (0, x.size - 1):
        raise InputError(f"crack_at = {show(s)} is not allowed; a crack must be at an interior vertex of the mesh, "
                         f"in (0, {x[-1]:g}) (vertices at {show(x[1])}, ..., {show(x[-2])})")
    if mass == "redistributed":
        raise InputError("mass = 'redistributed' moves the mass off a stop's node, and a cracked bar has no stop "
                         "(its contact is the crack's faces); use mass = 'consistent' or 'lumped'")
    if any(xp == x[j[0]] for xp, _ in point_masses):
        raise InputError(f"a point mass at the crack x = {show(s)} is not allowed (it would be on one face only); "
                         "put it on another vertex")
    if supports == "clamped-clamped" and any(xp == x[-1] for xp, _ in point_masses):
        raise InputError(f"a point mass (an end mass) at x = L = {show(x[-1])} is on the clamp of a bar clamped at "
                         "both ends; put it on a free vertex")
    return float(x[j[0]])


def split_mesh(x: np.ndarray, s: float):
    """The scikit-fem line mesh of the vertices ``x`` split at the vertex ``s``: the elements from ``s`` on start at
    a second vertex there (the outer face, the mesh's last vertex, so that a stable sort by position puts it after
    the inner one)."""
    import skfem

    x = np.asarray(x, float)
    k = int(np.flatnonzero(x == s)[0])
    t = np.vstack([np.arange(x.size - 1), np.arange(1, x.size)])
    t[0, k] = x.size
    return skfem.MeshLine(np.append(x, x[k])[None, :], t)
