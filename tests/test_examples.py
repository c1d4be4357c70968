"""Examples run as scripts (MPLBACKEND=agg) and their numbers are asserted."""

import os
import runpy
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

EX = Path(__file__).parents[1] / "examples"


def _run(script, *args, timeout=300):
    env = dict(os.environ, MPLBACKEND="agg")
    p = subprocess.run([sys.executable, str(EX / script), *map(str, args)], capture_output=True, text=True,
                       timeout=timeout, env=env)
    assert p.returncode == 0, p.stderr[-2000:]
    return p.stdout


def test_paper_sec41_numbers():
    out = _run("paper_sec41.py")
    assert "T0_I = 10.1664" in out and "T0_II = 22.0749" in out
    ns = runpy.run_path(str(EX / "paper_sec41.py"))
    red, green = ns["points"]["red"], ns["points"]["green"]
    assert red["T2"] == pytest.approx(8.1525, abs=5e-3) and green["T2"] == pytest.approx(9.8894, abs=5e-3)
    assert np.mod(red["phi"], 2 * np.pi) == pytest.approx(3.5495, abs=5e-3)
    assert np.mod(green["phi"], 2 * np.pi) == pytest.approx(4.8050, abs=5e-3)
    assert green["dPL"] == pytest.approx(1.05, rel=0.05)
    # Eq. (22) evaluated exactly: larger than the paper's Fig. 6b reading (0.052), see docs/paper.md
    assert green["xi"] == pytest.approx(0.0763, abs=5e-4)
    assert red["xi"] == pytest.approx(0.00105, abs=5e-5)
    assert "paper, read off Fig. 6b" in out


@pytest.mark.slow
def test_stability_continuation_example(tmp_path):
    out = _run("stability_continuation.py", tmp_path)
    assert "event:" in out and "ends:" in out
    for name in ("frequency_response.png", "paths_T1_T2.png"):
        assert (tmp_path / name).stat().st_size > 10_000


@pytest.mark.slow
def test_settle_from_rest_example(tmp_path):
    out = _run("settle_from_rest.py", tmp_path)
    assert (tmp_path / "settle_from_rest.png").stat().st_size > 10_000
    assert "settle" in out.lower()


def test_one_response_example():
    import re

    out = _run("one_response.py")
    assert float(re.search(r"xi_eq = ([0-9.]+)", out).group(1)) == pytest.approx(0.0763, abs=5e-4)
    assert "admissible (no premature switch on (0, T)): True" in out
    assert float(re.search(r"back to it within ([0-9.e+-]+)", out).group(1)) < 1e-9
    assert float(re.search(r"periodicity defect ([0-9.e+-]+)", out).group(1)) < 1e-12


def test_load_sweep_example(tmp_path):
    env = dict(os.environ, MPLBACKEND="agg", PLBAR_GRID="60,60")
    p = subprocess.run([sys.executable, str(EX / "load_sweep.py"), str(tmp_path)], capture_output=True, text=True,
                       timeout=300, env=env)
    assert p.returncode == 0, p.stderr[-2000:]
    single = float(p.stdout.split("max xi_eq of a single force = ")[1].split()[0])
    worst = float(p.stdout.split("worst load distribution xi_eq = ")[1].split()[0])
    assert single == pytest.approx(0.0958, abs=2e-3) and worst >= single
    assert (tmp_path / "worst_load.csv").read_text().startswith("branch,point,T1,T2,phi,T,xi_worst,")


@pytest.mark.slow
def test_restitution_example(tmp_path):
    """Issue 31: xi_eq of the real motion against the coefficient of restitution, chain and FE bar (quick)."""
    out = _run("restitution.py", tmp_path, "--quick")
    rows = [ln.split() for ln in out.splitlines() if ln.startswith("  ") and ln.split()[0] in ("0.00", "0.30",
                                                                                                  "0.60", "1.00")]
    assert len(rows) == 8, out
    for r in rows:
        ratio = float(r[5])
        assert (ratio == 1.0) if r[0] == "0.00" else (ratio == 0.0 if r[0] == "1.00" else 0.0 < ratio < 1.0), r
    assert out.count("energy budget closes to") == 2 and "of the plastic upper bound" in out
    for name in ("restitution_chain.csv", "restitution_fe.csv", "restitution_chain.json", "restitution.png",
                 "restitution.pdf"):
        assert (tmp_path / name).stat().st_size > 1_000, name


@pytest.mark.slow
def test_refinement_example(tmp_path):
    env = dict(os.environ, MPLBACKEND="agg", PLBAR_NMAX="16")
    p = subprocess.run([sys.executable, str(EX / "refinement.py"), str(tmp_path)], capture_output=True, text=True,
                       timeout=900, env=env)
    assert p.returncode == 0, p.stderr[-2000:]
    out = p.stdout
    assert "nan" not in out.lower()
    # the end-mass loss ratio is S / M_e = 1 + 1/N exactly (P1 lumped, M_e = rhoA L / 2) where a point is admissible
    for n in (8, 16):
        line = [ln for ln in out.split("2. P1")[0].splitlines() if ln.strip().startswith(f"{n} ")]
        assert line, n
        if not line[0].rstrip().endswith("-"):
            assert float(line[0].split()[-1]) == pytest.approx(1 + 1 / n, rel=1e-9)
    # N = 8, 16 (and the chain's 5, 6, 8): too few meshes to state a rate (docs/refinement.md: from 4 on)
    assert "S/M_e         no rate stated: rests on 2 meshes" in out and "-> 2: rate" not in out
    assert "T0_I_L        no rate stated: rests on 3 meshes" in out
    steps = [float(ln.split("step / ln 2 = ")[1].split()[0]) for ln in out.splitlines() if "step / ln 2" in ln]
    assert len(steps) == 4 and steps[-1] == pytest.approx(2 / 3.141592653589793, rel=2e-3)


@pytest.mark.slow
def test_inherent_damping_example(tmp_path):
    """Issue 21: xi_eq of the impact with 0, 1, 2, 5 % Rayleigh damping, chain and FE bar; the figure."""
    out = _run("inherent_damping.py", tmp_path)
    rows = [ln.split() for ln in out.splitlines() if ln.strip().endswith(tuple("0123456789")) and "%" in ln]
    chain = {float(r[0]): (float(r[4]), float(r[5]), float(r[6])) for r in rows[:4]}
    fe = {float(r[0]): (float(r[4]), float(r[5]), float(r[6])) for r in rows[4:8]}
    assert chain[0.0][0] == pytest.approx(0.0773, abs=5e-4)          # the undamped maximum (Eq. 22)
    assert chain[2.0][0] == pytest.approx(0.0685, abs=5e-4) and chain[2.0][1] == pytest.approx(12.44, abs=0.05)
    # damping lowers the impact's own share, but the total ratio at its maximum grows
    xs = [chain[z][0] for z in (0.0, 1.0, 2.0, 5.0)]
    tot = [chain[z][2] for z in (0.0, 1.0, 2.0, 5.0)]
    assert xs == sorted(xs, reverse=True) and tot == sorted(tot)
    for z, (xi, _T, total) in list(chain.items()) + list(fe.items()):
        assert total >= xi and (z > 0) == (total > xi)
    assert fe[2.0][0] == pytest.approx(0.0711, abs=1e-3)
    for ext in ("png", "pdf"):
        assert (tmp_path / f"xi_rayleigh.{ext}").stat().st_size > 10_000


def test_impact_oscillator_example(tmp_path):
    """COCO's impact oscillator (issue 41): the orbit the test's own integrator finds
    (tests/periodic/test_peer_coco_impact.py: impact velocity 1.69573294, phase 0.07595216), stable, one branch."""
    out = _run("impact_oscillator.py", tmp_path)
    assert "impact velocity 1.695733" in out and "forcing phase at the impact 0.075952" in out
    assert "|mu| = 0.58432 (stable)" in out and out.count("branch ") == 1
    assert (tmp_path / "impact_oscillator.png").is_file()


def test_cantilever_stop_example(tmp_path):
    """A cantilever against a tip stop with a clearance (issue 41): xi_eq over (T, A / d); more of the motions
    reach the stop as A / d grows, none of them damp at A / d = 1 below the resonance band, and the figure."""
    out = _run("cantilever_stop.py", tmp_path, "--quick")
    hits = [int(line.split(":")[1].split("of")[0]) for line in out.splitlines() if "motions reach the stop" in line]
    assert len(hits) == 3 and hits == sorted(hits) and hits[-1] == 7
    assert (tmp_path / "cantilever_stop.png").is_file()


def test_base_excited_cantilever_example(tmp_path):
    """A base-excited cantilever against a tip stop (issue 41): more motions reach the stop as a_g / d grows."""
    out = _run("base_excited_cantilever.py", tmp_path, "--quick")
    hits = [int(line.split(":")[1].split("of")[0]) for line in out.splitlines() if "motions reach the stop" in line]
    assert len(hits) == 3 and hits == sorted(hits) and hits[-1] == 7
    assert (tmp_path / "base_excited_cantilever.png").is_file()


def test_cracked_bar_example(tmp_path):
    """A breathing crack (issue 41): xi_eq of the crack between two clamps halves with the element size (the faces
    carry no mass), most motions there settle on a periodic orbit within 300 periods; the floating crack opens for
    good after its first contacts; and the figure."""
    import re

    out = _run("cracked_bar.py", tmp_path, "--quick")
    ratios = [float(r) for r in re.findall(r"= ([0-9.]+) \(O\(h\): 2\)", out)]
    assert len(ratios) == 1 and 1.6 < ratios[0] < 2.3
    periodic = [int(k) for k in re.findall(r"(\d+) of 8 motions periodic", out)]
    assert len(periodic) == 2 and min(periodic) >= 6
    last = [float(p) for p in re.findall(r"\(period ([0-9.]+) of 40\)", out)]
    assert len(last) == 3 and max(last) < 5
    assert (tmp_path / "cracked_bar.png").is_file()
