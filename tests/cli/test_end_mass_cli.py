"""--end-mass and --end-mass-absolute: shared by every command, refused beside a case file."""

import json

import pytest

import plbar
from plbar.cli.main import main

PAPER = ["--signatures", "paper"]      # the paper's class only: these runs are not about the other signatures


def test_run_end_mass_in_summary(tmp_path):
    out = tmp_path / "em"
    assert main(["run", *PAPER, "--model", "fe", "-N", "6", "--grid", "40", "40", "--end-mass", "0.5",
                 "--out", str(out), "--no-plot", "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["case"]["end_mass"] == 0.5 and s["case"]["end_mass_absolute"] is False
    with_mass = plbar.Case(model="fe", n=6, end_mass=0.5).problem().system.T0[1]
    bare = plbar.Case(model="fe", n=6).problem().system.T0[1]
    assert s["T0_II"] == pytest.approx(with_mass, rel=1e-12)
    assert s["T0_II"] > 1.2 * bare                                  # the mass is really there


def test_run_end_mass_absolute(tmp_path):
    out = tmp_path / "abs"
    assert main(["run", *PAPER, "-N", "4", "--grid", "30", "30", "--end-mass", "0.5", "--end-mass-absolute",
                 "--out", str(out), "--no-plot", "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["case"]["end_mass"] == 0.5 and s["case"]["end_mass_absolute"] is True
    expect = plbar.Case(n=4, end_mass=0.5, end_mass_absolute=True).problem().system.T0[1]
    assert s["T0_II"] == pytest.approx(expect, rel=1e-12)


@pytest.mark.parametrize("opt", [["--end-mass", "0.5"], ["--end-mass-absolute"]])
def test_end_mass_with_case_file_exit_2(tmp_path, capsys, opt):
    f = tmp_path / "c.toml"
    f.write_text('[bar]\nmodel = "chain"\n\n[[load]]\nnode = 1\n')
    assert main(["run", str(f), *opt, "--out", str(tmp_path / "o"), "--no-plot"]) == 2
    err = capsys.readouterr().err.strip()
    assert opt[0] in err and "case file" in err and "\n" not in err
    assert not (tmp_path / "o").exists()


def test_negative_end_mass_exit_2(tmp_path, capsys):
    assert main(["run", *PAPER, "--end-mass", "-1", "--out", str(tmp_path / "o"), "--no-plot"]) == 2
    err = capsys.readouterr().err.strip()
    assert "end_mass = -1.0" in err and ">= 0" in err and "\n" not in err
