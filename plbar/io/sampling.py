"""A periodic response, or a simulated motion, sampled on its bar mesh: displacements, velocities, strains, energies.

The bar is sampled at its mesh nodes (quadratic ``line3`` cells with their
midside nodes for P2), the clamped node ``x = 0`` included with zero
displacement; see :mod:`plbar.io.vtk` for the fields and their definitions.
The displacements and velocities are those of :meth:`Orbits.response`, so
the files hold exactly the solver's response.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..errors import InputError, PlbarError
from ..model import BeamOrigin
from ..motion import Series
from ..util.reprs import build, rng
from .beamfields import beam_fields

__all__ = ["ResponseData", "response_data", "motion_data", "nodal_stress", "FIELD_KEYS", "POINT_FIELDS",
           "CELL_FIELDS"]

FIELD_KEYS = ("time", "phase_time", "state", "contact_reaction", "gap", "kinetic_energy", "potential_energy")
#: the point and cell fields of a response (what ``plbar render --field`` may colour by; ``*_vec`` are 3-vectors)
POINT_FIELDS = ("displacement", "displacement_vec", "velocity", "velocity_vec", "kinetic_energy_density",
                "potential_energy_density", "stress_nodal", "kinetic_energy_nodal")
CELL_FIELDS = ("strain", "stress", "strain_energy")


@dataclass(frozen=True)
class ResponseData:
    """One periodic response sampled on the bar mesh.

    Attributes
    ----------
    points : ndarray, shape (n_points,)
        Node coordinates sorted along ``x`` (clamp first).
    cells : ndarray of int, shape (n_cells, 2) or (n_cells, 3)
        ``line`` cells, or ``line3`` cells ``(end, end, midside)``.
    cell_type : {"line", "line3"}
    times : ndarray, shape (K,)
        Absolute times ``k T / steps``.
    point_data : dict of name -> ndarray (K, n_points)
    cell_data : dict of name -> ndarray (K, n_cells)
    field_data : dict of name -> ndarray (K,)
    info : dict
        The orbit: ``T1, T2, phi, T`` and, where known, ``branch, index, xi, dPL``.
    """

    points: np.ndarray
    cells: np.ndarray
    cell_type: str
    times: np.ndarray
    point_data: dict
    cell_data: dict
    field_data: dict
    info: dict

    @property
    def n_steps(self) -> int:
        return self.times.size

    def __repr__(self) -> str:
        info = {k: self.info[k] for k in ("T", "T1", "T2", "phi", "branch", "index", "xi") if k in self.info}
        return build("ResponseData", {"points": self.points.size, "x": rng(self.points),
                                      "cells": f"{self.cells.shape[0]} {self.cell_type}", "steps": self.n_steps,
                                      "times": rng(self.times), "point_data": _names(self.point_data),
                                      "cell_data": _names(self.cell_data), "field_data": _names(self.field_data),
                                      "info": "{" + ", ".join(f"{k}: {v:.6g}" if isinstance(v, float) else f"{k}: {v}"
                                                              for k, v in info.items()) + "}"})

    def points3(self) -> np.ndarray:
        """Points as ``(n_points, 3)`` with ``y = z = 0``."""
        return np.c_[self.points, np.zeros((self.points.size, 2))]


def _names(d: dict) -> str:
    return "[" + ", ".join(map(str, d)) + "]"


def _mesh(prob):
    """Sorted points, cells, cell type, per-cell EA, rhoA of ``prob``'s bar, and each free DOF's point."""
    bar, asm = prob.bar, prob.asm
    if bar is None or asm is None:
        raise InputError("export needs a Problem built from a Bar (plbar.problem or Case.problem)")
    if bar.crack_at is not None or bar.supports == "free-free":
        return _split_mesh(bar, asm)
    xd = np.asarray(asm.basis.doflocs[0], float)
    pts = np.sort(xd)
    if pts[0] != 0.0 or pts.size != asm.n + 1 or not np.array_equal(pts[1:], asm.x):
        raise PlbarError("the bar's DOF positions do not match its free DOFs; cannot map the response")
    ne = bar.n_elements
    if bar.element == "P1":
        cells, ctype = np.c_[np.arange(ne), np.arange(1, ne + 1)], "line"
    else:
        i = np.arange(ne)
        cells, ctype = np.c_[2 * i, 2 * i + 2, 2 * i + 1], "line3"
    EA = np.broadcast_to(np.asarray(bar.EA, float), (ne,))
    rA = np.broadcast_to(np.asarray(bar.rhoA, float), (ne,))
    return pts, cells, ctype, EA, rA, np.arange(1, asm.n + 1)


def _split_mesh(bar, asm):
    """:func:`_mesh` of a cracked bar (:mod:`plbar.model.crack`) or one with no support: every basis DOF a point,
    sorted as the free DOFs are (the crack's inner face before its outer one), the cells the basis' own elements
    (the two faces are two points of no common cell: the opening shows), a clamp a point held at 0."""
    xd = np.asarray(asm.basis.doflocs[0], float)
    order = np.argsort(xd, kind="stable")
    at = np.empty(xd.size, int)
    at[order] = np.arange(xd.size)
    ed = at[np.asarray(asm.basis.element_dofs)]           # (2 or 3, elements): the ends, then the midside (P2)
    ed = ed[:, np.argsort(xd[order][ed[0]], kind="stable")]
    ne = ed.shape[1]
    EA = np.broadcast_to(np.asarray(bar.EA, float), (ne,))
    rA = np.broadcast_to(np.asarray(bar.rhoA, float), (ne,))
    return xd[order], ed.T.copy(), "line" if bar.element == "P1" else "line3", EA, rA, at[asm.free]


def _full(a: np.ndarray, at: np.ndarray, n_points: int) -> np.ndarray:
    """Free-DOF values ``a`` (K, n) on every point (the clamps' 0)."""
    out = np.zeros((a.shape[0], n_points))
    out[:, at] = a
    return out


def _strains(u, pts, cells, ctype):
    """Strains at each element's start, middle and end: each (K, n_cells)."""
    a, b = cells[:, 0], cells[:, 1]
    h = pts[b] - pts[a]
    if ctype == "line":
        e = (u[:, b] - u[:, a]) / h
        return e, e, e
    m = cells[:, 2]
    u0, u1, um = u[:, a], u[:, b], u[:, m]
    return (-3 * u0 - u1 + 4 * um) / h, (u1 - u0) / h, (u0 + 3 * u1 - 4 * um) / h


def _node_average(values_at, cells, n_points, K):
    """Average per-element values given at element nodes onto the points."""
    acc = np.zeros((K, n_points))
    cnt = np.zeros(n_points)
    for col, val in values_at:
        np.add.at(acc.T, cells[:, col], val.T)
        np.add.at(cnt, cells[:, col], 1.0)
    return acc / cnt


def nodal_stress(u, points, cells, cell_type: str, EA) -> np.ndarray:
    """``EA du/dx`` at every point: the average of the adjacent elements' end (P2: and midside) values.

    Parameters
    ----------
    u : ndarray, shape (K, n_points) or (n_points,)
        Nodal displacements (clamp included).
    points, cells, cell_type
        As in :class:`ResponseData` (``line``: ``(a, b)``, ``line3``: ``(a, b, midside)``).
    EA : float or ndarray, shape (n_cells,)

    Returns
    -------
    ndarray, shape (K, n_points) (or (n_points,) for a 1D ``u``)
        The element end strains are those of the energy densities: P1 the
        constant ``(u_b - u_a) / h`` of each element, P2 the exact end and
        midside derivatives of the element's quadratic.  A vertex shared by two
        elements gets the mean of their two end stresses; for P1 that is the
        mean of the adjacent cell ``stress`` values.
    """
    u = np.asarray(u, float)
    uu = np.atleast_2d(u)
    points, cells = np.asarray(points, float), np.asarray(cells)
    e0, em, e1 = _strains(uu, points, cells, cell_type)
    EA = np.broadcast_to(np.asarray(EA, float), (cells.shape[0],))
    at = [(0, EA * e0), (1, EA * e1)] + ([(2, EA * em)] if cell_type == "line3" else [])
    out = _node_average(at, cells, points.size, uu.shape[0])
    return out if u.ndim == 2 else out[0]


def _densities(u, vel, pts, cells, ctype, EA, rA):
    """Mid-element strain, element strain energy, nodal potential and kinetic energy densities per step."""
    K = u.shape[0]
    e0, em, e1 = _strains(u, pts, cells, ctype)
    h = pts[cells[:, 1]] - pts[cells[:, 0]]
    if ctype == "line":
        sen = 0.5 * EA * h * em ** 2
    else:
        sen = EA * h * (e0 ** 2 + e0 * e1 + e1 ** 2) / 6.0
    pe_at = [(0, 0.5 * EA * e0 ** 2), (1, 0.5 * EA * e1 ** 2)]
    rho_at = [(0, rA[None, :]), (1, rA[None, :])]
    if ctype == "line3":
        pe_at.append((2, 0.5 * EA * em ** 2))
        rho_at.append((2, rA[None, :]))
    ped = _node_average(pe_at, cells, pts.size, K)
    rho_pt = _node_average(rho_at, cells, pts.size, 1)[0]
    return em, sen, ped, 0.5 * rho_pt * vel ** 2


def response_data(orbit, info: dict | None = None, periods: int = 1, steps: int = 40) -> ResponseData:
    """Sample a single periodic response on its bar mesh (no files).

    Parameters
    ----------
    orbit : Orbits or plbar.motion.Series
        One orbit (its first is used), or an orbit of another signature as a series
        (:func:`plbar.periodic.orbit_series`: sampled over its whole orbit, ``m`` forcing periods); ``orbit.prob``
        must come from a Bar.
    info : dict, optional
        Extra orbit information kept in :attr:`ResponseData.info`.
    periods : {1, 2}
        Periods to sample.
    steps : int
        Steps per period (>= 4); times ``k T / steps``, ``k = 0 .. periods*steps - 1``.
    """
    if periods not in (1, 2) or isinstance(periods, bool):
        raise InputError(f"periods = {periods!r} is not allowed; choose 1 or 2")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 4:
        raise InputError(f"steps = {steps!r} must be an integer >= 4 (steps per period)")
    series = isinstance(orbit, Series)
    orb = orbit if series else orbit.take([0])
    T = float(orb.span) if series else float(orb.T[0])
    k = np.arange(periods * steps)
    t_abs = k * T / steps
    t_loc = (k % steps) * T / steps
    if series:
        x, v, state = orb.response(t_loc)
        margin = orb.reaction(t_loc)
        ek, ep = orb.energies(t_loc)
        full = {"T1": float(orb.stuck_time), "T2": float(orb.free_time), "phi": float(np.mod(orb.phi, 2 * np.pi)),
                "T": T}
    else:
        x, v, state = (a[0] for a in orb.response(t_loc[None, :]))
        margin = orb.reaction_margin(np.minimum(t_loc, orb.T1[0])[None, :])[0]
        ek, ep = (a[0] for a in orb.energies(t_loc[None, :]))
        full = {"T1": float(orb.T1[0]), "T2": float(orb.T2[0]), "phi": float(np.mod(orb.phi[0], 2 * np.pi)), "T": T}
    full.update(info or {})
    full.update({"periods": periods, "steps": steps})
    return _sampled(orb.prob, t_abs, _Samples(t_abs, t_loc, x, v, state, margin, ek, ep), full)


def _nodal_kinetic(M, v) -> np.ndarray:
    """Each DOF's share of the kinetic energy, ``v_i (M v)_i / 2``: it sums to ``v^T M v / 2`` (Eq. (12)) for any
    mass matrix, consistent or lumped, with point masses and the chain's."""
    Mv = (M @ v.T).T if not hasattr(M, "toarray") else np.asarray(M @ v.T).T
    return 0.5 * v * Mv


class _Samples(NamedTuple):
    """The states sampled: at absolute times ``t_abs`` (``t_loc`` in the period or window), ``x, v`` (K, n), the
    contact ``state``, the wall's reaction ``margin`` and the kinetic and potential energies ``ek, ep`` (K,)."""

    t_abs: np.ndarray
    t_loc: np.ndarray
    x: np.ndarray
    v: np.ndarray
    state: np.ndarray
    margin: np.ndarray
    ek: np.ndarray
    ep: np.ndarray


def _sampled(prob, times, sm: _Samples, info, extra=None) -> ResponseData:
    """The fields of the sampled states ``sm`` on the mesh of ``prob`` (``times`` the series' own)."""
    t_abs, t_loc, x, v, state, margin, ek, ep = sm
    inI, zero = state == 1, np.zeros(t_loc.size)
    opening = prob.gap - x[:, -1] if prob.gap else -x[:, -1]   # d - u, u the contact coordinate (FORMULATION §9)
    field = {
        "time": t_abs, "phase_time": t_loc, "state": state.astype(np.int32),
        "contact_reaction": np.where(inI, margin, zero), "gap": np.where(inI, zero, opening),
        "kinetic_energy": ek, "potential_energy": ep, **(extra or {}),
    }
    origin = prob.origin
    if isinstance(origin, BeamOrigin):       # a beam: deflection, slope, moment, shear (plbar.io.beamfields)
        st = prob.structure
        pts, cells, point, cell = beam_fields(origin.beam, origin.asm, st.physical(x), st.physical(v), st.M)
        return ResponseData(pts, cells, "line", times, point, cell, field, dict(info, cell_type="line"))
    pts, cells, ctype, EA, rA, at = _mesh(prob)
    M = prob.system.M
    if prob.bar.crack_at is not None:        # a crack's contact coordinates are not its DOFs: x = B y
        x, v, M = prob.structure.physical(x), prob.structure.physical(v), prob.structure.M
    u, vel = _full(x, at, pts.size), _full(v, at, pts.size)
    em, sen, ped, ked = _densities(u, vel, pts, cells, ctype, EA, rA)
    zeros2 = np.zeros_like(u)
    point = {
        "displacement": u, "displacement_vec": np.stack([u, zeros2, zeros2], axis=-1),
        "velocity": vel, "velocity_vec": np.stack([vel, zeros2, zeros2], axis=-1),
        "kinetic_energy_density": ked, "potential_energy_density": ped,
        "stress_nodal": nodal_stress(u, pts, cells, ctype, EA),
        "kinetic_energy_nodal": _full(_nodal_kinetic(M, v), at, pts.size),
    }
    cell = {"strain": em, "stress": EA * em, "strain_energy": sen}
    crack = {} if prob.bar.crack_at is None else {"crack_at": prob.bar.crack_at, "supports": prob.bar.supports}
    return ResponseData(pts, cells, ctype, times, point, cell, field, dict(info, cell_type=ctype, **crack))


def motion_data(series, steps: int = 40, info: dict | None = None) -> ResponseData:
    """Sample a simulated motion (:func:`plbar.motion.motion_series`, or a continuum's
    :class:`plbar.continuum.ContinuumSeries`) on its bar mesh, events marked.

    ``steps`` samples per forcing period over the series' window, and one more just after every event (opening or
    impact), so the time series holds the impacts as marked steps: the per-step fields ``event`` (0 a regular
    sample, 1 the gap opens, 2 an impact, 3 an impact followed at once by the opening: a zero dwell, one step
    since the times of a series increase strictly; with a coefficient of restitution: 4 a rebound, the gap stays
    open, and 5 the impact that ends a chattering sequence, the contact stuck after it, marked at the
    accumulation point of its rebounds) and ``impact_loss`` (the energy an impact took, Eq. (14), times
    ``1 - e^2`` for a rebound; 0 elsewhere).
    ``time`` is absolute; the series' own times (``times``, ``phase_time``) run from 0 at the window's start, and
    ``info["T"]`` is the window's length, so that a render draws the whole window.
    """
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 4:
        raise InputError(f"steps = {steps!r} must be an integer >= 4 (steps per period)")
    P, T, t0 = series.periods, series.T, series.t0
    grid = t0 + np.arange(P * steps + 1) * (T / steps)
    ev = series.events
    inside = ev["time"] < t0 + series.span
    t_ev, k_ev, l_ev = ev["time"][inside], ev["kind"][inside].astype(np.int32), ev["loss"][inside]
    k_ev = np.where(k_ev >= 3, k_ev + 1, k_ev)  # the simulator's rebound (3) and chatter's end (4): codes 4 and 5
    # one step per distinct time: an impact and the opening that follows it at once (a zero dwell) are one step
    u_ev, first = np.unique(t_ev, return_index=True)
    code = np.zeros(u_ev.size, np.int32)
    loss_ev = np.zeros(u_ev.size)
    where = np.searchsorted(u_ev, t_ev)
    np.add.at(code, where, k_ev)                # 1 opening, 2 impact, 3 impact with an immediate opening
    np.add.at(loss_ev, where, np.where(k_ev >= 2, l_ev, 0.0))
    grid = grid[~np.isin(grid, u_ev)]
    t_abs = np.concatenate([grid, u_ev])
    kind = np.concatenate([np.zeros(grid.size, np.int32), code])
    loss = np.concatenate([np.zeros(grid.size), loss_ev])
    order = np.argsort(t_abs, kind="stable")
    t_abs, kind, loss = t_abs[order], kind[order], loss[order]
    x, v, state = series.response(t_abs)           # at an event's own time: the state just after it
    margin = series.reaction(t_abs)
    ek, ep = series.energies(t_abs)
    full = {"T1": float(series.stuck_time), "T2": float(series.span - series.stuck_time), "phi": series.phi,
            "T": float(series.span), "T_forcing": T, "t_start": float(t0), "periods": int(P), "steps": int(steps),
            "impacts": int(np.sum(kind >= 2)), "openings": int(np.sum((kind == 1) | (kind == 3))),
            "impact_loss": float(loss.sum()), "motion": True}
    full.update(info or {})
    return _sampled(series.prob, t_abs - t0, _Samples(t_abs, t_abs - t0, x, v, state, margin, ek, ep), full,
                    extra={"event": kind, "impact_loss": loss})
