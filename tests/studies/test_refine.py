"""Mesh refinement: anchors, families followed through N (checked against the scan and the full solve),
continuum limits, FE rates and the logarithmic growth of the damping denominator on a velocity jump."""

import json
import math

import numpy as np
import pytest

import plbar
from plbar.cli.main import main
from plbar.errors import InputError
from plbar.studies.refine.anchors import parse_anchor, window_band
from plbar.studies.refine.convergence import known_limit
from plbar.studies.refine.tables import continuum_periods
from plbar.studies.refine.track import TrackSettings, carry_level, seed_levels
from plbar.check import IMPACT, OPEN
from plbar.response import periodic_state
from plbar.studies.refine.track_check import compare_with_scan

# -- anchors --------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("spec, state, factor, text", [
    ("T0_I", "I", 1.0, "T0_I"), ("T0_II/2", "II", 0.5, "T0_II/2"), ("t0_ii / 2", "II", 0.5, "T0_II/2"),
    ("2*T0_I", "I", 2.0, "2*T0_I"), ("3*T0_II/2", "II", 1.5, "3*T0_II/2"), ("3.6", None, 3.6, "3.6")])
def test_anchor_parsing(spec, state, factor, text):
    a = parse_anchor(spec)
    assert (a.state, a.factor, str(a)) == (state, pytest.approx(factor), text)
    assert a.period(2.0, 6.0) == pytest.approx({"I": 2.0, "II": 6.0, None: 1.0}[state] * factor)


@pytest.mark.parametrize("spec", ["", "T0_III", "-2*T0_I", "T0_I/0", "abc", 3, None, "0"])
def test_bad_anchor_is_one_clear_line(spec):
    with pytest.raises(InputError, match="anchor"):
        parse_anchor(spec)


def test_window_band_is_the_period_window():
    b = window_band(parse_anchor("T0_II/2"), 2.0, 6.0, 0.1)
    assert b.T == pytest.approx((2.7, 3.3)) and b.T1 == (0.0, 1.0)
    assert window_band(parse_anchor("T0_I"), 2.0, 6.0, 0.2).T1[1] == 1.0             # T1 <= T0_I / 2 (paper)
    assert window_band(parse_anchor("T0_I/4"), 2.0, 6.0, 0.2).T1[1] == pytest.approx(0.999 * 0.4)   # T2 > 0
    with pytest.raises(InputError, match="window"):
        window_band(parse_anchor("T0_I"), 2.0, 6.0, 1.5)


# -- the continuum and the FE rates ---------------------------------------------------------------------------------

@pytest.mark.parametrize("mu", [0.0, 0.25, 0.5, 2.0])
def test_continuum_periods_match_a_fine_mesh(mu):
    """T0^I = 2L/c; T0^II from x tan x = 1/mu (4L/c without an end mass), against P2 with N = 64."""
    EA, rhoA, L = 2.0, 0.5, 1.5
    case = plbar.Case(model="fe", n=64, element="P2", mass="consistent", EA=EA, rhoA=rhoA, length=L, end_mass=mu)
    T0I, T0II = case.problem().system.T0
    base = {"model": "fe", "EA": EA, "rhoA": rhoA}
    lim = continuum_periods({"end_mass": case.end_mass_value, "length": L, "n": 64}, base)
    assert lim[0] == pytest.approx(2 / math.sqrt(EA / rhoA))
    assert T0I / L == pytest.approx(lim[0], rel=1e-8) and T0II / L == pytest.approx(lim[1], rel=1e-8)


@pytest.mark.parametrize("element, mass, rate", [("P1", "lumped", 2), ("P1", "consistent", 2),
                                                 ("P2", "consistent", 4), ("P2", "lumped", 4)])
def test_periods_converge_at_the_element_rates(element, mass, rate):
    """Both fundamental periods against the continuum: P1 at rate 2, P2 at rate 4 (its row-sum lumping is
    Simpson's rule, so lumped P2 keeps rate 4 too)."""
    ns = [8, 16, 32, 64]
    T = np.array([plbar.Case(model="fe", n=n, element=element, mass=mass, end_mass=0.5).problem().system.T0
                  for n in ns])
    lim = continuum_periods({"end_mass": 0.5, "length": 1.0, "n": 64}, {"model": "fe"})
    for j in (0, 1):
        c = known_limit("T0", 1.0 / np.array(ns), T[:, j], lim[j], n=np.array(ns))
        assert c.rate == pytest.approx(rate, abs=0.1), (element, mass, j, c)


def test_chain_periods_converge_and_state_II_at_rate_one():
    """The chain's contact mass m (its m/2 end mass is 1/(2N) of its mass) makes T0^II converge at rate 1."""
    ns = [8, 16, 32, 64, 128]
    T = np.array([plbar.Case(model="chain", n=n).problem().system.T0 for n in ns]) / np.array(ns)[:, None]
    lim = continuum_periods({"end_mass": 0.0, "length": 1.0, "n": 1}, {"model": "chain"})
    assert lim == pytest.approx((2.0, 4.0))
    h = 1.0 / np.array(ns)
    assert known_limit("T0_I", h, T[:, 0], lim[0]).rate == pytest.approx(2, abs=0.05)
    assert known_limit("T0_II", h, T[:, 1], lim[1]).rate == pytest.approx(1, abs=0.05)


@pytest.mark.parametrize("element, mass", [("P1", "lumped"), ("P1", "consistent"), ("P2", "consistent")])
def test_jump_energy_grows_like_2_over_pi_ln_N(element, mass):
    """The damping denominator of Eq. (22) weights modal velocities by w_j.  For the velocity a plastic impact
    leaves in the bar (0 at the clamp, v_c stopped at the contact: one jump) sum_j w_j etadot_j^2 grows by
    (2/pi) rhoA c v_c^2 per unit of ln N, for v = x and v = sin(pi x / 2); v = 1 jumps at the clamp too: 4/pi."""
    ns = [16, 32, 64, 128, 256]
    fields = {"x": (lambda x: x, 2 / math.pi, 3e-3, 2e-4), "one": (lambda x: np.ones_like(x), 4 / math.pi, 3e-3, 2e-4),
              "sin": (lambda x: np.sin(0.5 * math.pi * x), 2 / math.pi, 1.5e-2, 5e-4)}
    e = {k: [] for k in fields}
    for n in ns:
        s = plbar.Case(model="fe", n=n, element=element, mass=mass, end_mass=0.5).problem().system
        for k, (v, *_) in fields.items():
            ed = s.V1.T @ (s.M[:-1, :-1] @ v(s.x[:-1]))         # modal velocities of the field (state I)
            e[k].append(np.sum(s.w1 * ed ** 2))
    for k, (_, law, rel, last) in fields.items():
        step = np.diff(e[k]) / math.log(2)                      # per unit of ln N
        assert step == pytest.approx(law, rel=rel), k           # sin: O(1/N) from its curvature, then 2/pi too
        assert abs(step[-1] - law) < last, k


# -- families through N ---------------------------------------------------------------------------------------------

def _levels(cases, anchor, st):
    levels = seed_levels(cases[0], anchor, st)
    out = [levels[0]]
    for c in cases[1:]:
        out.append(carry_level(out[-1], c, anchor, st))
    return out


@pytest.mark.slow
def test_chain_family_is_the_full_solve_branch():
    """The paper's path 2 followed from N = 5 to 6 and 8 lies on the full solve's branches (and they on it)."""
    anchor = parse_anchor("T0_II/2")
    st = TrackSettings()
    cases = [plbar.Case(model="chain", n=n) for n in (5, 6, 8)]
    levels = _levels(cases, anchor, st)
    for case, lv in zip(cases, levels):
        res = plbar.solve(case)
        r = compare_with_scan(lv, case, paths=res.paths)
        assert r["tracked"] > 50 and r["branches"], (case.n, r)
        assert r["tracked_on_scan"] < 1e-12 and r["scan_on_tracked"] < 1e-12, (case.n, r)
        # what only one side has lies within two grid cells of the other (the ends of a stretch)
        assert r["tracked_off_cells"] is None or r["tracked_off_cells"] < 2, (case.n, r)
        assert r["off"] <= 0.1 * r["scan_points"], (case.n, r)
    assert levels[0]["status"] == "seed" and all(lv["status"] in ("tracked", "split") for lv in levels[1:])


@pytest.mark.slow
def test_fe_family_at_N32_is_the_scan_branch():
    """Acceptance: FE P1 lumped, end mass 0.5, T0_II/2 followed 8 -> 16 -> 32 against the 200 x 200 scan of the
    same window: every point of the scan's branches of the family lies on the followed curves (1e-9), the followed
    admissible points on those branches lie on them (1e-9), and what the walker has beyond the scan (stretches
    shorter than a grid cell between grid lines) are exact admissible responses (find_response, independently)."""
    anchor = parse_anchor("T0_II/2")
    st = TrackSettings()
    cases = [plbar.Case(model="fe", n=n, end_mass=0.5) for n in (8, 16, 32)]
    lv = _levels(cases, anchor, st)[-1]
    r = compare_with_scan(lv, cases[-1], grid=(200, 200))
    assert r["tracked"] > 50 and r["branches"] and r["scan_points"] > 50, r
    assert r["tracked_on_scan"] < 1e-9 and r["scan_on_tracked"] < 1e-9 and r["off"] == 0, r
    # what the walker has beyond the scan: each an exact admissible periodic response, checked by the independent
    # event-driven simulator (one period from the closed-form state: back to it, switching only at T1 and at T)
    prob = cases[-1].problem()
    extra = {tuple(p) for p in r["tracked_off_points"]}
    pts = [(p["T1"][k], p["T2"][k], p["phi"][k]) for p in lv["pieces"] for k in range(len(p["T1"]))
           if (p["T1"][k], p["T2"][k]) in extra]
    assert len(pts) == len(extra) > 0
    for T1, T2, phi in pts:
        orb = plbar.orbits(prob, np.array([T1]), np.array([T2]), np.array([phi]))
        xr, vr = periodic_state(orb)
        sim = plbar.simulate(prob, T1 + T2, phi, xr[0], vr[0], n_periods=1.0)
        assert list(sim.events["kind"]) == [OPEN, IMPACT]
        assert np.abs(sim.events["time"] - [T1, T1 + T2]).max() < 1e-9 * (T1 + T2)
        z0, z1 = np.r_[xr[0], vr[0]], np.r_[sim.x[:-1], sim.v[:-1]]
        assert np.linalg.norm(z1 - z0) < 1e-8 * np.linalg.norm(z0)


@pytest.mark.slow
def test_refine_command_tables_rates_plots_and_resume(tmp_path, capsys):
    out = tmp_path / "r"
    args = ["refine", "--model", "fe", "-N", "6", "8", "12", "--end-mass", "0.5", "--family", "T0_II/2",
            "--grid", "80", "80", "--executor", "serial", "--out", str(out)]
    assert main(args + ["--json"]) == 0
    first = json.loads(capsys.readouterr().out)
    for f in ("refine.csv", "refine_rates.json", "refine_convergence.png", "refine_family.png"):
        assert (out / f).is_file(), f
    text = (out / "refine.csv").read_text()
    assert "nan" not in text.lower() and len(text.splitlines()) == 4
    rows = first["rows"]
    assert [r["n"] for r in rows] == [6, 8, 12] and rows[0]["status"] == "seed"
    for r in rows:                      # Delta_PL / (M_e v_c^2 / 2) = S / M_e exactly (at the largest xi)
        if r["loss_ratio"] is not None:
            assert r["loss_ratio"] == pytest.approx(r["impact_mass"] / r["end_mass"], rel=1e-9)
        assert r["impact_mass"] / r["end_mass"] == pytest.approx(1 + 1 / (2 * r["n"] * 0.5), rel=1e-12)
    rates = first["rates"]["fe-P1-lumped+Me0.5"]["T0_II/2"]
    assert rates["T0_I_L"]["limit"] == pytest.approx(2.0) and rates["S/M_e"]["rate"] == pytest.approx(1, abs=1e-6)
    stamp = {p: p.stat().st_mtime_ns for p in (out / "levels").rglob("N*.json")}
    assert len(stamp) == 3
    assert main(args + ["--json"]) == 0                          # a rerun resumes: nothing recomputed
    assert json.loads(capsys.readouterr().out)["rows"] == rows
    assert {p: p.stat().st_mtime_ns for p in (out / "levels").rglob("N*.json")} == stamp
    other = args[:-2] + ["--out", str(out), "--window", "0.1"]
    assert main(other + ["-q"]) == 2 and "--overwrite" in capsys.readouterr().err
    assert main(other + ["-q", "--overwrite"]) == 0
    assert len(list((out / "levels").rglob("N*.json"))) == 3 and len(list((out / "tasks").glob("*.json"))) == 1


def test_refine_refuses_bad_input(tmp_path, capsys):
    base = ["refine", "--executor", "serial", "--out", str(tmp_path / "x"), "-q"]
    assert main(base + ["-N", "1", "2"]) == 2
    assert main(base + ["--family", "T0_X"]) == 2
    assert "anchor" in capsys.readouterr().err
    assert main(base + ["--window", "2"]) == 2
    assert main(base + ["--T2-frac", "0.5", "1"]) == 2
    for bad in (["--T1", "0", "1"], ["--method", "grid"], ["--mesh-file", "meshes/bar_uniform_8.msh"]):
        assert main(base + ["--model", "fe"] + bad) == 2, bad
    assert "window" in capsys.readouterr().err


def test_truncation_warns_for_xi_and_refine_refuses_it(tmp_path, capsys):
    res = None
    with pytest.warns(plbar.errors.TruncationWarning, match="truncated"):
        res = plbar.solve(plbar.Case(signatures="paper", model="fe", n=12, modes=5, grid=(40, 40)))
    assert res.branches                                    # the paths are still located
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error", plbar.errors.TruncationWarning)
        plbar.solve(plbar.Case(signatures="paper", model="fe", n=6, grid=(40, 40)))     # the full model: no warning
    assert main(["refine", "--model", "fe", "-N", "6", "8", "--modes", "4", "--out", str(tmp_path), "-q"]) == 2
    assert "full model" in capsys.readouterr().err


def test_a_family_on_another_family_s_curves_is_merged_and_ends():
    from plbar.studies.refine.track import mark_merges

    piece = {"T1": [0.1, 0.2, 0.3], "T2": [2.8, 2.75, 2.7], "good": [1, 1, 0], "xi": [0.01, 0.02, 0.0],
             "dPL": [0.1, 0.2, 0.0], "v_c": [1.0, 1.1, 0.0], "phi": [1.0, 1.0, 1.0], "why": ["", "", "x"]}
    other = {**piece, "T2": [2.5, 2.45, 2.4]}
    base = {"band": {"T1": [0.0, 1.0], "T": [2.5, 3.4]}, "notes": [], "status": "tracked"}
    st = TrackSettings()
    out = mark_merges([{**base, "pieces": [piece]}, {**base, "pieces": [piece]}, {**base, "pieces": [other]}],
                      ["A#1", "A#2", "A#3"], st)
    assert [lv["status"] for lv in out] == ["tracked", "merged", "tracked"]
    assert "merged with A#1" in out[1]["notes"][-1]
    case = plbar.Case(model="chain", n=6)
    head = {**out[1], "T0_I": 12.0, "T0_II": 26.0}
    nxt = carry_level(head, case, parse_anchor("T0_II/2"), st)
    assert nxt["status"] == "ended" and "merged" in nxt["notes"][0] and nxt["evaluations"] == 0
