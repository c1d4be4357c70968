"""sweep_loads: the old per-load sweep tables reproduced from one path solve, and the study outputs."""

import csv
import json

import numpy as np
import pytest

import plbar
from plbar.studies.loads import bruteforce as sweep
from plbar.studies.loads import WORST_HEADER, pair_table, sweep_loads
from plbar.studies import solve_task

GRID = (60, 60)
POSITIONS = [1.0, 2.5, 3.3]
PAIRS = [((1.0, 0.5), (3.0, 0.5)), ((2.0, 0.5), (4.0, 0.5))]


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("loads")
    first = plbar.solve(plbar.Case(signatures="paper", grid=GRID))
    s = first.prob.system
    T = float(first.branches[-1].T[len(first.branches[-1]) // 2])
    q = (s.K - (2 * np.pi / T) ** 2 * s.M)[:, 0]                 # h(q) = 0 at that path point (u = e_1)
    zero_load = ((1.0, float(q[0])), (2.0, float(q[1])))
    res = sweep_loads(plbar.Case(grid=GRID), out, per_element=10, loads=[zero_load])
    return out, res, (zero_load, T)


def test_old_sweep_tables_reproduced(study):
    """plbar.studies.loads.bruteforce (one full solve per load: positions and node pairs) = the quadratic forms."""
    _, res, _ = study
    st = sweep.load_sweep_study(5, positions=POSITIONS, pairs=PAIRS, grid=GRID)
    results = [solve_task(t) for t in st.tasks]
    old = sweep.sweep_tables(st.tasks, results)
    lf, fam = res.forms, res.families
    loads = [((s, 1.0),) for s in POSITIONS] + list(PAIRS)
    new = pair_table(lf, fam, loads)
    key = lambda t, i: (t["s1"][i], t["a1"][i], repr(t["s2"][i]), t["family"][i])
    nmap = {key(new, i): i for i in range(len(new["family"]))}
    checked = 0
    for i in range(len(old.maxima["family"])):
        j = nmap[key(old.maxima, i)]
        assert old.maxima["points"][i] == new["points"][j]
        for k in ("xi_max", "xi_min", "dPL_at_max"):
            assert abs(old.maxima[k][i] - new[k][j]) < 1e-9 * max(1.0, abs(old.maxima[k][i])), k
        for k in ("T_at_max", "T1_at_max", "T2_at_max", "T_min", "T_max"):
            assert abs(old.maxima[k][i] - new[k][j]) < 1e-9, k
        d = old.maxima["phi_at_max"][i] - new["phi_at_max"][j]       # the load's own admissible phase (not mod pi)
        assert abs(np.angle(np.exp(1j * d))) < 1e-9 and 0 <= new["phi_at_max"][j] < 2 * np.pi, "phi_at_max"
        checked += 1
    assert checked == len(loads) * 2
    # the tidy rows too: every point of every load case
    rows = old.rows
    for ci, ld in enumerate(loads):
        m = np.asarray(rows["case"]) == ci
        xi_new = lf.xi(np.sum([a * lf.point_vectors([s])[0] for s, a in ld], axis=0))
        assert np.abs(np.asarray(rows["xi"])[m] - xi_new).max() < 1e-9


def test_outputs(study):
    out, res, _ = study
    for f in ("xi_positions.npz", "worst_load.csv", "worst_load_shapes.npz", "xi_along_mesh.vtu",
              "load_pairs.csv", "summary.json", "xi_T_s.png"):
        assert (out / f).stat().st_size > 0, f
    with open(out / "worst_load.csv") as fh:
        rd = list(csv.reader(fh))
    assert rd[0] == WORST_HEADER
    lf = res.forms
    assert len(rd) - 1 == len(lf)
    vals = np.array(rd[1:], float)
    assert np.all(np.isfinite(vals))
    assert np.all(vals[:, 6] >= vals[:, 7] * (1 - 1e-12))          # worst >= best single force
    pos = np.load(out / "xi_positions.npz")
    assert pos["xi"].shape == pos["dPL"].shape == (len(lf), 50)    # 5 elements x 10 positions
    assert pos["s"].shape == (50,) and pos["T"].shape == pos["branch"].shape == (len(lf),)
    assert np.all(np.isfinite(pos["xi"])) and np.array_equal(pos["T"], lf.T)
    z = np.load(out / "worst_load_shapes.npz")
    assert z["q_star"].shape == (len(lf), lf.n)
    assert np.allclose(np.linalg.norm(z["q_star"], axis=1), 1.0)


def test_zero_contact_response_is_reported(study):
    out, res, (zero_load, T) = study
    summ = json.loads((out / "summary.json").read_text())
    assert summ == json.loads(json.dumps(res.summary))
    name = "+".join(f"{a:g}@{s:g}" for s, a in zero_load)
    hit = [e for e in summ["no_path"] if e["load"] == name]
    assert hit and hit[0]["points"] >= 1 and not hit[0]["all_points"]
    assert any(a["T"] == T for a in hit[0]["at"])


def test_single_force_best_matches_positions(study):
    """The exact best single force is >= every sampled position (xi_positions.npz)."""
    _, res, _ = study
    xi = res.positions["xi"]
    w = res.worst_load
    assert np.all(xi.max(axis=1) <= w["xi_best_single"] + 1e-14)
    assert np.all(w["xi_best_single"] <= w["xi_worst"] * (1 + 1e-12))


def test_the_study_is_a_frozen_result_object(study):
    """A LoadStudy like every study result: files, summary and the tables as attributes; a short repr."""
    import dataclasses

    out, res, _ = study
    assert isinstance(res, plbar.studies.LoadStudy) and dataclasses.is_dataclass(res)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.summary = {}
    assert set(res.files) >= {"xi_positions", "worst_load", "load_pairs", "summary"}
    assert res.tables["worst"] is res.worst_load and res.pairs["family"] and res.case == plbar.Case(grid=GRID)
    r = repr(res)
    assert r.startswith("LoadStudy(path_points=") and len(r) < 300 and "xi_worst=" in r


def test_xi_along_mesh_holds_the_evaluated_positions(study):
    """Issue 44: the .vtu is a line through the 50 evaluated positions with the table's values, not the mesh's 6
    vertices."""
    meshio = pytest.importorskip("meshio")
    out, res, _ = study
    pos = np.load(out / "xi_positions.npz")
    m = meshio.read(out / "xi_along_mesh.vtu")
    order = np.argsort(pos["s"])
    assert m.points.shape[0] == pos["s"].size == 50
    np.testing.assert_array_equal(m.points[:, 0], pos["s"][order])
    np.testing.assert_array_equal(m.point_data["xi_eq_max"], pos["xi"].max(axis=0)[order])
    np.testing.assert_array_equal(m.point_data["dPL_max"], pos["dPL"].max(axis=0)[order])
    assert np.all(m.point_data["has_value"] == 1)
    assert sum(c.data.shape[0] for c in m.cells) == 49          # the polyline's segments
