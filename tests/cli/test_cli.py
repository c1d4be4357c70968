"""The command line: output format of `plbar run`, case files, exit codes, --json/--quiet."""

import json

import numpy as np
import pytest

from plbar.cli import main
from plbar.app import CSV_HEADER

PAPER = ["--signatures", "paper"]      # the paper's class only: these runs are not about the other signatures


def _csv(path):
    lines = path.read_text().splitlines()
    return lines[0], [line.split(",") for line in lines[1:]]


def test_run_default_writes_exact_header_and_summary(tmp_path, capsys):
    assert main(["run", "--out", str(tmp_path), "--no-plot"]) == 0
    out = capsys.readouterr().out
    assert "branch" in out and "T0_I = 10.1664" in out and str(tmp_path) in out
    header, rows = _csv(tmp_path / "paths.csv")
    assert header == ("branch,T1,T2,phi,T,dPL,xi,grazing,stable,max_abs_multiplier,max_abs_xc,omega,xi_w,"
                      "viscous_loss,zeta_rayleigh,xi_total,m,k,signature,loss_per_T,durations")
    assert header.split(",")[:8] == "branch,T1,T2,phi,T,dPL,xi,grazing".split(",")
    assert header.split(",") == CSV_HEADER
    s = json.loads((tmp_path / "summary.json").read_text())
    paper = [r for r in rows if int(r[0]) < s["n_paper_branches"]]       # the paper's class first, then the others
    assert {r[18] for r in paper} == {"1P"} and {r[16] for r in paper} == {"1"}
    assert all(r[18] != "1P" for r in rows if int(r[0]) >= s["n_paper_branches"])
    assert len({r[18] for r in rows} - {"1P"}) >= 8 and {r[16] for r in rows} <= {"1", "2", "3", "4"}
    vals = np.array([[float(v) for v in r[:18] + r[19:20]] for r in rows])
    assert np.all(np.isfinite(vals))
    assert np.all((vals[:, 3] >= 0) & (vals[:, 3] < 2 * np.pi))
    np.testing.assert_allclose(vals[:, 1] + vals[:, 2], vals[:, 16] * vals[:, 4], rtol=1e-13)   # stuck + free = m T
    # floats with at least 10 significant digits
    digits = [len(r[1].replace(".", "").replace("-", "").split("e")[0].lstrip("0")) for r in paper]
    assert min(digits) >= 10
    for key in ("case", "T0_I", "T0_II", "n_branches", "n_paper_branches", "branches", "run_time"):
        assert key in s
    assert s["T0_I"] == pytest.approx(10.1664, abs=1e-4) and s["n_branches"] == len(s["branches"])
    for b in s["branches"]:
        assert b["T_range"][0] <= b["T_range"][1] and b["xi_range"][0] <= b["xi_range"][1]
        assert "events" in b and "ends" in b
    assert sorted({int(r[0]) for r in rows}) == list(range(s["n_branches"]))
    assert [b["signature"] for b in s["branches"]][:s["n_paper_branches"]] == ["1P"] * s["n_paper_branches"]


def test_run_json_and_quiet(tmp_path, capsys):
    assert main(["run", *PAPER, "--out", str(tmp_path / "a"), "--json", "--no-plot", "--grid", "60", "60"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["summary"]["case"]["grid"] == [60, 60]
    assert main(["run", *PAPER, "--out", str(tmp_path / "b"), "--quiet", "--no-plot", "--grid", "60", "60"]) == 0
    assert capsys.readouterr().out == ""


def test_run_fe_options(tmp_path):
    rc = main(["run", *PAPER, "--model", "fe", "-N", "4", "--element", "P2", "--mass", "consistent",
               "--load-at", "0.37", "--grid", "60", "60", "--out", str(tmp_path), "--quiet", "--no-plot"])
    assert rc == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["case"]["element"] == "P2" and s["case"]["load_points"] == [[0.37, 1.0]]
    assert s["T0_II"] == pytest.approx(4.0, rel=1e-3)       # clamped-free bar, L = EA = rhoA = 1


def test_run_case_file(tmp_path, capsys):
    from pathlib import Path

    f = Path(__file__).parents[2] / "examples" / "cases" / "paper_sec42_node3.toml"
    assert main(["run", str(f), "--out", str(tmp_path), "--no-plot"]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["case"]["load_nodes"] == [[3, 1.0]]


@pytest.mark.parametrize("text, key", [
    ('[bar]\nmodel = "chain"\nn = "5"\n[[load]]\nnode = 1\n', "n"),                      # wrong type
    ('[bar]\nmodel = "chain"\nnn = 5\n[[load]]\nnode = 1\n', "nn"),                      # unknown key
    ('[[load]]\nnode = 1\n', "[bar]"),                                                   # missing section
    ('[bar]\nmodel = "chain"\n[[load]]\nnode = 1\n[search]\ngrid = [1, 1]\n', "grid"),  # bad value
])
def test_malformed_case_file_exit_2_one_line(tmp_path, capsys, text, key):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    assert main(["run", str(f), "--out", str(tmp_path / "o"), "--no-plot"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and key in err and err.startswith("plbar: error:")


def test_bad_cli_input_exit_2(tmp_path, capsys):
    assert main(["run", *PAPER, "--load-at", "7.5", "--out", str(tmp_path), "--no-plot"]) == 2
    err = capsys.readouterr().err.strip()
    assert "7.5" in err and "\n" not in err
    assert main(["run", *PAPER, "--element", "P3"]) == 2
    assert main([]) == 2


def test_refuses_other_case_in_same_folder(tmp_path, capsys):
    assert main(["run", *PAPER, "--out", str(tmp_path), "--quiet", "--no-plot", "--grid", "40", "40"]) == 0
    assert main(["run", *PAPER, "--out", str(tmp_path), "--quiet", "--no-plot", "--grid", "41", "41"]) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert main(["run", *PAPER, "--out", str(tmp_path), "--quiet", "--no-plot", "--grid", "41", "41",
                 "--overwrite"]) == 0


CASES = sorted((__import__("pathlib").Path(__file__).resolve().parents[2] / "examples" / "cases").glob("*.toml"))


#: with the slow tests: cases like one the default run keeps (paper_sec41 is the default case, which
#: test_run_default_writes_exact_header_and_summary runs; chain_N3_node1 stands for the chains, paper_sec42_node2 for
#: the load at another node; tests/app/test_casefile.py solves fe_p2_consistent; the damped case's every signature,
#: 88 s, stands beside tests/periodic/test_hybrid.py's damped responses of every signature)
SLOW_CASES = {"paper_sec41", "chain_N4_node1", "chain_N6_node1", "paper_sec42_node3", "paper_sec42_node4",
              "fe_p2_consistent", "paper_sec41_rayleigh_2pct", "paper_sec42_node2", "paper_sec42_split_075_025"}


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow) if p.stem in SLOW_CASES else p
                                  for p in CASES], ids=[p.stem for p in CASES])
def test_every_example_case_file_runs(tmp_path, path):
    assert main(["run", str(path), "--out", str(tmp_path), "--quiet", "--no-plot"]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["n_branches"] >= 1
    _, rows = _csv(tmp_path / "paths.csv")
    assert rows and np.all(np.isfinite(np.array([[float(v) for v in r[:18] + r[19:20]] for r in rows])))
