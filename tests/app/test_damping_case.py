"""Inherent damping as a case input (issue 21): Case, TOML, command line, outputs."""

import json

import numpy as np
import pytest

import plbar
from plbar.app import dump_case, loads_case, read_paths
from plbar.cli import main
from plbar.errors import CaseFileError, InputError

PAPER = ["--signatures", "paper"]      # the paper's class only: these runs are not about the other signatures


def test_rayleigh_from_ratio():
    a, b = plbar.rayleigh_from_ratio(0.02, 8.0, 12.0)
    for T in (8.0, 12.0):
        w = 2 * np.pi / T
        assert a / (2 * w) + b * w / 2 == pytest.approx(0.02, rel=1e-14)
    w = 2 * np.pi / 10.0                       # between the two periods the ratio is a little lower
    assert a / (2 * w) + b * w / 2 < 0.02
    assert plbar.rayleigh_from_ratio(0.0, 8, 12) == (0.0, 0.0)
    for bad, match in (((0.02, 8, 8), "two different periods"), ((-0.1, 8, 12), "ratio"), ((1.5, 8, 12), "ratio"),
                       ((0.02, 0, 12), "period T_a"), ((0.02, 8, float("inf")), "period T_b"),
                       (("x", 8, 12), "number")):
        with pytest.raises(InputError, match=match):
            plbar.rayleigh_from_ratio(*bad)


def test_case_field_validation_and_problem():
    c = plbar.Case(rayleigh=(0.01, 0.02))
    assert c.rayleigh == (0.01, 0.02)
    s = c.problem().system
    assert s.damped and (s.alpha, s.beta) == (0.01, 0.02)
    assert np.allclose(s.zeta1, 0.01 / (2 * s.w1) + 0.02 * s.w1 / 2, rtol=1e-15)
    assert np.allclose(s.zeta2, 0.01 / (2 * s.w2) + 0.02 * s.w2 / 2, rtol=1e-15)
    assert np.allclose(s.C, 0.01 * s.M + 0.02 * s.K)
    assert plbar.Case(rayleigh=(0, 0)).rayleigh is None and plbar.Case().rayleigh is None
    assert "rayleigh" not in plbar.Case().to_dict() and c.to_dict()["rayleigh"] == [0.01, 0.02]
    for bad in ((-0.1, 0.0), (0.1,), "0.1 0.2", (0.1, float("nan")), (0.1, 0.2, 0.3)):
        with pytest.raises(InputError, match="rayleigh"):
            plbar.Case(rayleigh=bad)


def test_toml_rayleigh_and_damping_ratio():
    base = '[bar]\nmodel = "chain"\n{extra}\n[[load]]\nnode = 1\n'
    c, _ = loads_case(base.format(extra="rayleigh = [0.01, 0.02]"))
    assert c.rayleigh == (0.01, 0.02)
    c2, _ = loads_case(dump_case(c))
    assert c2 == c
    c3, _ = loads_case(base.format(extra="damping_ratio = 0.02\ndamping_at = [8.0, 12.0]"))
    assert c3.rayleigh == pytest.approx(plbar.rayleigh_from_ratio(0.02, 8.0, 12.0), rel=1e-15)
    for extra, match in (("damping_ratio = 0.02", "damping_at"), ("rayleigh = [0.1, 0.1]\ndamping_ratio = 0.02\n"
                                                                   "damping_at = [8.0, 12.0]", "not both"),
                         ("rayleigh = [-1.0, 0.0]", "rayleigh"), ("damping_ratio = 0.02\ndamping_at = [8.0, 8.0]",
                                                                  "two different periods")):
        with pytest.raises(CaseFileError, match=match):
            loads_case(base.format(extra=extra))


def test_cli_run_with_damping_ratio(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["run", *PAPER, "--damping-ratio", "0.02", "--at", "8", "12", "--grid", "60", "60", "--out", str(out),
                 "--no-plot"]) == 0
    assert "Rayleigh damping alpha" in capsys.readouterr().out
    cols = read_paths(out / "paths.csv")
    a, b = plbar.rayleigh_from_ratio(0.02, 8.0, 12.0)
    W = 2 * np.pi / cols["T"]
    assert np.allclose(cols["zeta_rayleigh"], a / (2 * W) + b * W / 2, rtol=1e-14)
    assert np.allclose(cols["xi_total"], cols["zeta_rayleigh"] + cols["xi"], rtol=1e-14)
    assert np.all(cols["viscous_loss"] > 0)
    s = json.loads((out / "summary.json").read_text())
    assert s["rayleigh"] == pytest.approx([a, b]) and s["case"]["rayleigh"] == pytest.approx([a, b])
    assert all("viscous_loss_range" in br and "xi_total_range" in br for br in s["branches"])
    # the same case by --rayleigh: same results folder accepted without --overwrite
    assert main(["run", *PAPER, "--rayleigh", repr(a), repr(b), "--grid", "60", "60", "--out", str(out), "--no-plot",
                 "--quiet"]) == 0


@pytest.mark.parametrize("argv,match", [
    (["--rayleigh", "0.1", "0.1", "--damping-ratio", "0.02", "--at", "8", "12"], "not both"),
    (["--damping-ratio", "0.02"], "needs --at"),
    (["--at", "8", "12"], "needs --at"),
    (["--rayleigh", "-1", "0"], "rayleigh"),
])
def test_cli_damping_errors(tmp_path, capsys, argv, match):
    assert main(["run", *argv, "--out", str(tmp_path / "x"), "--no-plot"]) == 2
    assert match in capsys.readouterr().err


def test_undamped_outputs_have_zero_damping_columns(default_result, tmp_path):
    plbar.write_results(default_result, tmp_path)
    cols = read_paths(tmp_path / "paths.csv")
    assert np.all(cols["viscous_loss"] == 0) and np.all(cols["zeta_rayleigh"] == 0)
    assert np.array_equal(cols["xi_total"], cols["xi"])
    assert json.loads((tmp_path / "summary.json").read_text())["rayleigh"] is None


def test_sweep_loads_takes_damping_at(tmp_path):
    """sweep-loads keeps --at for its positions: the damping periods are --damping-at there."""
    out = tmp_path / "sw"
    assert main(["sweep-loads", "--damping-ratio", "0.02", "--damping-at", "8", "12", "--grid", "50", "50",
                 "--per-element", "4", "--no-pairs", "--no-plot", "--out", str(out), "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert "phase" in s["note"] and s["case"]["rayleigh"] == pytest.approx(list(plbar.rayleigh_from_ratio(0.02, 8, 12)))


def test_batched_simulator_and_chain_take_damping():
    """No silent undamped run of a damped case (issue 21): the survey's simulator and the chain carry the
    damping (their flows take zeta, the margin the damper's share of the reaction)."""
    from plbar.motion import padded

    prob = plbar.Case(rayleigh=(0.01, 0.02)).problem()
    pad = padded(prob)
    assert pad.zeta is not None and np.allclose(pad.zeta[1], prob.system.zeta2)
    assert np.allclose(pad.cv[0, :-1], -prob.system.r_v)
    assert padded(plbar.Case().problem()).zeta is None
