"""A beam's response on its mesh: deflection, slope, bending moment and shear force (issue 41 item 2's export).

The beam (:mod:`plbar.model.beam`) is sampled at its nodes, the supported ones included (their held DOFs 0), with
``line`` cells, one per element.  On each element the deflection is the Hermite cubic of its end deflections and
slopes (the element's own shape functions, so the fields are those the stiffness was assembled from):

``w(xi) = N1 w_a + h N2 th_a + N3 w_b + h N4 th_b``, ``xi = (x - x_a) / h``, with ``N1 = 1 - 3 xi^2 + 2 xi^3``,
``N2 = xi - 2 xi^2 + xi^3``, ``N3 = 3 xi^2 - 2 xi^3``, ``N4 = xi^3 - xi^2``;

* the **bending moment** ``M = EI w''``, linear along the element: at the points the mean of the adjacent
  elements' end values (``moment``), per cell its value at mid-element (``moment_mid``);
* the **shear force** ``V = dM/dx = EI w'''``, constant along the element (a cell field, ``shear``);
* the **strain energy** of each element, ``int EI w''^2 / 2 = EI h (m_a^2 + m_a m_b + m_b^2) / 6`` with ``m`` the
  curvatures at its ends (a cell field: they sum to ``x^T K x / 2`` exactly);
* the deflection as a vector along ``y`` (``displacement_vec``, for ParaView's *Warp By Vector*), the slope, the
  velocity, and each DOF's share of the kinetic energy ``v_i (M v)_i / 2`` summed onto its node.
"""

from __future__ import annotations

import numpy as np

__all__ = ["BEAM_POINT_FIELDS", "BEAM_CELL_FIELDS", "beam_fields"]

#: the point and cell fields of a beam's response (``*_vec`` are 3-vectors)
BEAM_POINT_FIELDS = ("deflection", "displacement_vec", "slope", "velocity", "velocity_vec", "moment",
                     "kinetic_energy_nodal")
BEAM_CELL_FIELDS = ("moment_mid", "shear", "strain_energy")


def _nodal(asm, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Free-DOF vectors ``a`` (K, n) as the deflections and slopes of every node (K, nodes), the held ones 0."""
    full = np.zeros((a.shape[0], asm.basis.N))
    full[:, asm.free] = a
    nd = asm.basis.nodal_dofs
    return full[:, nd[0]], full[:, nd[1]]


def _curvatures(w: np.ndarray, th: np.ndarray, h: np.ndarray):
    """``w''`` at each element's two ends and ``w'''`` (K, elements) from the nodal ``w, th`` (K, nodes)."""
    wa, wb, ta, tb = w[:, :-1], w[:, 1:], th[:, :-1], th[:, 1:]
    ka = (-6.0 * wa - 4.0 * h * ta + 6.0 * wb - 2.0 * h * tb) / h ** 2
    kb = (6.0 * wa + 2.0 * h * ta - 6.0 * wb + 4.0 * h * tb) / h ** 2
    return ka, kb, (kb - ka) / h


def beam_fields(beam, asm, x: np.ndarray, v: np.ndarray, M: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict, dict]:
    """``(points, cells, point_data, cell_data)`` of the beam's physical states ``x, v`` (K, n free DOFs).

    Parameters
    ----------
    beam : plbar.model.Beam
    asm : plbar.model.BeamAssembled
    x, v : ndarray, shape (K, n)
        Physical DOF vectors (deflections and slopes of the free DOFs, :attr:`BeamAssembled.free` order).
    M : ndarray, shape (n, n)
        The mass matrix over the free DOFs.
    """
    pts = np.asarray(beam.nodes, float)
    h = np.diff(pts)
    cells = np.c_[np.arange(h.size), np.arange(1, h.size + 1)]
    w, th = _nodal(asm, x)
    wv, _ = _nodal(asm, v)
    ka, kb, k3 = _curvatures(w, th, h)
    EI = beam.EI
    moment = np.zeros_like(w)
    count = np.zeros(pts.size)
    np.add.at(moment.T, cells[:, 0], (EI * ka).T)
    np.add.at(moment.T, cells[:, 1], (EI * kb).T)
    np.add.at(count, cells.ravel(), 1.0)
    ke = np.zeros((x.shape[0], asm.basis.N))
    ke[:, asm.free] = 0.5 * v * (v @ M)
    node_of = np.zeros(asm.basis.N, int)
    node_of[asm.basis.nodal_dofs[0]] = node_of[asm.basis.nodal_dofs[1]] = np.arange(pts.size)
    ke_nodal = np.zeros_like(w)
    np.add.at(ke_nodal.T, node_of, ke.T)
    zeros = np.zeros_like(w)
    point = {"deflection": w, "displacement_vec": np.stack([zeros, w, zeros], axis=-1), "slope": th,
             "velocity": wv, "velocity_vec": np.stack([zeros, wv, zeros], axis=-1), "moment": moment / count,
             "kinetic_energy_nodal": ke_nodal}
    cell = {"moment_mid": 0.5 * EI * (ka + kb), "shear": EI * k3,
            "strain_energy": EI * h * (ka * ka + ka * kb + kb * kb) / 6.0}
    return pts, cells, point, cell
