"""``plbar refine``: what it refuses before any folder, a study extended with new N or rerun after a failure, the rates
it states (or why not), its help and the jump law of its page.

From the newcomer reports (the first hour, issues 22 and 44). Every test here failed on the code before the fix it
covers.
"""

import json

import numpy as np

from plbar.cli import main
from plbar.errors import InputError

from _helpers import ROOT, _refused, _run


# refused before any folder (issue 22) -------------------------------------------------------------------------------

def test_refine_refuses_grading_on_the_chain_before_any_folder(tmp_path, capsys):
    _refused(capsys, ["refine", "-N", "3", "4", "--grading", "3", "--out", tmp_path / "r"], "grading = 3.0")
    _refused(capsys, ["refine", "-N", "3", "4", "--modes", "3", "--out", tmp_path / "r"], "--modes")
    _refused(capsys, ["refine", "-N", "3", "4", "--window", "5", "--out", tmp_path / "r"], "window = 5.0")
    assert not (tmp_path / "r").exists()


# extended with new N, a failed study leaves nothing (issue 22) ------------------------------------------------------

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


# rates with their meshes, never null without a reason, never nan, one verdict per quantity --------------------------

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


def test_refine_rates_say_why_and_write_no_nan(tmp_path, capsys):
    out = tmp_path / "r"
    code, text, _ = _run(capsys, ["refine", "-N", "3", "4", "--grid", "40", "40", "--executor", "serial",
                                  "--out", out, "--json"])
    assert code == 0
    rates = json.loads(text)["rates"]
    for fams in rates.values():
        for qs in fams.values():
            for q, r in qs.items():
                if q == "xi_decay":                      # a decay law, or why none
                    assert r["model"] or r["why"], r
                else:
                    assert r["rate"] is not None or r["why"], (q, r)
    for f in ("refine.csv", "refine_rates.json"):
        assert "nan" not in (out / f).read_text().lower()


def _refine(xi):
    """A refine result of one family with ``xi_max`` per N = 3 ... (the P2 lumped family T0_II/2 of the issue)."""
    from plbar.studies.refine import RefineStudy, known_limit
    from plbar.studies.refine.tables import decay_of

    n = [3, 4, 5, 6, 8, 12, 16][:len(xi)]
    rows = [{"series": "fe-P2-lumped", "family": "T0_II/2", "n": k, "status": "split", "admissible": 100,
             "T_min_L": 2.0, "T_max_L": 2.1, "xi_max": x, "T_at_max_L": 2.05, "impact_mass": 0.0, "end_mass": 0.0,
             "length": 1.0}
            for k, x in zip(n, xi)]
    rates = {"xi_max": known_limit("xi_max", [1 / k for k in n], xi, 0.0, n=n).as_dict(), "xi_decay": decay_of(rows)}
    return RefineStudy(rows, {"fe-P2-lumped": {"T0_II/2": rates}}, {}, {})


def test_refine_states_no_decay_law_after_no_rate():
    from plbar.cli.studies import _refine_lines

    wander = [0.031264, 0.024611, 0.013656, 0.011029, 0.0057532, 0.0015713, 0.0020888]   # grows at the end
    lines = [ln.strip() for ln in _refine_lines(_refine(wander))]
    (xi,) = [ln for ln in lines if ln.startswith("xi_max")]
    assert xi.startswith("xi_max        no rate")
    lines = [ln.strip() for ln in _refine_lines(_refine(wander), always=True)]
    assert any("decays like" in ln and "not a verdict" in ln for ln in lines)
    decay = [0.031264, 0.024611, 0.013656, 0.011029, 0.0057532, 0.0015713]                # decays throughout
    lines = [ln.strip() for ln in _refine_lines(_refine(decay))]
    assert [ln for ln in lines if ln.startswith("xi_max")][0].startswith("xi_max        -> 0: rate")
    assert any(ln.startswith("xi_max decays like q ~") and "verdict" not in ln for ln in lines)


# its help, the jump law in docs/refinement.md (issue 22) ------------------------------------------------------------

def test_refine_help_lists_only_what_refine_accepts(capsys):
    assert main(["refine", "--help"]) == 0
    text = capsys.readouterr().out
    for opt in ("--modes", "--mesh-file", "--T1", "--T2", "--method"):
        assert opt not in text, opt
    assert "--rates-always" in text and "--grading" in text


def test_docs_state_the_jump_law_with_two_over_pi():
    text = " ".join((ROOT / "docs" / "refinement.md").read_text().split())
    assert r"\frac{2}{\pi} \rho A c \, v_c^2 \ln N" in text and r"\frac{4}{\pi} \rho A c \, v_c^2 \ln N" not in text
    assert r"\lesssim \frac{\pi S}{4 \rho A c \, T \ln(N/N_0)}" in text and r"\frac{\pi S}{8" not in text
