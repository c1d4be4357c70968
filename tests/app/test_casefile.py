"""TOML case files: the shipped examples load (and the small ones solve); mistakes give one-line errors."""

from pathlib import Path

import pytest

import plbar
from plbar.app import OutputSettings, dump_case, load_case, loads_case
from plbar.errors import CaseFileError

CASES = sorted((Path(__file__).resolve().parents[2] / "examples" / "cases").glob("*.toml"))
GOOD = """
[bar]
model = "fe"
n = 6
element = "P1"

[[load]]
node = 2

[search]
grid = [40, 40]
"""


def test_examples_exist():
    names = {p.name for p in CASES}
    assert {"paper_sec41.toml", "fe_p2_consistent.toml", "paper_sec42_split_075_025.toml"} <= names
    assert len(CASES) >= 9


@pytest.mark.parametrize("path", CASES, ids=[p.stem for p in CASES])
def test_example_loads_and_round_trips(path):
    case, out = load_case(path)
    assert isinstance(case, plbar.Case) and isinstance(out, OutputSettings)
    assert case.label
    back, out2 = loads_case(dump_case(case, out))
    assert back == case and out2 == out


def test_paper_cases_mean_what_they_say():
    d = {p.stem: load_case(p)[0] for p in CASES}
    assert d["paper_sec41"] == plbar.Case(n=5, label="x")
    assert d["paper_sec41"].load_nodes == ((1, 1.0),)
    split = d["paper_sec42_split_075_025"].problem().q
    assert split[:2].tolist() == pytest.approx([0.75, 0.25]) and not split[2:].any()


@pytest.mark.parametrize("name", ["paper_sec41", "chain_N3_node1", "fe_p2_consistent"])
def test_small_examples_solve(name):
    case, _ = load_case(next(p for p in CASES if p.stem == name))
    # the case file is what is tested: its model and load, with a coarse scan and the paper's class alone (every
    # signature of an FE P2 bar took 95 s here; tests/periodic covers the search of every signature)
    case = plbar.Case(**{**case.to_dict(), "grid": tuple(min(g, 60) for g in case.grid), "label": case.label,
                         "signatures": "paper"})
    res = plbar.solve(case)
    assert res.branches and max(b.xi.max() for b in res.branches) > 0


def test_mesh_file_relative_to_toml(tmp_path):
    from plbar.io import write_nodes

    (tmp_path / "m").mkdir()
    write_nodes(tmp_path / "m" / "bar.msh", [0.0, 0.3, 0.6, 1.0])
    f = tmp_path / "c.toml"
    f.write_text('[bar]\nmodel = "fe"\nmesh_file = "m/bar.msh"\n[[load]]\nat = 0.5\n')
    case, _ = load_case(f)
    assert case.bar().n_elements == 3


def _err(tmp_path, text, name="case.toml"):
    f = tmp_path / name
    f.write_text(text)
    with pytest.raises(CaseFileError) as exc:
        load_case(f)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith(f"{name}: ")
    assert isinstance(exc.value, ValueError)
    return msg


@pytest.mark.parametrize("bad, expect", [
    (GOOD.replace('element = "P1"', 'element = "P3"'), '[bar] element = "P3" is not allowed; choose P1 or P2'),
    (GOOD.replace("n = 6", 'n = "6"'), '[bar] n = "6" has the wrong type (string); expected an integer'),
    (GOOD.replace("n = 6", "n = 6.0"), "[bar] n = 6.0 has the wrong type (float)"),
    (GOOD.replace('element = "P1"', 'elemnt = "P1"'), '[bar] unknown key "elemnt"; did you mean "element"?'),
    (GOOD.replace("grid = [40, 40]", "grid = [40]"), "[search] grid = [40] must be two integers"),
    (GOOD.replace("grid = [40, 40]", "grid = [40, 2]"), "grid = (40, 2) must be two integers >= 3"),
    (GOOD.replace("grid = [40, 40]", "grd = [40, 40]"), '[search] unknown key "grd"; did you mean "grid"?'),
    (GOOD.replace("[bar]", "[bra]"), 'unknown key "bra"; did you mean "bar"?'),
    (GOOD.replace('model = "fe"', 'model = "chian"'),
     '[bar] model = "chian" is not allowed; choose chain, fe, continuum, beam or matrices'),
    (GOOD.replace('model = "fe"', ""), '[bar] missing required key "model"'),
    (GOOD.replace("[[load]]", "[load]"), "load must be an array of tables"),
    (GOOD.replace("node = 2", "node = 2\nat = 0.5"), "[load #1] give exactly one of node = K"),
    (GOOD.replace("node = 2", "node = 99"), "load node = 99 is out of range"),
    (GOOD.replace("node = 2", "node = 2\namplitude = true"), "[load] amplitude = true has the wrong type (boolean)"),
    (GOOD.replace("n = 6", "n = 6\nm = 2.0"), "m = 2.0 does not apply to model = 'fe'"),
    (GOOD + "[output]\nformat = \"vtk\"\n", '[output] format = "vtk" is not allowed; choose pvd, xdmf or both'),
    (GOOD + "[output]\nvtk = 1\n", "[output] vtk = 1 has the wrong type (integer); expected true or false"),
    (GOOD + "[output]\nperiods = 3\n", "[output] periods = 3 is not allowed; choose 1 or 2"),
    (GOOD.replace("n = 6", 'n = 6\nmesh_file = "nope.msh"'), '[bar] mesh_file = "nope.msh" does not exist'),
    (GOOD.replace("n = 6", "n = 6\nEA = -1.0"), "EA = -1.0 is not allowed; it must be a finite value > 0"),
    (GOOD.replace("n = 6", "n = 1"), "n = 1 is not allowed; it must be an integer >= 2"),
    (GOOD.replace("n = 6", "n = 6\nmodes = 0"), "modes = 0 is not allowed; it must be an integer >= 1"),
    (GOOD.replace("n = 6", "n = 6\nmodes = 2.5"), "[bar] modes = 2.5 has the wrong type (float)"),
    ("[bar\nmodel = 1", "invalid TOML:"),
])
def test_malformed(tmp_path, bad, expect):
    msg = _err(tmp_path, bad)
    assert expect in msg, msg


def test_missing_bar_section(tmp_path):
    assert "missing required section [bar]" in _err(tmp_path, "[[load]]\nnode = 1\n")


def test_output_settings_and_missing_file(tmp_path):
    f = tmp_path / "c.toml"
    f.write_text(GOOD + '[output]\ndir = "o"\nvtk = true\nformat = "both"\nperiods = 2\nbranch = 3\n')
    _, out = load_case(f)
    assert out == OutputSettings(dir="o", vtk=True, format="both", periods=2, branch=3)
    with pytest.raises(CaseFileError, match="nope.toml: cannot read"):
        load_case(tmp_path / "nope.toml")


def test_modes_round_trip_and_truncate(tmp_path):
    f = tmp_path / "c.toml"
    f.write_text(GOOD.replace("n = 6", "n = 6\nmodes = 3"))
    case, out = load_case(f)
    assert case.modes == 3
    back, _ = loads_case(dump_case(case, out))
    assert back == case
    prob = case.problem()
    assert prob.system.w1.size == 3 and prob.system.w2.size == 3
