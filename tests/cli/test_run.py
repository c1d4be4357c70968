"""``plbar run``: what a run records and prints, what it refuses, what a large solve costs; the result behind it.

From the newcomer reports (the first hour, issues 22 and 30). Where a test failed on the code before the fix it
covers, its docstring says so (or says what happened before).
"""

import json

import numpy as np
import pytest

import plbar
from plbar.cli import main

from _helpers import FAST, MESH, PAPER, _run


# what a run records: the options used, the version, the chain's length, amplitude and frequency ---------------------

def test_summary_records_only_the_options_used(tmp_path, capsys):
    """Failed on the code before the fix it covers (issue 22)."""
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", tmp_path / "c", *FAST])[0] == 0
    case = json.loads((tmp_path / "c" / "summary.json").read_text())["case"]
    assert not {"element", "mass", "grading", "mesh_file", "EA", "rhoA", "point_masses"} & set(case)
    assert case["n"] == 4 and case["length"] == 4.0
    assert _run(capsys, ["run", *PAPER, "--model", "fe", "--mesh-file", MESH, "--out", tmp_path / "m", *FAST])[0] == 0
    s = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert not {"n", "grading", "length", "m", "k"} & set(s["case"]) and s["dofs"] == 8
    assert plbar.app.case_of_run(tmp_path / "m").bar().n_elements == 8


def test_summary_has_the_plbar_version(tmp_path, capsys):
    """Failed on the code before the fix it covers (issue 22)."""
    assert _run(capsys, ["run", *PAPER, "-N", "3", "--out", tmp_path, *FAST])[0] == 0
    assert json.loads((tmp_path / "summary.json").read_text())["plbar_version"] == plbar.__version__


def test_summary_length_of_the_chain_is_N(tmp_path, capsys):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--grid", "30", "30", "--out", tmp_path / "o", "-q",
                         "--no-plot"])[0] == 0
    assert json.loads((tmp_path / "o" / "summary.json").read_text())["case"]["length"] == 4.0


def test_paths_csv_has_amplitude_and_frequency(tmp_path, capsys):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    assert _run(capsys, ["run", *PAPER, "-N", "5", "--grid", "60", "60", "--out", tmp_path / "o", "-q",
                         "--no-plot"])[0] == 0
    cols = plbar.app.read_paths(tmp_path / "o" / "paths.csv")
    assert np.allclose(cols["omega"], 2 * np.pi / cols["T"], rtol=1e-15)
    assert np.all(cols["max_abs_xc"] > 0)


# what a run prints: the stable responses first, on one screen, a warning where nothing is found ---------------------

FE_RUN = ["run", "--model", "fe", "-N", "6", "--element", "P2", "--mass", "consistent", "--load-at", "0.37", "--grid",
          "60", "60", "--signatures", "paper", "--no-plot"]


def test_an_fe_run_leads_with_its_stable_responses(tmp_path, capsys):
    """The summary says how many points are stable, lists branches with stable points first and no branch of fewer
    than 3 points (before: a 1-point branch in the top five, the stable ones among the rest)."""
    assert main([*FE_RUN, "--out", str(tmp_path / "f")]) == 0
    out = capsys.readouterr().out.splitlines()
    assert any("points are stable, on 2 branches" in line for line in out)
    listed = [line for line in out if line.startswith("  branch ")]
    stable = [int(line.rsplit(",", 1)[1].split()[0]) > 0 for line in listed]
    assert len(listed) == 5 and stable == sorted(stable, reverse=True) and stable[0]
    assert all(int(line.split(":")[1].split()[0]) >= 3 for line in listed)


def test_a_run_without_a_stable_point_points_to_the_survey(tmp_path, capsys):
    """No stable point: one line says so and names the survey with the same case options."""
    fe = FE_RUN[:FE_RUN.index("--grid")]
    assert main([*fe, "--grid", "40", "40", "--signatures", "paper", "--no-plot", "--T1", "0.08", "0.16", "--T2", "0.6",
                 "0.85", "--out", str(tmp_path / "f")]) == 0
    out = capsys.readouterr().out.splitlines()
    i = next(i for i, line in enumerate(out) if line.startswith("  none of"))        # after the units' lines
    found = next(line for line in out if "admissible points" in line).split()[2]   # "  1 branches, 385 ..."
    assert out[i].startswith(f"  none of the {found} points is stable") and out[i].endswith(
        "run plbar survey --model fe -N 6 --element P2 --mass consistent --load-at 0.37")
    assert "stable points first" not in out[i + 1]


@pytest.mark.slow
def test_many_branches_print_a_short_summary(tmp_path, capsys):
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    argv = ["run", *PAPER, "--model", "fe", "-N", "8", "--element", "P2", "--grid", "60", "60", "--out", tmp_path / "f",
            "--no-plot"]
    code, out, _ = _run(capsys, argv)
    n = json.loads((tmp_path / "f" / "summary.json").read_text())["n_branches"]
    assert code == 0 and n > 10
    # 16 lines: the case, its periods, its units, the window searched, the count, the stability, five branches, the
    # rest in one line, the note on other signatures, the time, the files
    assert out.count("\n") <= 16 and "--verbose lists all" in out and f"{n - 5} more branches" in out
    code, out, _ = _run(capsys, argv + ["--verbose", "--overwrite"])
    assert out.count("  branch ") == n


def test_one_point_is_singular():
    """Failed on the code before the fix it covers (issue 22)."""
    from plbar.cli.run import _line

    b = {"branch": 3, "signature": "1P", "points": 1, "T_range": [1.0, 1.0], "xi_range": [0.1, 0.1],
         "stable_points": 0}
    assert "1 point," in _line(b) and "1 points" not in _line(b)


def test_nothing_found_warns_and_the_plot_covers_the_range_asked(tmp_path, capsys, monkeypatch):
    """A search window with no response: a warning naming it, and a figure over the range asked (before: "0
    branches" without a word, then 'failed: ValueError: Data cannot be log-scaled', exit 1)."""
    pytest.importorskip("matplotlib")
    import plbar.visuals.plots as plots

    seen = {}
    save = plots._save

    def spy(fig, out, name):
        seen[name] = fig.axes[-1].get_xlim()
        return save(fig, out, name)

    monkeypatch.setattr(plots, "_save", spy)
    assert main(["run", "--T1", "0.001", "0.002", "--T2", "0.001", "0.002", "--grid", "40", "40", "--signatures",
                 "paper", "--out", str(tmp_path / "e")]) == 0
    err = capsys.readouterr().err
    assert "warning: no admissible periodic response in T1 = [0.001, 0.002]" in err
    assert seen["frequency_response"] == pytest.approx((0.002, 0.004))


# what a run refuses, what a large solve costs before it starts ------------------------------------------------------

def test_errors_say_what_to_give(tmp_path, capsys):
    """``run -N 8 16`` names the one size run takes and where several go (before: "conflicts with the case file
    '16'"); an FE bar too fine for its shortest element says the largest N (before: "element 25005 ... too short")."""
    assert main(["run", "-N", "8", "16", "--out", str(tmp_path / "r"), "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert "one size" in err and "plbar refine -N 8 16" in err and "case file '16'" not in err
    assert main(["run", "--model", "fe", "-N", "100000", "--out", str(tmp_path / "r"), "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert "N <= 99999" in err and "element 25005" not in err
    assert not (tmp_path / "r").exists()


def test_run_says_what_a_large_solve_costs_before_it_starts(tmp_path, capsys, monkeypatch):
    """Failed on the code before the fix it covers (issue 22)."""
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
    """Failed on the code before the fix it covers (issue 22)."""
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


# the result behind a run: its impact loss (Delta_PL = S v_c^2 / 2), its repr ----------------------------------------

def test_impact_loss_is_exact_near_grazing(fe_p2_coarse):
    """Delta_PL is S v_c^2 / 2 itself (every digit), not a difference of kinetic energies.
    Failed on the code before the fix it covers (issue 22)."""
    res = fe_p2_coarse
    S = res.prob.system.impact_mass
    for b in res.paths.branches:
        vc = b.orbits.contact_velocity(b.orbits.T2[:, None])[:, 0]
        np.testing.assert_allclose(b.dPL, 0.5 * S * vc ** 2, rtol=1e-14, atol=0)


def test_truncated_impact_loss_keeps_the_projection_loss():
    """Failed on the code before the fix it covers (issue 22)."""
    from plbar.response import impact_loss, kinetic_energy_loss

    res = plbar.solve(plbar.Case(signatures="paper", model="fe", n=12, modes=4, grid=(40, 40)))
    orb = res.paths.branches[0].orbits
    S = res.prob.system.impact_mass
    vc = orb.contact_velocity(orb.T2[:, None])[:, 0]
    np.testing.assert_array_equal(impact_loss(orb), kinetic_energy_loss(orb))
    assert np.all(impact_loss(orb) >= 0.5 * S * vc ** 2 * (1 - 1e-12))
    assert np.any(impact_loss(orb) > 1.01 * 0.5 * S * vc ** 2)


def test_result_repr_is_short():
    """Failed on the code before the fix it covers (a newcomer's first hour)."""
    res = plbar.solve(plbar.Case(signatures="paper", model="fe", n=8, grid=(60, 60)))
    text = repr(res)
    assert len(text) < 3000 and text.startswith("Result(") and f"{len(res.branches)} branches" in text
    assert len(repr(res.case)) < 500 and len(repr(res.prob)) < 2000
