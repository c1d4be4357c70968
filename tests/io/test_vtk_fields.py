"""VTK fields: the XDMF carries the per-step state, contact reaction and gap; nodal stresses for P1 and P2."""

import numpy as np
import pytest

from plbar import io as pio
from plbar.io.sampling import nodal_stress

meshio = pytest.importorskip("meshio")
pytest.importorskip("h5py")


def _largest_xi(res):
    b = max(res.paths.branches, key=lambda b: b.xi.max())
    j = int(np.argmax(b.xi))
    return b.orbits.take([j]), {"branch": b.id, "index": j, "xi": float(b.xi[j])}


@pytest.mark.parametrize("fixture", ["small", "p2_small"])
def test_xdmf_has_state_reaction_and_gap_of_the_steps_csv(fixture, request, tmp_path):
    res = request.getfixturevalue(fixture)
    orb, info = _largest_xi(res)
    d = pio.response_data(orb, info, periods=2, steps=10)
    f = pio.write_data(d, tmp_path, format="xdmf")
    csv = np.genfromtxt(f.steps_csv, delimiter=",", names=True)
    assert csv.size == 20 and set(csv["state"]) == {1.0, 2.0}
    assert np.any(csv["contact_reaction"] > 0) and np.any(csv["gap"] > 0)
    with meshio.xdmf.TimeSeriesReader(str(f.xdmf)) as r:
        pts, _ = r.read_points_cells()
        assert r.num_steps == 20
        for k in range(r.num_steps):
            t, pd, _ = r.read_data(k)
            assert t == pytest.approx(csv["time"][k], rel=1e-15, abs=1e-15)
            for nm in ("state", "contact_reaction", "gap", "phase_time", "kinetic_energy", "potential_energy"):
                v = np.asarray(pd[nm])
                assert v.shape == (pts.shape[0],)
                assert np.all(v == v[0]), nm                  # constant over the mesh
                assert v[0] == pytest.approx(csv[nm][k], rel=1e-14, abs=1e-300), nm
            assert np.issubdtype(np.asarray(pd["state"]).dtype, np.integer)
            np.testing.assert_allclose(pd["stress_nodal"], d.point_data["stress_nodal"][k], rtol=0, atol=1e-13)


def test_nodal_stress_p1_is_the_mean_of_adjacent_element_stresses():
    x = np.array([0.0, 0.3, 0.5, 1.1, 1.6])                  # non-uniform
    cells = np.c_[np.arange(4), np.arange(1, 5)]
    u = x ** 2                                                # element strains x_a + x_b
    s = nodal_stress(u, x, cells, "line", 2.0)
    elem = 2.0 * (x[:-1] + x[1:])
    expect = np.r_[elem[0], 0.5 * (elem[:-1] + elem[1:]), elem[-1]]
    np.testing.assert_allclose(s, expect, rtol=1e-14)
    np.testing.assert_allclose(s, [0.6, 1.1, 2.4, 4.3, 5.4], rtol=1e-14)
    # per-element EA: each end stress with its own element's EA
    EA = np.array([1.0, 2.0, 3.0, 4.0])
    e = EA * (x[:-1] + x[1:])
    np.testing.assert_allclose(nodal_stress(u, x, cells, "line", EA),
                               np.r_[e[0], 0.5 * (e[:-1] + e[1:]), e[-1]], rtol=1e-14)


def test_nodal_stress_p2_is_exact_for_a_quadratic_field():
    v = np.array([0.0, 0.2, 0.7, 1.0])                        # vertices
    m = 0.5 * (v[:-1] + v[1:])                                # midside nodes
    pts = np.sort(np.r_[v, m])
    idx = {float(p): i for i, p in enumerate(pts)}
    cells = np.array([[idx[a], idx[b], idx[c]] for a, b, c in zip(v[:-1], v[1:], m)])
    a, b, EA = 1.5, -0.4, 3.0
    u = np.stack([a * pts ** 2 + b * pts, 2 * (a * pts ** 2 + b * pts)])   # two steps
    s = nodal_stress(u, pts, cells, "line3", EA)
    exact = EA * (2 * a * pts + b)
    np.testing.assert_allclose(s[0], exact, rtol=0, atol=1e-13)
    np.testing.assert_allclose(s[1], 2 * exact, rtol=0, atol=1e-13)
    # the one cell value is the midpoint stress only: it misses the ends by EA * a * h
    cell = EA * (u[0, cells[:, 1]] - u[0, cells[:, 0]]) / (pts[cells[:, 1]] - pts[cells[:, 0]])
    np.testing.assert_allclose(cell, exact[cells[:, 2]], rtol=0, atol=1e-13)


def test_response_data_stress_nodal_p1_and_p2(small, p2_small, tmp_path):
    orb, info = _largest_xi(small)
    d = pio.response_data(orb, info, steps=8)
    cs = d.cell_data["stress"]                                 # (K, n_cells), P1 chain
    sn = d.point_data["stress_nodal"]
    np.testing.assert_allclose(sn[:, 1:-1], 0.5 * (cs[:, :-1] + cs[:, 1:]), rtol=0, atol=1e-13)
    np.testing.assert_allclose(sn[:, [0, -1]], cs[:, [0, -1]], rtol=0, atol=1e-13)
    orb, info = _largest_xi(p2_small)
    d = pio.response_data(orb, info, steps=8)
    u, x, c = d.point_data["displacement"], d.points, d.cells
    sn = d.point_data["stress_nodal"]
    np.testing.assert_allclose(sn[:, c[:, 2]], d.cell_data["stress"], rtol=0, atol=1e-12)   # midside
    h = x[c[:, 1]] - x[c[:, 0]]
    EA = np.broadcast_to(np.asarray(p2_small.prob.bar.EA, float), (c.shape[0],))
    start = EA * (-3 * u[:, c[:, 0]] - u[:, c[:, 1]] + 4 * u[:, c[:, 2]]) / h     # du/dx of the quadratic
    end = EA * (u[:, c[:, 0]] + 3 * u[:, c[:, 1]] - 4 * u[:, c[:, 2]]) / h
    np.testing.assert_allclose(sn[:, 0], start[:, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(sn[:, -1], end[:, -1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(sn[:, c[1:, 0]], 0.5 * (end[:, :-1] + start[:, 1:]), rtol=0, atol=1e-12)
    pv = pytest.importorskip("pyvista")
    f = pio.write_data(d, tmp_path, format="pvd")
    m = pv.read(str(f.vtus[2]))
    np.testing.assert_allclose(np.asarray(m.point_data["stress_nodal"]), sn[2], rtol=0, atol=1e-13)
