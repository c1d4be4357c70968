"""A newcomer's second hour (issue 22): each item through ``main(argv)``, the public API or a subprocess.

Every test here failed on the code before the fix it covers.
"""

import io
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import plbar
from plbar.cli import main
from plbar.errors import InputError, OutputExistsError

PAPER = ["--signatures", "paper"]      # the paper's class only: these runs are not about the other signatures

ROOT = Path(__file__).resolve().parents[2]
MESH = ROOT / "meshes" / "bar_uniform_8.msh"
FAST = ["--grid", "30", "30", "-q", "--no-plot"]


def _run(capsys, argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _refused(capsys, argv, *words):
    """Exit 2 with one line on stderr naming ``words``; returns the line."""
    code, _, err = _run(capsys, argv)
    assert code == 2 and err.count("\n") == 1 and err.startswith("plbar: error:"), err
    for w in words:
        assert w in err, (w, err)
    return err


# 1. one rule for which options apply to which model, checked in Case ---------------------------------------------

@pytest.mark.parametrize("argv, words", [
    (["--mesh-file", MESH], ["mesh_file", "model = 'chain'", "--model fe"]),
    (["--model", "fe", "--mesh-file", MESH, "-N", "16"], ["n = 16", "mesh_file", "drop n (-N)"]),
    (["--grading", "3"], ["grading = 3.0", "model = 'chain'"]),
    (["--model", "fe", "--mesh-file", MESH, "--grading", "3"], ["grading = 3.0", "fixes the mesh"]),
    (["--end-mass-absolute"], ["end_mass_absolute", "--end-mass M"]),
    (["--model", "fe", "--end-mass-absolute"], ["end_mass_absolute", "--end-mass M"]),
])
def test_options_that_do_not_apply_are_refused(tmp_path, capsys, argv, words):
    _refused(capsys, ["run", *argv, "--out", tmp_path / "o", *FAST], *words)
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("kw", [dict(mesh_file=str(MESH)), dict(model="fe", mesh_file=str(MESH), n=16),
                                dict(grading=3.0), dict(model="fe", mesh_file=str(MESH), grading=2.0),
                                dict(end_mass_absolute=True), dict(EA=2.0), dict(model="chain", length=2.5),
                                dict(model="fe", m=2.0), dict(model="fe", mesh_file=str(MESH), length=2.0)])
def test_case_is_the_one_validator(kw):
    with pytest.raises(InputError) as exc:
        plbar.Case(**kw)
    assert "\n" not in str(exc.value) and ("does not apply" in str(exc.value) or "mesh" in str(exc.value)
                                           or "end mass" in str(exc.value))


def test_summary_records_only_the_options_used(tmp_path, capsys):
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", tmp_path / "c", *FAST])[0] == 0
    case = json.loads((tmp_path / "c" / "summary.json").read_text())["case"]
    assert not {"element", "mass", "grading", "mesh_file", "EA", "rhoA", "point_masses"} & set(case)
    assert case["n"] == 4 and case["length"] == 4.0
    assert _run(capsys, ["run", *PAPER, "--model", "fe", "--mesh-file", MESH, "--out", tmp_path / "m", *FAST])[0] == 0
    s = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert not {"n", "grading", "length", "m", "k"} & set(s["case"]) and s["dofs"] == 8
    assert plbar.app.case_of_run(tmp_path / "m").bar().n_elements == 8


def test_refine_refuses_grading_on_the_chain_before_any_folder(tmp_path, capsys):
    _refused(capsys, ["refine", "-N", "3", "4", "--grading", "3", "--out", tmp_path / "r"], "grading = 3.0")
    _refused(capsys, ["refine", "-N", "3", "4", "--modes", "3", "--out", tmp_path / "r"], "--modes")
    _refused(capsys, ["refine", "-N", "3", "4", "--window", "5", "--out", tmp_path / "r"], "window = 5.0")
    assert not (tmp_path / "r").exists()


# 2. one ownership rule for output folders across commands --------------------------------------------------------

def test_run_then_sweep_loads_into_one_folder_is_refused(tmp_path, capsys):
    out = tmp_path / "Y"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", out, *FAST])[0] == 0
    before = (out / "summary.json").read_text()
    _refused(capsys, ["sweep-loads", "-N", "4", "--out", out, *FAST], "'plbar run'", "--overwrite")
    assert (out / "summary.json").read_text() == before
    _refused(capsys, ["refine", "-N", "3", "4", "--grid", "30", "30", "--out", out, "-q"], "'plbar run'")
    assert not (out / "study.json").exists() and not (out / "levels").exists()


def test_run_into_a_refine_folder_is_refused_and_overwrite_clears_only_the_owners_files(tmp_path, capsys):
    out = tmp_path / "R"
    assert _run(capsys, ["refine", "-N", "3", "4", "--grid", "30", "30", "--executor", "serial", "--out", out,
                         "-q", "--no-plot"])[0] == 0
    (out / "notes.txt").write_text("mine")
    _refused(capsys, ["run", *PAPER, "-N", "4", "--out", out, *FAST], "'plbar refine'")
    _refused(capsys, ["sweep-loads", "-N", "4", "--out", out, *FAST], "'plbar refine'")
    assert (out / "study.json").is_file() and (out / "levels").is_dir()
    assert _run(capsys, ["sweep-loads", "-N", "4", "--out", out, *FAST, "--overwrite"])[0] == 0
    names = {p.name for p in out.iterdir()}
    assert not {"study.json", "tasks", "levels", "refine.csv"} & names and "notes.txt" in names
    owner = json.loads((out / ".plbar-owner.json").read_text())
    assert owner["command"] == "sweep-loads" and owner["plbar"] == plbar.__version__


def test_the_marker_names_command_case_and_owned_files(tmp_path, capsys):
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", tmp_path, *FAST])[0] == 0
    m = json.loads((tmp_path / ".plbar-owner.json").read_text())
    assert set(m) == {"command", "fingerprint", "owned", "plbar"} and m["command"] == "run"
    assert m["fingerprint"] == plbar.app.case_fingerprint(plbar.Case(n=4, grid=(30, 30), signatures="paper"))
    assert {"paths.csv", "summary.json", "vtk", "render"} <= set(m["owned"])


def test_claim_folder_is_one_rule_for_every_command(tmp_path):
    from plbar.util.outputs import check_folder, claim_folder, read_owner

    d = tmp_path / "a" / "b"
    claim_folder(d, "survey", "f1", ("survey.csv", "parts"), False)
    (d / "survey.csv").write_text("x")
    claim_folder(d, "survey", "f1", ("survey.csv",), False)                  # the same study: resumes
    with pytest.raises(OutputExistsError, match="another case"):
        claim_folder(d, "survey", "f2", ("survey.csv",), False)
    with pytest.raises(OutputExistsError, match="'plbar survey'"):
        claim_folder(d, "run", "f1", ("paths.csv",), False)
    claim_folder(d, "export", "f1", ("response.pvd",), False, joins=("survey",))   # joins the same case
    assert read_owner(d).command == "survey" and "response.pvd" in read_owner(d).owned
    (d / "response.pvd").write_text("x")
    claim_folder(d, "run", "f3", ("paths.csv",), True)                       # overwrite: the old owner's files go
    assert not (d / "survey.csv").exists() and not (d / "response.pvd").exists()
    e = tmp_path / "new" / "deep"
    with pytest.raises(KeyboardInterrupt), check_folder(e, "run", "f", ("paths.csv",)) as claim:
        claim.take()
        raise KeyboardInterrupt                                         # nothing written: the claim is undone
    assert not (tmp_path / "new").exists()


def test_export_into_the_run_folder_then_run_overwrite_leaves_no_stale_paraview_data(tmp_path, capsys):
    pytest.importorskip("pyvista")
    R = tmp_path / "R"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", R, *FAST])[0] == 0
    assert _run(capsys, ["export", "--from", R, "--out", R, "--steps", "8", "-q"])[0] == 0
    assert (R / "response.pvd").is_file() and (R / "response.json").is_file()
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--load-node", "3", "--out", R, *FAST, "--overwrite"])[0] == 0
    left = sorted(p.name for p in R.iterdir() if p.name.startswith("response"))
    assert left == [] and json.loads((R / "summary.json").read_text())["case"]["load_nodes"] == [[3, 1.0]]


# 3. progress and messages: whole lines when stderr is not a terminal ------------------------------------------------

def test_progress_is_whole_lines_and_messages_start_on_a_new_line(monkeypatch):
    from plbar.util import progress as prog

    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr(prog, "EVERY", 0.0)
    with prog.progress_bar(4, True, "scanning", "point", delay=0.0) as bar:
        bar.update(1)
        prog.message("plbar: warning: something")
        bar.update(3)
    text = err.getvalue()
    assert "\r" not in text and text.endswith("\n")
    lines = text.splitlines()
    assert all(line.startswith("plbar: ") for line in lines), lines
    assert "plbar: warning: something" in lines and lines[-1].startswith("plbar: scanning: 4/4 points (100 %), done")


def test_a_piped_run_writes_whole_lines(tmp_path):
    """A real run with progress on and stderr a pipe: no carriage return, every line a plbar message."""
    r = subprocess.run([sys.executable, "-m", "plbar", "run", *PAPER, "--model", "fe", "-N", "6", "--element", "P2",
                        "--grid", "40", "40", "--out", str(tmp_path / "o"), "--no-plot"],
                       capture_output=True, text=True, env=dict(os.environ, PLBAR_PROGRESS_DELAY="0"), timeout=600)
    assert r.returncode == 0, r.stderr
    assert "\r" not in r.stderr and r.stderr.endswith("\n")
    lines = r.stderr.splitlines()
    assert lines and all(line.startswith("plbar: ") for line in lines), lines
    assert any("warning" in line for line in lines) and any("scanning" in line for line in lines)


def test_edge_refinement_shows_progress(monkeypatch):
    import plbar.util.progress as prog

    seen = []
    real = prog.progress_bar

    def spy(total, enabled, desc, unit="it", delay=1.0, initial=0):
        seen.append((desc, enabled))
        return real(total, False, desc, unit, delay)

    monkeypatch.setattr(sys.modules["plbar.paths.scan"], "progress_bar", spy)
    plbar.find_paths(plbar.Case(n=3).problem(), grid=(30, 30), progress=True)
    assert ("refining crossings", True) in seen


def test_run_says_what_a_large_solve_costs_before_it_starts(tmp_path, capsys, monkeypatch):
    import plbar.cli.run as cli_run

    def stop(*a, **k):
        raise KeyboardInterrupt                                     # the user's Ctrl-C, right at the start

    monkeypatch.setattr(cli_run, "solve", stop)
    code, _, err = _run(capsys, ["run", *PAPER, "--model", "fe", "-N", "2000", "--out", tmp_path / "big", "--yes"])
    lines = err.splitlines()
    assert code == 130 and len(lines) == 2 and "days" in lines[0] and "GB" in lines[0]
    assert "'plbar refine'" in lines[0] and "--modes" in lines[0]
    assert lines[1].startswith("plbar: interrupted") and "continue a study" not in lines[1]
    assert not (tmp_path / "big").exists()                      # an interrupted run leaves no empty folder
    code, _, err = _run(capsys, ["run", *PAPER, "--model", "fe", "-N", "8", "--out", tmp_path / "small"])
    assert code == 130 and "note" not in err


def test_cost_estimate_follows_the_measured_scaling():
    from plbar.app.cost import estimate_cost

    for n, seconds in ((10, 4.6), (20, 32.0), (50, 239.0), (100, 583.0)):        # docs/speed.md
        c = estimate_cost(plbar.Case(model="fe", n=n, signatures="paper"))
        assert seconds / 2 < c.seconds < 2 * seconds, (n, c)
        assert c.signatures == 0
    assert estimate_cost(plbar.Case(model="fe", n=100, modes=20, signatures="paper")).seconds < 60
    assert estimate_cost(plbar.Case(model="fe", n=100, grid=(100, 100), signatures="paper")).seconds < 200
    for n, seconds in ((16, 70.0), (32, 220.0)):                                 # the search for every signature
        c = estimate_cost(plbar.Case(model="fe", n=n, end_mass=0.5))
        assert seconds / 2 < c.signatures < 2 * seconds, (n, c)
    assert estimate_cost(plbar.Case()).signatures < 5


# 4. sweep-loads: a compact positions table, a warning above a size, bad input before the solve --------------------

def test_sweep_positions_are_npz_and_csv_behind_a_switch(tmp_path, capsys):
    out = tmp_path / "s"
    assert _run(capsys, ["sweep-loads", "-N", "4", "--per-element", "3", "--out", out, *FAST])[0] == 0
    z = np.load(out / "xi_positions.npz")
    assert z["xi"].shape == (z["T"].size, 12) and not (out / "xi_positions.csv").exists()
    s = json.loads((out / "summary.json").read_text())
    assert s["plbar_version"] == plbar.__version__
    assert _run(capsys, ["sweep-loads", "-N", "4", "--per-element", "3", "--positions-csv", "--out", out,
                         *FAST])[0] == 0
    rows = (out / "xi_positions.csv").read_text().splitlines()
    assert rows[0] == "branch,point,T,s,xi,dPL" and len(rows) - 1 == z["xi"].size


def test_sweep_warns_above_a_size(tmp_path, capsys, monkeypatch):
    import plbar.studies.loads.write as loads

    monkeypatch.setattr(loads, "WARN_BYTES", 1000.0)
    code, _, err = _run(capsys, ["sweep-loads", "-N", "4", "--out", tmp_path / "s", *FAST])
    assert code == 0 and "plbar: warning: the positions table holds" in err and "--per-element" in err


@pytest.mark.parametrize("argv, word", [(["--model", "fe", "-N", "10", "--per-element", "0"], "per_element = 0"),
                                        (["--positions", "7.5"], "outside the bar (0, 5]")])
def test_sweep_bad_positions_refused_before_the_solve(tmp_path, capsys, monkeypatch, argv, word):
    import plbar.app as app

    monkeypatch.setattr(app, "solve", lambda *a, **k: pytest.fail("solved before checking the positions"))
    _refused(capsys, ["sweep-loads", *argv, "--out", tmp_path / "s", "-q"], word)
    assert not (tmp_path / "s").exists()


# 5. refine: extended with new N, a failed study leaves nothing, rates with their meshes --------------------------

REFINE = ["refine", "--grid", "30", "30", "--executor", "serial", "-q", "--no-plot"]


def test_refine_is_extended_with_new_N_reusing_finished_meshes(tmp_path, capsys):
    out = tmp_path / "r"
    assert _run(capsys, REFINE + ["-N", "3", "4", "5", "--out", out])[0] == 0
    levels = {p: p.read_text() for p in (out / "levels").glob("*/N*.json")}
    stamps = {p: p.stat().st_mtime_ns for p in levels}
    assert len(levels) == 3
    assert _run(capsys, REFINE + ["-N", "3", "4", "5", "6", "--out", out])[0] == 0
    assert all(p.stat().st_mtime_ns == stamps[p] and p.read_text() == levels[p] for p in levels)
    assert len(list((out / "levels").glob("*/N*.json"))) == 4
    assert [int(x.split(",")[2]) for x in (out / "refine.csv").read_text().splitlines()[1:]] == [3, 4, 5, 6]


def test_a_failed_refine_leaves_nothing_that_blocks_the_rerun(tmp_path, capsys, monkeypatch):
    import plbar.studies.refine.study as refinement

    def broken(*a, **k):
        raise InputError("the seed failed")

    monkeypatch.setattr(refinement, "seed_levels", broken)
    out = tmp_path / "r"
    _refused(capsys, REFINE + ["-N", "3", "4", "--out", out], "the seed failed")
    assert not out.exists()
    monkeypatch.undo()
    assert _run(capsys, REFINE + ["-N", "3", "4", "--window", "0.1", "--out", out])[0] == 0


def test_rates_say_how_many_meshes_and_are_not_stated_from_three(tmp_path, capsys):
    base = ["refine", "--grid", "30", "30", "--executor", "serial", "--no-plot", "-N", "3", "4", "5"]
    code, text, _ = _run(capsys, base + ["--out", tmp_path / "a"])
    rate_lines = [x for x in text.splitlines() if x.startswith("    T0_I_L")]
    assert code == 0 and "no rate stated" in rate_lines[0] and "3 meshes" in rate_lines[0]
    assert "--rates-always" in rate_lines[0] and "->" not in rate_lines[0]
    code, text, _ = _run(capsys, base + ["--out", tmp_path / "a", "--rates-always"])
    line = [x for x in text.splitlines() if x.startswith("    T0_I_L")][0]
    assert "-> 2: rate" in line and "(3 meshes" in line


def test_no_rate_for_values_that_wander():
    """The issue's T_mid_T0I (N = 8..64): differences that change sign state no limit and no rate."""
    from plbar.studies.refine.convergence import caution, converge

    n = np.array([8, 16, 32, 64])
    c = converge("T_mid_T0I", 1.0 / n, [1.517, 1.560, 1.529, 1.507], n=n)
    assert c.meshes == 4 and "change sign" in c.caution and not c.stated
    assert caution(1.0 / n, 2.0 + 1.0 / n ** 2) == ""
    assert "3 meshes" in caution(1.0 / n[:3], 2.0 + 1.0 / n[:3] ** 2)


# 6. no test depends on timing under load; bad input before any work or folder -------------------------------------

@pytest.mark.parametrize("cmd, opts, word", [
    ("export", ["--branch", "99"], "branch = 99"), ("export", ["--index", "999"], "index = 999"),
    ("export", ["--steps", "2"], "--steps 2"), ("render", ["--field", "bogus"], "--field bogus"),
    ("render", ["--snapshots", "0"], "--snapshots 0"), ("render", ["--branch", "99"], "branch = 99")])
def test_bad_export_and_render_options_create_nothing(tmp_path, capsys, cmd, opts, word):
    pytest.importorskip("pyvista")
    R = tmp_path / "R"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", R, *FAST])[0] == 0
    _refused(capsys, [cmd, "--from", R, "--out", tmp_path / "d", *opts], word)
    assert not (tmp_path / "d").exists()


# 10. the TOML case format ------------------------------------------------------------------------------------------

def test_docs_document_every_case_file_key():
    from plbar.app.casefile import HELP, SCHEMA, schema_table

    assert {k: set(v) for k, v in SCHEMA.items()} == {k: set(v) for k, v in HELP.items()}
    text = (ROOT / "docs" / "casefile.md").read_text()         # the README links to it
    assert schema_table() in text
    for sec, keys in SCHEMA.items():
        for key in keys:
            if key not in ("bar", "load", "search", "output"):
                assert f"`{key}`" in schema_table(), (sec, key)


def test_a_case_file_without_load_gets_the_default_load():
    from plbar.app import loads_case

    assert loads_case('[bar]\nmodel = "chain"\n')[0].load_nodes == ((1, 1.0),)
    assert loads_case('[bar]\nmodel = "fe"\nn = 4\n')[0].load_points == ((0.5, 1.0),)


def test_case_file_types_are_checked_before_what_is_missing():
    from plbar.app import loads_case
    from plbar.errors import CaseFileError

    with pytest.raises(CaseFileError, match=r"\[search\] grid = \"x\" must be two integers"):
        loads_case('[search]\ngrid = "x"\n')


# 11. the jump law, 13. Delta_PL = S v_c^2 / 2 ------------------------------------------------------------------------

def test_docs_state_the_jump_law_with_two_over_pi():
    text = " ".join((ROOT / "docs" / "refinement.md").read_text().split())
    assert r"\frac{2}{\pi} \rho A c \, v_c^2 \ln N" in text and r"\frac{4}{\pi} \rho A c \, v_c^2 \ln N" not in text
    assert r"\lesssim \frac{\pi S}{4 \rho A c \, T \ln(N/N_0)}" in text and r"\frac{\pi S}{8" not in text


def test_impact_loss_is_exact_near_grazing(fe_p2_coarse):
    """Delta_PL is S v_c^2 / 2 itself (every digit), not a difference of kinetic energies."""
    res = fe_p2_coarse
    S = res.paths.prob.system.impact_mass
    for b in res.branches:
        vc = b.orbits.contact_velocity(b.orbits.T2[:, None])[:, 0]
        np.testing.assert_allclose(b.dPL, 0.5 * S * vc ** 2, rtol=1e-14, atol=0)


def test_truncated_impact_loss_keeps_the_projection_loss():
    from plbar.response import impact_loss, kinetic_energy_loss

    res = plbar.solve(plbar.Case(signatures="paper", model="fe", n=12, modes=4, grid=(40, 40)))
    orb = res.branches[0].orbits
    S = res.paths.prob.system.impact_mass
    vc = orb.contact_velocity(orb.T2[:, None])[:, 0]
    np.testing.assert_array_equal(impact_loss(orb), kinetic_energy_loss(orb))
    assert np.all(impact_loss(orb) >= 0.5 * S * vc ** 2 * (1 - 1e-12))
    assert np.any(impact_loss(orb) > 1.01 * 0.5 * S * vc ** 2)


# smaller ------------------------------------------------------------------------------------------------------------

def test_refine_help_lists_only_what_refine_accepts(capsys):
    assert main(["refine", "--help"]) == 0
    text = capsys.readouterr().out
    for opt in ("--modes", "--mesh-file", "--T1", "--T2", "--method"):
        assert opt not in text, opt
    assert "--rates-always" in text and "--grading" in text


def test_export_index_minus_one_is_documented(capsys):
    assert main(["export", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "-1" in text and "last" in text
    assert "--index -1" in (ROOT / "README.md").read_text()


def test_summary_has_the_plbar_version(tmp_path, capsys):
    assert _run(capsys, ["run", *PAPER, "-N", "3", "--out", tmp_path, *FAST])[0] == 0
    assert json.loads((tmp_path / "summary.json").read_text())["plbar_version"] == plbar.__version__


def test_one_point_is_singular():
    from plbar.cli.run import _line

    b = {"branch": 3, "points": 1, "T_range": [1.0, 1.0], "xi_range": [0.1, 0.1], "stable_points": 0}
    assert "1 point," in _line(b) and "1 points" not in _line(b)
