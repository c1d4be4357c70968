"""ParaView output: files read back equal the solver's response."""

import json

import numpy as np
import pytest

import plbar
from plbar import io as pio
from plbar.app import export
from plbar.errors import InputError

pv = pytest.importorskip("pyvista")
meshio = pytest.importorskip("meshio")
pytest.importorskip("h5py")


def _expected(orb, times_local):
    x, v, state = orb.response(np.asarray(times_local)[None, :])
    return x[0], v[0], state[0]


def test_pvd_and_xdmf_read_back_equal_response(default_result, tmp_path):
    f = export.write_response(default_result, tmp_path, format="both", periods=2, steps=16)
    orb, info = export.select(default_result)
    assert f.info["xi"] == pytest.approx(max(b.xi.max() for b in default_result.paths.branches))
    T = info["T"]
    k = np.arange(32)
    t_loc = (k % 16) * T / 16
    x, v, state = _expected(orb, t_loc)
    # .pvd + .vtu through pyvista
    rd = pv.PVDReader(str(f.pvd))
    assert np.allclose(rd.time_values, k * T / 16, rtol=0, atol=1e-12 * T)
    for i in range(32):
        rd.set_active_time_point(i)
        m = rd.read()[0]
        u = np.asarray(m.point_data["displacement"])
        assert m.points[0, 0] == 0.0 and u[0] == 0.0
        np.testing.assert_allclose(u[1:], x[i], rtol=0, atol=1e-12)
        np.testing.assert_allclose(np.asarray(m.point_data["displacement_vec"])[1:, 0], x[i], rtol=0, atol=1e-12)
        np.testing.assert_allclose(np.asarray(m.point_data["velocity"])[1:], v[i], rtol=0, atol=1e-12)
        assert int(m.field_data["state"][0]) == state[i]
        assert float(m.field_data["phase_time"][0]) == pytest.approx(t_loc[i], abs=1e-12 * T)
    # .xdmf + .h5 through meshio
    with meshio.xdmf.TimeSeriesReader(str(f.xdmf)) as r:
        pts, cells = r.read_points_cells()
        assert cells[0].type == "line" and pts.shape[0] == x.shape[1] + 1
        assert r.num_steps == 32
        for i in range(32):
            t, pd, cd = r.read_data(i)
            assert t == pytest.approx(k[i] * T / 16, abs=1e-12 * T)
            np.testing.assert_allclose(pd["displacement"][1:], x[i], rtol=0, atol=1e-12)
    assert json.loads(f.info_json.read_text())["T"] == pytest.approx(T)
    assert [p.name for p in tmp_path.glob(".*")] == [".plbar-owner.json"], "temporary files left behind"


def test_p2_line3_cells_and_energy_consistency(p2_small, tmp_path):
    orb, info = export.select(p2_small, index=0, branch=p2_small.paths.branches[0].id)
    d = pio.response_data(orb, info, steps=12)
    assert d.cell_type == "line3" and d.cells.shape[1] == 3
    # exact element strain energies sum to the modal potential energy; kinetic/potential totals match Orbits
    ek, ep = orb.energies(d.field_data["phase_time"][None, :])
    np.testing.assert_allclose(d.cell_data["strain_energy"].sum(axis=1), ep[0], rtol=1e-10, atol=1e-12 * ep.max())
    np.testing.assert_allclose(d.field_data["kinetic_energy"], ek[0])
    assert np.all(d.point_data["kinetic_energy_density"] >= 0)
    assert np.all(d.field_data["contact_reaction"] >= -1e-9) and np.all(d.field_data["gap"] >= -1e-9)
    f = pio.write_data(d, tmp_path, format="pvd")
    m = pv.read(str(f.vtus[3]))
    assert set(np.unique(m.celltypes)) == {pv.CellType.QUADRATIC_EDGE}
    x, _, _ = _expected(orb, d.field_data["phase_time"])
    np.testing.assert_allclose(np.asarray(m.point_data["displacement"])[1:], x[3], rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.asarray(m.cell_data["stress"]), d.cell_data["stress"][3], rtol=0, atol=1e-12)


def test_from_run_matches_solver(small, tmp_path):
    plbar.write_results(small, tmp_path)
    b = max(small.paths.branches, key=len)
    case, orb, info = export.from_run(tmp_path, branch=b.id, index=1)
    assert case.to_dict() == small.case.to_dict()
    ref = b.orbits.take([1])
    t = np.linspace(0, ref.T[0], 7)
    np.testing.assert_allclose(orb.response(t)[0], ref.response(t)[0], rtol=0, atol=1e-9)
    assert info["xi"] == pytest.approx(b.xi[1], rel=1e-9)


def test_bad_selection_and_format(small, tmp_path):
    with pytest.raises(InputError, match="branch = 999"):
        export.write_response(small, tmp_path, branch=999)
    with pytest.raises(InputError, match="index = 10000"):
        export.write_response(small, tmp_path, index=10000)
    with pytest.raises(InputError, match="format = 'vtk'"):
        export.write_response(small, tmp_path, format="vtk")
    with pytest.raises(InputError, match="periods = 3"):
        export.write_response(small, tmp_path, periods=3)


def test_orbits_source_and_xi_along_mesh(small, tmp_path):
    prob = small.prob
    b = small.paths.branches[0]
    f = export.write_response((prob, b.orbits), tmp_path / "o", steps=8)
    assert len(f.vtus) == 8 and "branch" not in f.info
    bar = prob.bar
    pos = bar.nodes[1:]
    path = pio.write_xi_along_mesh(bar, pos, {"xi_max": np.linspace(0.01, 0.1, pos.size),
                                                 "dPL": np.arange(pos.size, dtype=float)}, tmp_path / "xi.vtu")
    m = pv.read(str(path))
    assert m.n_points == bar.nodes.size
    np.testing.assert_allclose(np.asarray(m.point_data["xi_max"])[1:], np.linspace(0.01, 0.1, pos.size))
    assert m.point_data["xi_max"][0] == 0.0 and list(m.point_data["has_value"]) == [0] + [1] * pos.size
    p2 = pio.write_xi_along_mesh(bar.nodes, [1.25], {"xi": [0.05]}, tmp_path / "xi2.vtu")
    assert pv.read(str(p2)).n_points == bar.nodes.size + 1
    with pytest.raises(InputError, match="one value per position"):
        pio.write_xi_along_mesh(bar, pos, {"xi": [1.0]}, tmp_path / "bad.vtu")
