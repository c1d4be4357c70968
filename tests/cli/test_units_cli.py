"""Units on the command line (issue 44, finding 4): ``--length``, ``--EA``, ``--rhoA``, ``--amplitude`` are the case
file's ``length``, ``EA``, ``rhoA`` and load ``amplitude``; refused where a command or model would ignore them."""

import csv
import json

import numpy as np
import pytest

from plbar.app import load_case
from plbar.cli import main
from plbar.cli.common import case_from_args
from plbar.cli.main import build_parser

#: the 3 m steel column of the issue: EA = 2.7e9 N, rhoA = 216 kg/m (c = 3,536 m/s), a 1 kN load at 1.5 m
COLUMN = ["--model", "fe", "-N", "4", "--length", "3", "--EA", "2.7e9", "--rhoA", "216"]
COLUMN_TOML = """[bar]
model = "fe"
n = 4
length = 3.0
EA = 2.7e9
rhoA = 216.0
[[load]]
at = 1.5
amplitude = 1000.0
[search]
grid = [60, 60]
signatures = "paper"
"""
QUICK = ["--signatures", "paper", "--grid", "60", "60", "--no-plot"]


def _rows(folder):
    with open(folder / "paths.csv") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in ("T1", "T2", "dPL", "xi", "max_abs_xc")}


def test_column_options_are_the_case_file(tmp_path, capsys):
    path = tmp_path / "column.toml"
    path.write_text(COLUMN_TOML)
    flags = [*COLUMN, "--load-at", "1.5", "--amplitude", "1000", "--grid", "60", "60", "--signatures", "paper"]
    case, _ = case_from_args(build_parser().parse_args(["run", *flags]))
    assert case == load_case(path)[0]
    assert main(["run", *flags, "--no-plot", "--json", "--out", str(tmp_path / "cli")]) == 0
    by_cli = json.loads(capsys.readouterr().out)["summary"]
    assert main(["run", str(path), "--no-plot", "--json", "--out", str(tmp_path / "file")]) == 0
    by_file = json.loads(capsys.readouterr().out)["summary"]
    assert by_cli["case"] == by_file["case"] and by_cli["case"]["EA"] == 2.7e9
    assert by_cli["T0_I"] == by_file["T0_I"] and by_cli["n_points"] == by_file["n_points"] > 0
    # the column's own periods, in seconds: T0_I of 4 P1 lumped elements near 2 L / c = 1.70 ms
    assert by_cli["T0_I"] == pytest.approx(2 * 3 / np.sqrt(2.7e9 / 216), rel=0.05)
    a, b = _rows(tmp_path / "cli"), _rows(tmp_path / "file")
    for k in a:
        np.testing.assert_array_equal(a[k], b[k])


def test_amplitude_scales_the_response_not_xi(tmp_path):
    """Zero gap: the problem is linear and homogeneous in the force, so the same (T1, T2) points with the contact
    amplitude times Q, the loss times Q^2 and xi_eq unchanged (an identity, not a regression)."""
    q = 2.5e3
    assert main(["run", *COLUMN, *QUICK, "--quiet", "--out", str(tmp_path / "one")]) == 0
    assert main(["run", *COLUMN, *QUICK, "--quiet", "--amplitude", str(q), "--out", str(tmp_path / "q")]) == 0
    one, big = _rows(tmp_path / "one"), _rows(tmp_path / "q")
    assert one["T1"].size > 20
    np.testing.assert_allclose(big["T1"], one["T1"], rtol=1e-9)
    np.testing.assert_allclose(big["T2"], one["T2"], rtol=1e-9)
    np.testing.assert_allclose(big["max_abs_xc"], q * one["max_abs_xc"], rtol=1e-7)
    np.testing.assert_allclose(big["dPL"], q * q * one["dPL"], rtol=1e-7, atol=1e-12 * q * q * one["dPL"].max())
    np.testing.assert_allclose(big["xi"], one["xi"], rtol=1e-7, atol=1e-12)


def test_amplitude_scales_the_default_and_given_loads():
    parse = build_parser().parse_args
    case, _ = case_from_args(parse(["run", *COLUMN, "--amplitude", "1000"]))
    assert case.load_points == ((1.5, 1000.0),)
    case, _ = case_from_args(parse(["run", "--amplitude", "3", "--load-node", "2", "--load-node", "4"]))
    assert case.load_nodes == ((2, 3.0), (4, 3.0))


@pytest.mark.parametrize("argv, words", [
    (["run", "--model", "chain", "--EA", "2"], ["EA", "--EA", "chain"]),
    (["run", "--model", "chain", "--length", "3"], ["length", "--length", "chain"]),
    (["run", *COLUMN, "--amplitude", "0"], ["--amplitude 0"]),
    (["run", "examples/cases/paper_sec41.toml", "--length", "3"], ["--length", "case file"]),
    (["sweep-loads", *COLUMN, "--amplitude", "2"], ["--amplitude", "sweep-loads"]),
    (["survey", *COLUMN, "--positions", "1.5", "--amplitude", "2"], ["--amplitude", "--positions"]),
])
def test_refused_where_ignored(argv, words, tmp_path, capsys):
    assert main([*argv, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and all(w in err for w in words), err
    assert not (tmp_path / "out").exists()


def test_run_says_its_units_and_window_in_the_users_time_unit(tmp_path, capsys):
    """The column's own periods are milliseconds: the run says the window it searched, in seconds, and how to reach
    an engineer's forcing period (0.2 s: the survey)."""
    assert main(["run", *COLUMN, *QUICK, "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "units: L = 3, c = 3,536;" in out and "docs/cli.md 'Units'" in out
    T = json.loads((tmp_path / "summary.json").read_text())["domain"]
    hi = T["T1"][1] + T["T2"][1]
    assert 2e-3 < hi < 3e-3 and f"T = T1 + T2 in (0, {hi:.4g}] (the bar's own" in out
    assert "--T1 LO HI --T2 LO HI" in out
    assert "plbar survey --model fe -N 4 --length 3 --EA 2.7e+09 --rhoA 216 --T-list T" in out


def test_plot_units_have_the_digits_they_have():
    from plbar.app import Case
    from plbar.visuals.style import unit_note

    assert unit_note(Case(model="fe", n=4, length=3.0, EA=2.7e9, rhoA=216.0).bar()) == "L = 3, c = 3,536"
    assert unit_note(Case(model="fe", n=4).bar()) == "L = c = 1"


def test_refine_table_gives_periods_in_the_cases_time_unit():
    """``plbar refine``: the periods of an FE bar (one length on every mesh) in its time unit, not T/L; the chain's
    L = N changes with N, so its T/L."""
    from plbar.cli.studies import _refine_lines

    nan = float("nan")
    row = dict(series="fe", family="T0_II/2", n=4, status="ok", admissible=10, T_min_L=0.0005, T_max_L=0.0006,
               xi_max=0.01, T_at_max_L=0.00055, impact_mass=0.0, end_mass=0.0, length=3.0)

    class R:
        rows = [row]
        rates = {"fe": {"T0_II/2": {"xi_decay": {}}}}

        def family(self, series, family):
            return self.rows

    text = "\n".join(_refine_lines(R()))
    assert "main stretch T " in text and "T/L" not in text and "[0.0015, 0.0018]" in text and "0.00165" in text
    R.rows = [row, {**row, "n": 5, "length": 5.0, "T_min_L": nan}]
    assert "main stretch T/L" in "\n".join(_refine_lines(R()))


def test_estimates_are_ranges_from_idle_to_busy():
    """Issue 44, finding 7: estimates 3-6x low on a busy machine.  Each is a range whose high end is the measured
    busy factor times the tables' time, and the cost message points at docs/speed.md (README 'Speed' is gone)."""
    from plbar.app import Case, cost_note
    from plbar.app.cost import BUSY, duration_range

    assert duration_range(86.0) == "1-9 minutes"                  # the run: 86 s estimated, 358-565 s taken
    assert 565 <= 86.0 * BUSY and duration_range(67.0, 2.6) == "1-3 minutes"
    assert duration_range(4000.0) == "1-7 hours" and duration_range(0.2) == "under 2 s"
    assert duration_range(5.0) == "5-33 s"
    note = cost_note(Case(model="fe", n=32), threshold=0.0)
    assert "minutes (idle to busy machine)" in note and "docs/speed.md" in note and "README" not in note
    lo, hi = (int(x) for x in note.split("will take ")[1].split(" minutes")[0].split("-"))
    assert hi / lo == pytest.approx(BUSY, rel=0.2)
