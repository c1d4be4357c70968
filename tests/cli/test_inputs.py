"""What every command accepts and refuses: options that do not apply to the model (one rule, in Case), case files,
refused inputs that leave no folder, costly jobs, a missing optional package, --help and one vocabulary.

From the newcomer reports (the first hour, issues 22, 30 and 44). Where a test failed on the code before the fix it
covers, its docstring says so (or says what happened before).
"""

import json

import pytest

import plbar
from plbar.cli import main
from plbar.errors import InputError

from _helpers import CASES, FAST, MESH, PAPER, ROOT, _refused, _run


# which options apply to which model: one rule, checked in Case ------------------------------------------------------

@pytest.mark.parametrize("argv, words", [
    (["--mesh-file", MESH], ["mesh_file", "model = 'chain'", "--model fe"]),
    (["--model", "fe", "--mesh-file", MESH, "-N", "16"], ["n = 16", "mesh_file", "drop n (-N)"]),
    (["--grading", "3"], ["grading = 3.0", "model = 'chain'"]),
    (["--model", "fe", "--mesh-file", MESH, "--grading", "3"], ["grading = 3.0", "fixes the mesh"]),
    (["--end-mass-absolute"], ["end_mass_absolute", "--end-mass M"]),
    (["--model", "fe", "--end-mass-absolute"], ["end_mass_absolute", "--end-mass M"]),
])
def test_options_that_do_not_apply_are_refused(tmp_path, capsys, argv, words):
    """Failed on the code before the fix it covers (issue 22)."""
    _refused(capsys, ["run", *argv, "--out", tmp_path / "o", *FAST], *words)
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("kw", [dict(mesh_file=str(MESH)), dict(model="fe", mesh_file=str(MESH), n=16),
                                dict(grading=3.0), dict(model="fe", mesh_file=str(MESH), grading=2.0),
                                dict(end_mass_absolute=True), dict(EA=2.0), dict(model="chain", length=2.5),
                                dict(model="fe", m=2.0), dict(model="fe", mesh_file=str(MESH), length=2.0)])
def test_case_is_the_one_validator(kw):
    """Failed on the code before the fix it covers (issue 22)."""
    with pytest.raises(InputError) as exc:
        plbar.Case(**kw)
    assert "\n" not in str(exc.value) and ("does not apply" in str(exc.value) or "mesh" in str(exc.value)
                                           or "end mass" in str(exc.value))


def test_default_fe_load_is_a_fixed_position():
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    for n in (4, 8, 16):
        case = plbar.Case(model="fe", n=n)
        assert case.load_points == ((0.5, 1.0),) and not case.load_nodes


def test_load_on_the_contact_dof_is_refused(tmp_path, capsys):
    """Failed on the code before the fix it covers (issue 44)."""
    code, _, err = _run(capsys, ["run", "--load-node", "5", "--out", tmp_path / "r", "--no-plot"])
    assert code == 2 and "--load-node 5 is the contact DOF" in err and "1..4" in err and err.count("\n") == 1
    code, _, err = _run(capsys, ["survey", "--model", "fe", "--element", "P2", "-N", "2", "--load-node", "4",
                                 "--T-list", "3", "--out", tmp_path / "s"])
    assert code == 2 and "--load-node 4 is the contact DOF" in err and "1..3" in err


# case files: options given with one are refused, every key documented, types checked first --------------------------

def test_option_conflicting_with_case_file_is_exit_2(tmp_path, capsys):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    code, out, err = _run(capsys, ["run", CASES / "fe_p2_consistent.toml", "-N", "6", "--out", tmp_path / "m"])
    assert code == 2 and "-N/--elements conflicts with the case file" in err and err.count("\n") == 1
    assert not (tmp_path / "m" / "paths.csv").exists()


def test_docs_document_every_case_file_key():
    """Failed on the code before the fix it covers (issue 22)."""
    from plbar.app.casefile import HELP, SCHEMA, schema_table

    assert {k: set(v) for k, v in SCHEMA.items()} == {k: set(v) for k, v in HELP.items()}
    text = (ROOT / "docs" / "casefile.md").read_text()         # the README links to it
    assert schema_table() in text
    for sec, keys in SCHEMA.items():
        for key in keys:
            if key not in ("bar", "load", "search", "output"):
                assert f"`{key}`" in schema_table(), (sec, key)


def test_a_case_file_without_load_gets_the_default_load():
    """Failed on the code before the fix it covers (issue 22)."""
    from plbar.app import loads_case

    assert loads_case('[bar]\nmodel = "chain"\n')[0].load_nodes == ((1, 1.0),)
    assert loads_case('[bar]\nmodel = "fe"\nn = 4\n')[0].load_points == ((0.5, 1.0),)


def test_case_file_types_are_checked_before_what_is_missing():
    """Failed on the code before the fix it covers (issue 22)."""
    from plbar.app import loads_case
    from plbar.errors import CaseFileError

    with pytest.raises(CaseFileError, match=r"\[search\] grid = \"x\" must be two integers"):
        loads_case('[search]\ngrid = "x"\n')


# a refused input leaves no folder (issue 30) ------------------------------------------------------------------------

@pytest.mark.parametrize("bad", [["--periods", "1"], ["--record", "2000", "--periods", "100"],
                                 ["--T-list", "-1", "8"], ["--positions", "7"]])
def test_a_refused_survey_leaves_no_folder(tmp_path, capsys, bad):
    out = tmp_path / "a" / "b"
    assert main(["survey", "--num", "3", "--out", str(out), "-q", *bad]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not (tmp_path / "a").exists()


REFUSED = {
    "run": [["--T1", "-1", "2"], ["-N", "0"], ["--grid", "1", "1"], ["--load-node", "9"], ["--modes", "0"],
            ["--model", "fe", "-N", "2000"]],
    "refine": [["--workers", "0"], ["--executor", "dask"], ["-N", "0", "4"], ["--window", "-1"], ["--family", "foo"]],
    "sweep-loads": [["--positions", "99"], ["-N", "0"], ["--per-element", "0"], ["--T1", "5", "1"],
                    ["--model", "fe", "-N", "2000"]],
    "export": [["--from", "{run}", "--branch", "999"], ["--from", "{run}", "--steps", "2"],
               ["--from", "{run}", "--periods", "5"], ["--case", "{case}", "--from", "{new}", "--branch", "999"],
               ["--case", "{case}", "--from", "{new}", "--index", "99999"]],
    "render": [["--from", "{run}", "--field", "foo"], ["--from", "{run}", "--snapshots", "0"],
               ["--case", "{case}", "--from", "{new}", "--branch", "999"]],
}


@pytest.mark.parametrize("cmd, bad", [(c, b) for c, bs in REFUSED.items() for b in bs],
                         ids=[f"{c}{' '.join(b)}" for c, bs in REFUSED.items() for b in bs])
def test_a_refused_command_leaves_no_folder(tmp_path, capsys, monkeypatch, cheap_run, cmd, bad):
    """Every command that writes a folder validates before it makes one: a refused input (exit 2, one line) leaves
    neither its --out nor, for export/render --case, the run folder (before: export/render --case solved and
    wrote the run, then refused the --branch or --index; run made its folder before its cost was checked)."""
    import sys

    if cmd in ("export", "render"):
        pytest.importorskip("pyvista")
    monkeypatch.setitem(sys.modules, "dask.distributed", None)         # "--executor dask" without dask installed
    args = [b.format(run=cheap_run / "run", case=cheap_run / "c.toml", new=tmp_path / "a" / "run") for b in bad]
    plot = ["--no-plot"] if cmd in ("run", "refine", "sweep-loads") else []
    assert main([cmd, *args, *plot, "--out", str(tmp_path / "a" / "b"), "-q"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not (tmp_path / "a").exists()


def test_small_inputs_say_what_they_do(tmp_path, capsys):
    """survey --num 1 is refused with what to give (before: only T = 6, a clipped figure); --modes beyond the DOFs is
    refused (before: accepted and recorded as 1000); the FE survey's default periods end where run's search does
    (before: up to 2.25 T0_I, half the figure without exact branches); sweep-loads says "largest xi_eq", not "worst"."""
    import plbar
    from plbar.app.signatures import search_window
    from plbar.paths.branches import default_domain
    from plbar.studies.survey import default_periods

    assert main(["survey", "--num", "1", "--out", str(tmp_path / "s"), "-q"]) == 2
    assert "--T-list" in capsys.readouterr().err and not (tmp_path / "s").exists()
    assert main(["run", "--modes", "1000", "--no-plot", "--out", str(tmp_path / "m")]) == 2
    assert "at most 5" in capsys.readouterr().err and not (tmp_path / "m").exists()
    case = plbar.Case(model="fe", n=8)
    prob = case.problem()
    assert default_periods(case, 5)[-1] == pytest.approx(search_window(prob, default_domain(prob))[1])
    assert main(["sweep-loads", "-N", "4", "--load-at", "1.5", "--grid", "40", "40", "--positions", "1", "2",
                 "--no-plot", "--out", str(tmp_path / "w")]) == 0
    out = capsys.readouterr().out
    assert "largest xi_eq of any load" in out and "worst" not in out.replace("worst_load", "")


# a costly job: refused before anything is made, started with --yes (issue 30) ---------------------------------------

def _stop(*a, **k):
    raise KeyboardInterrupt                                         # the user's Ctrl-C, right at the start


@pytest.mark.parametrize("args, says", [
    (["run", "--model", "fe", "-N", "2000", "--no-plot"], ["days", "12.3 GB", "'plbar refine'", "--yes to start"]),
    (["sweep-loads", "--model", "fe", "-N", "2000", "--no-plot"], ["days", "GB", "--yes to start"]),
    (["survey", "--num", "100000", "--periods", "20000", "--no-plot"],
     ["100,000 motions x 20,000 forcing periods", "hours", "--num", "--yes to start"]),
    (["run", "--model", "fe", "-N", "99999", "--no-plot", "--yes"], ["240.0 GB", "memory", "not started"])],
    ids=["run", "sweep-loads", "survey", "beyond-memory"])
def test_a_costly_job_is_refused_before_anything_is_made(tmp_path, capsys, args, says):
    """Above an hour or half the memory: exit 2, one line with the estimate, what to do instead and --yes (before:
    "about 4 days and 12.3 GB" and it started; a survey of 100,000 periods started without a word; -N 99999 died
    with a MemoryError, a 74.5 GiB dense eigenproblem); larger than the memory: refused even with --yes."""
    assert main([*args, "--out", str(tmp_path / "big")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and all(s in err for s in says), err
    assert not (tmp_path / "big").exists()


def test_yes_starts_a_costly_job_and_the_default_jobs_start_without_it(tmp_path, capsys, monkeypatch):
    import plbar.cli.run as cli_run
    import plbar.studies.survey as survey

    monkeypatch.setattr(cli_run, "solve", _stop)
    monkeypatch.setattr(survey, "run_survey", _stop)
    assert main(["run", "--model", "fe", "-N", "2000", "--no-plot", "--yes", "--out", str(tmp_path / "a")]) == 130
    assert "note: this solve (2000 DOFs" in capsys.readouterr().err
    for args in (["run", "--no-plot"], ["survey", "--no-plot"]):
        assert main([*args, "--out", str(tmp_path / "b")]) == 130
        err = capsys.readouterr().err
        assert "error" not in err and "note" not in err and err.startswith("plbar: interrupted"), err
    assert main(["survey", "--num", "100000", "--no-plot", "--out", str(tmp_path / "c")]) == 130   # a note, then it
    err = capsys.readouterr().err                                                               # starts (14 min)
    assert "note: this survey simulates 100,000 motions x 1,000 forcing periods" in err and "error" not in err, err


# a missing optional package names the extra -------------------------------------------------------------------------

def test_missing_matplotlib_is_said_once(tmp_path, capsys, monkeypatch):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "matplotlib" else real(name, *a))
    code, _, err = _run(capsys, ["run", *PAPER, "-N", "3", "--grid", "30", "30", "--out", tmp_path / "o"])
    assert code == 0 and err.count('pip install "plbar[plot]"') == 1
    code, _, err = _run(capsys, ["figures", "--out", tmp_path / "f"])
    assert code == 2 and 'pip install "plbar[plot]"' in err and not (tmp_path / "f").exists()


# one vocabulary: --quiet, --json and --out everywhere, the same names for the same things ---------------------------

@pytest.mark.parametrize("cmd", ["run", "mesh", "export", "render", "sweep-loads", "refine", "figures"])
def test_every_command_has_quiet_json_out(capsys, cmd):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    assert main([cmd, "--help"]) == 0
    text = capsys.readouterr().out
    for opt in ("--quiet", "--json", "--out"):
        assert opt in text, (cmd, opt)


def test_same_names_for_the_same_things(tmp_path, capsys):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    code, text, _ = _run(capsys, ["sweep-loads", "-N", "4", "--load-at", "1.5", "--grid", "40", "40",
                                  "--positions", "1.0", "2.0", "--out", tmp_path / "s", "--json", "--no-plot"])
    assert code == 0 and json.loads(text)["summary"]["positions"] == 2
    assert _run(capsys, ["refine", "-N", "3", "--grid", "30", "30", "--executor", "serial", "--out",
                         tmp_path / "r", "-q"])[0] == 0
    assert _run(capsys, ["run", *PAPER, "-N", "3", "--grid", "30", "30", "--out", tmp_path / "o", "-q",
                         "--no-plot"])[0] == 0
    if __import__("importlib").util.find_spec("pyvista"):
        code, text, _ = _run(capsys, ["export", "--from", tmp_path / "o", "--out", tmp_path / "v", "--steps", "8",
                                      "--json"])
        assert code == 0 and (tmp_path / "v" / "response.pvd").is_file()
