"""A beam's export (plbar.io.beamfields): deflection, slope, bending moment and shear force on its mesh.

Checked against closed forms the test writes: a cantilever under a static tip force (Hermite elements are exact
for it: ``M = F (L - x)``, ``V = -F``, ``w(L) = F L^3 / (3 EI)``), the element strain energies summing to
``x^T K x / 2`` and the nodal kinetic energies to ``v^T M v / 2`` for any state; and ``plbar export`` of a beam's
periodic response end to end.
"""

import numpy as np
import pytest

from plbar.io.beamfields import BEAM_CELL_FIELDS, BEAM_POINT_FIELDS, beam_fields
from plbar.model import assemble_beam, uniform_beam


@pytest.mark.parametrize("supports", ["clamped-free", "pinned-pinned"])
def test_a_static_tip_force_gives_the_closed_form_moment_and_shear(supports):
    EI, L, F = 2.5, 1.5, 0.7
    beam = uniform_beam(5, L, EI, 1.0, supports)
    a = assemble_beam(beam)
    s = L if supports == "clamped-free" else 0.6 * L            # a node: 3 of 5 elements of a span of 1.5
    x = np.linalg.solve(a.K, F * a.row(s))[None, :]
    pts, cells, point, cell = beam_fields(beam, a, x, np.zeros_like(x), a.M)
    mid = 0.5 * (pts[cells[:, 0]] + pts[cells[:, 1]])
    if supports == "clamped-free":
        M_exact, V_exact = F * (L - pts), np.full(cells.shape[0], -F)
        assert point["deflection"][0, -1] == pytest.approx(F * L ** 3 / (3 * EI), rel=1e-12)
    else:                           # simply supported, a force at s: a triangle, hogging (w'' < 0 under the force)
        M_exact = -np.where(pts <= s, F * (L - s) * pts / L, F * s * (L - pts) / L)
        V_exact = -np.where(mid <= s, F * (L - s) / L, -F * s / L)
    scale = F * L
    assert np.max(np.abs(point["moment"][0] - M_exact)) < 1e-12 * scale
    assert np.max(np.abs(cell["shear"][0] - V_exact)) < 1e-12 * F
    assert point["deflection"][0, 0] == 0.0 and set(point) == set(BEAM_POINT_FIELDS)
    assert set(cell) == set(BEAM_CELL_FIELDS)


def test_the_fields_sum_to_the_beams_energies():
    beam = uniform_beam(7, 2.0, 1.3, 0.8, "clamped-clamped", point_masses=((2.0 * 3 / 7, 0.2),))
    a = assemble_beam(beam)
    rng = np.random.default_rng(3)
    x, v = rng.normal(size=(4, a.n)), rng.normal(size=(4, a.n))
    _, _, point, cell = beam_fields(beam, a, x, v, a.M)
    pe = 0.5 * np.einsum("ki,ij,kj->k", x, a.K, x)
    ke = 0.5 * np.einsum("ki,ij,kj->k", v, a.M, v)
    np.testing.assert_allclose(cell["strain_energy"].sum(axis=1), pe, rtol=1e-12)
    np.testing.assert_allclose(point["kinetic_energy_nodal"].sum(axis=1), ke, rtol=1e-12)


@pytest.mark.slow                    # long: with the slow tests (the default suite under 10 minutes)
def test_plbar_export_writes_a_beams_response(tmp_path):
    meshio = pytest.importorskip("meshio")
    from plbar.cli import main

    run = tmp_path / "run"
    assert main(["run", "--model", "beam", "-N", "4", "--gap", "0.05", "--end-mass", "0.5", "--end-mass-absolute",
                 "--no-plot", "--quiet", "--out", str(run)]) == 0
    assert main(["export", "--from", str(run), "--out", str(tmp_path / "vtk"), "--steps", "8", "--quiet"]) == 0
    m = meshio.read(tmp_path / "vtk" / "response_0003.vtu")
    assert m.points.shape[0] == 5 and set(BEAM_POINT_FIELDS) <= set(m.point_data)
    assert set(BEAM_CELL_FIELDS) <= set(m.cell_data) and m.point_data["deflection"][0] == 0.0
    steps = np.genfromtxt(tmp_path / "vtk" / "response_steps.csv", delimiter=",", names=True)
    free = steps["state"] == 2
    assert np.all(steps["gap"][free] >= -1e-12) and np.all(steps["gap"][~free] == 0.0)
