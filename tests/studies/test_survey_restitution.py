"""The real motion against the coefficient of restitution (issue 31 item 4): the table, the plastic rows against the
plain survey, the energy budget, the elastic impact, the inputs, the figure."""

import json

import numpy as np
import pytest

import plbar
from plbar.errors import InputError
from plbar.studies.survey import (RESTITUTION_COLUMNS, check_restitutions, default_periods, survey,
                                  survey_restitution, write_restitution)
from plbar.visuals import survey_restitution_plot

T = [9.0, 11.8, 12.4]
E = [0.0, 0.5, 1.0]
PERIODS = 300


@pytest.fixture(scope="module")
def small():
    return survey_restitution(plbar.Case(), T, E, periods=PERIODS)


def test_one_row_per_restitution_and_forcing_period(small):
    t = small.table
    assert set(t) == set(RESTITUTION_COLUMNS) and len(small) == len(E) * len(T)
    assert sorted(zip(t["e"], t["T"])) == [(e, x) for e in E for x in T] == list(zip(t["e"], t["T"]))
    assert np.array_equal(small.restitutions, E) and np.array_equal(small.T, T)
    assert small.grid("xi_eq").shape == (3, 3) and small.grid("kind").shape == (3, 3)
    assert "SurveyRestitution(rows=9" in repr(small) and "e=[0.0, 0.5, 1.0]" in repr(small)


def test_the_plastic_rows_are_the_survey_bit_for_bit(small):
    """e = 0 is the paper's plastic impact: the same tasks as survey(), the same rows, every column."""
    ref = survey(plbar.Case(), T, periods=PERIODS).table
    sel = small.table["e"] == 0.0
    for c in RESTITUTION_COLUMNS[1:]:
        a, b = small.table[c][sel], ref[c]
        if a.dtype == float:
            assert np.array_equal(a, b, equal_nan=True), c
        else:
            assert list(a) == list(b), c


def test_the_energy_budget_closes_at_every_e(small):
    assert np.all(np.abs(small.table["energy_residual"]) <= 1e-12)
    assert small.summary["energy_residual_max"] <= 1e-12


def test_an_elastic_impact_loses_nothing(small):
    t = small.table
    el = t["e"] == 1.0
    for c in ("loss_per_T", "loss_min", "loss_max", "xi_eq", "xi_w"):
        assert np.all(t[c][el] == 0.0), c
    assert np.all(t["impacts_per_T"][el] > 0)                   # it does hit the wall


def test_the_summary_per_e(small):
    s = small.summary
    assert s["restitutions"] == E and s["T"] == T and s["periods"] == PERIODS and s["rows"] == 9
    med = small.quantile("xi_eq", 0.5)
    for e, m in zip(E, med):
        d = s["by_e"][f"{e:g}"]
        assert d["xi_eq"]["median"] == pytest.approx(m, rel=1e-15, abs=0)
        assert d["xi_eq"]["q10"] <= d["xi_eq"]["median"] <= d["xi_eq"]["q90"]
        assert sum(d["kinds"].values()) == len(T)
        assert d["ratio_to_plastic"] == pytest.approx(m / med[0], rel=1e-15)
    assert np.allclose(small.ratio_to_plastic(), med / med[0], rtol=1e-15)
    # partly elastic impacts damp the motion less than the paper's plastic one (its upper limit)
    assert 0.0 < s["by_e"]["0.5"]["ratio_to_plastic"] < 1.0 and s["by_e"]["1"]["ratio_to_plastic"] == 0.0
    # e > 0: a periodic motion's exact orbit has rebounds (R) in its signature and the simulated loss
    t = small.table
    for i in np.flatnonzero((t["e"] > 0) & (t["signature"] != "")):
        assert "R" in t["signature"][i] and t["exact_loss"][i] == pytest.approx(t["loss_per_T"][i], rel=1e-6)


def test_an_fe_bar_with_an_end_mass():
    case = plbar.Case(model="fe", n=16, end_mass=0.5)
    Tf = default_periods(case)[[40, 120]]
    r = survey_restitution(case, Tf, [0.0, 0.4, 1.0], periods=200)
    t = r.table
    assert len(r) == 6 and np.all(np.abs(t["energy_residual"]) <= 1e-12)
    assert np.all(t["loss_per_T"][t["e"] == 1.0] == 0.0) and np.all(t["xi_eq"][t["e"] == 0.4] > 0.0)
    ref = survey(case, Tf, periods=200).table
    assert np.array_equal(t["xi_eq"][t["e"] == 0.0], ref["xi_eq"])


@pytest.mark.parametrize("bad", [[], [-0.1], [0.2, 1.5], "0.5", [np.nan], [True], None, [[0.1], "x"]])
def test_bad_restitutions_are_refused(bad):
    with pytest.raises(InputError, match=r"restitutions = .* must be coefficients of restitution e in \[0, 1\]"):
        survey_restitution(plbar.Case(), [10.0], bad, periods=10)


def test_restitutions_are_sorted_and_distinct():
    assert np.array_equal(check_restitutions([0.6, 0, 0.3, 0.6]), [0.0, 0.3, 0.6])
    assert np.array_equal(check_restitutions(1), [1.0])


def test_the_default_periods_do_not_depend_on_restitution():
    assert np.array_equal(default_periods(plbar.Case(restitution=0.5)), np.linspace(6.0, 14.0, 161))
    fe = plbar.Case(model="fe", n=16, end_mass=0.5)
    assert np.array_equal(default_periods(fe), default_periods(plbar.Case(model="fe", n=16, end_mass=0.5,
                                                                          restitution=0.3)))


def test_the_table_summary_and_figure_are_written(small, tmp_path):
    files = write_restitution(tmp_path, small, "chain")
    assert files["table"].read_text().startswith("e,T,kind,m,")
    assert len(files["table"].read_text().splitlines()) == 1 + len(small)
    assert set(json.loads(files["summary"].read_text())["by_e"]) == {"0", "0.5", "1"}
    figs = survey_restitution_plot({"chain": small.table, "again": small.table}, tmp_path, "restitution",
                                   periods={"chain": [9.0]}, units={"chain": "m = k = 1"})
    assert [f.name for f in figs] == ["restitution.png", "restitution.pdf"]
    assert all(f.stat().st_size > 10_000 for f in figs)
    one = survey_restitution_plot(small.table, tmp_path, "one")          # a single table
    assert all(f.stat().st_size > 10_000 for f in one)


def test_a_case_file_with_a_restitution_runs_the_survey(tmp_path):
    """``[bar] restitution = e`` in a TOML case: ``plbar survey --case`` simulates with it (no exact branches are
    drawn under it: those are the plastic impact's)."""
    from plbar.cli import main

    f = tmp_path / "case.toml"
    f.write_text('[bar]\nmodel = "chain"\nn = 5\nrestitution = 0.5\n\n[[load]]\nnode = 1\n')
    assert main(["survey", "--case", str(f), "--T-list", "11.8", "12.4", "--periods", str(PERIODS), "--out",
                 str(tmp_path / "s"), "-q"]) == 0
    text = (tmp_path / "s" / "survey.csv").read_text().splitlines()
    ref = survey(plbar.Case(restitution=0.5), [11.8, 12.4], periods=PERIODS).table
    xi = [float(line.split(",")[7]) for line in text[1:]]
    assert text[0].split(",")[7] == "xi_eq" and xi == list(ref["xi_eq"])
    assert (tmp_path / "s" / "survey.png").is_file()
