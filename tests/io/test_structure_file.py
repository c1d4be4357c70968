"""A structure from another FE program (``--model matrices``): the file, the case, the commands.

The file route adds no physics: the same matrices given as a file or built by plbar must give the same answers bit
for bit (the built-in bar, the two-body joint of ``tests/model/test_structure.py``); what is checked here is the
file format (round trip, a Rayleigh ``C`` recovered, every refusal), the case (its digest, a case file) and the
commands (``run``, ``survey``: the default case's files byte for byte).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from dataclasses import replace

import numpy as np
import pytest

import plbar
from plbar.app import dump_case, load_case
from plbar.errors import InputError
from plbar.io import read_structure, write_structure

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "model"))
from test_structure import two_bodies  # noqa: E402


def _chain_file(folder: Path) -> Path:
    c = plbar.Case()
    return write_structure(folder / "chain.npz", plbar.bar_structure(c.bar(), c.load()))


def test_a_structure_file_round_trips_exactly(tmp_path):
    st = plbar.Structure(two_bodies().M, two_bodies().K, two_bodies().contact, two_bodies().q, (0.01, 0.002), 0.3,
                         np.arange(5.0))
    back = read_structure(write_structure(tmp_path / "s.npz", st))
    for k in ("M", "K", "contact", "q", "x"):
        assert np.array_equal(getattr(back, k), getattr(st, k))
    assert back.rayleigh == st.rayleigh and back.restitution == st.restitution
    assert back.fingerprint == st.fingerprint


@pytest.mark.slow                    # long: with the slow tests (the default suite under 10 minutes)
def test_the_default_case_from_its_matrices_is_the_default_case(tmp_path):
    """Every branch of every signature, bit for bit (the contact row e_c: nothing is transformed)."""
    f = _chain_file(tmp_path)
    a, b = plbar.solve(plbar.Case()), plbar.solve(plbar.Case(model="matrices", matrices=str(f)))
    assert [x.label for x in a.branches] == [x.label for x in b.branches]
    for x, y in zip(a.branches, b.branches):
        assert np.array_equal(x.T, y.T) and np.array_equal(x.xi, y.xi) and np.array_equal(x.dPL, y.dPL)
        assert np.array_equal(x.max_abs_multiplier, y.max_abs_multiplier)


def test_a_joint_from_a_file_is_the_joint_given_as_a_structure(tmp_path):
    """The two-body joint (contact row e_2 - e_3), its contact as r; as an integer contact DOF the row e_c."""
    st = two_bodies()
    f = write_structure(tmp_path / "joint.npz", st)
    a = plbar.solve(plbar.Case(structure=st, signatures="paper"))
    b = plbar.solve(plbar.Case(model="matrices", matrices=str(f), signatures="paper"))
    assert len(a.branches) == len(b.branches) > 0
    for x, y in zip(a.branches, b.branches):
        assert np.array_equal(x.T, y.T) and np.array_equal(x.xi, y.xi)
    np.savez(tmp_path / "dof.npz", M=st.M, K=st.K, q=st.q, contact=np.int64(4))
    assert np.array_equal(read_structure(tmp_path / "dof.npz").contact, np.eye(5)[4])


def test_a_rayleigh_C_is_recovered_and_any_other_C_refused(tmp_path):
    st = two_bodies()
    alpha, beta = 0.013, 0.0021
    np.savez(tmp_path / "c.npz", M=st.M, K=st.K, r=st.contact, q=st.q, C=alpha * st.M + beta * st.K)
    ab = read_structure(tmp_path / "c.npz").rayleigh
    assert ab[0] == pytest.approx(alpha, rel=1e-12) and ab[1] == pytest.approx(beta, rel=1e-12)
    C = alpha * st.M + beta * st.K
    C[0, 0] += 1e-3
    np.savez(tmp_path / "bad.npz", M=st.M, K=st.K, r=st.contact, q=st.q, C=C)
    with pytest.raises(InputError, match="not of Rayleigh form"):
        read_structure(tmp_path / "bad.npz")


def test_a_structure_file_holds_a_gap(tmp_path):
    """A file's gap is the structure's; the case's gap replaces it; written back, it is kept."""
    st = two_bodies()
    np.savez(tmp_path / "g.npz", M=st.M, K=st.K, r=st.contact, q=st.q, gap=np.array(0.25))
    assert read_structure(tmp_path / "g.npz").gap == 0.25
    case = plbar.Case(model="matrices", matrices=str(tmp_path / "g.npz"))
    assert case.gap == 0.25 and case.problem().gap == 0.25 and case.to_dict()["gap"] == 0.25
    other = plbar.Case(model="matrices", matrices=str(tmp_path / "g.npz"), gap=-0.5)
    assert other.problem().gap == -0.5
    write_structure(tmp_path / "back.npz", other.problem().structure)
    assert read_structure(tmp_path / "back.npz").gap == -0.5


def test_a_file_s_constant_load(tmp_path):
    """``q_s`` in a file is the structure's constant load: read back exactly, in the fingerprint, not scaled by
    ``--amplitude``, and the static equilibrium of state II solves ``K x = q_s``."""
    st = two_bodies()
    q_s = np.linspace(0.1, 0.5, st.n)
    np.savez(tmp_path / "s.npz", M=st.M, K=st.K, r=st.contact, q=st.q, q_s=q_s)
    back = read_structure(tmp_path / "s.npz")
    assert np.array_equal(back.q_s, q_s)
    assert back.fingerprint != read_structure(tmp_path / "s.npz", scale=2.0).fingerprint
    assert np.array_equal(read_structure(tmp_path / "s.npz", scale=2.0).q_s, q_s)
    again = read_structure(write_structure(tmp_path / "back.npz", back))
    assert np.array_equal(again.q_s, q_s) and again.fingerprint == back.fingerprint
    none = read_structure(write_structure(tmp_path / "none.npz", replace(back, q_s=None)))
    assert again.fingerprint != none.fingerprint and none.q_s is None
    prob = plbar.Case(model="matrices", matrices=str(tmp_path / "s.npz")).problem()
    y = prob.structure.physical(prob.statics.x2)
    assert np.allclose(back.K @ y, q_s, rtol=1e-12, atol=1e-12 * np.abs(q_s).max())


@pytest.mark.parametrize("extra, match", [
    ({"gap": np.array(np.nan)}, "gap"),
    ({"q_s": np.ones(4)}, "q_s must have one entry per DOF"),
    ({"t": np.ones(5)}, "base excitation"),
    ({"x0": np.ones(5)}, "a given start"),
    ({"D": np.ones(5)}, "not an array plbar reads"),
    ({"contact": np.int64(1)}, "one of r"),
])
def test_what_a_structure_file_cannot_hold_is_refused_by_name(tmp_path, extra, match):
    st = two_bodies()
    np.savez(tmp_path / "x.npz", M=st.M, K=st.K, r=st.contact, q=st.q, **extra)
    with pytest.raises(InputError, match=match):
        read_structure(tmp_path / "x.npz")


def test_a_missing_or_broken_file_is_refused(tmp_path):
    st = two_bodies()
    with pytest.raises(InputError, match="does not exist"):
        read_structure(tmp_path / "none.npz")
    (tmp_path / "text.npz").write_text("not a zip")
    with pytest.raises(InputError, match="not a readable"):
        read_structure(tmp_path / "text.npz")
    np.savez(tmp_path / "noM.npz", K=st.K, r=st.contact, q=st.q)
    with pytest.raises(InputError, match="has no 'M'"):
        read_structure(tmp_path / "noM.npz")
    np.savez(tmp_path / "dof.npz", M=st.M, K=st.K, q=st.q, contact=np.int64(7))
    with pytest.raises(InputError, match=r"one integer DOF in \[0, 4\]"):
        read_structure(tmp_path / "dof.npz")
    np.savez(tmp_path / "spd.npz", M=st.M, K=st.K, r=st.contact, q=np.zeros(5))
    with pytest.raises(InputError, match="q = 0"):
        read_structure(tmp_path / "spd.npz")


def test_the_case_of_a_file_its_overrides_digest_and_refusals(tmp_path):
    f = _chain_file(tmp_path)
    c = plbar.Case(model="matrices", matrices=str(f), restitution=0.4, rayleigh=(0.01, 0.0))
    assert c.structure.restitution == 0.4 and c.rayleigh == (0.01, 0.0) and c.dofs == 5
    assert plbar.Case(**c.to_dict()) == c                    # what a study's task rebuilds
    with pytest.raises(InputError, match="changed"):
        plbar.Case(model="matrices", matrices=str(f), matrices_digest="0" * 16)
    with pytest.raises(InputError, match="needs a structure file"):
        plbar.Case(model="matrices")
    with pytest.raises(InputError, match="end_mass does not apply to model = 'matrices'"):
        plbar.Case(model="matrices", matrices=str(f), end_mass=0.5)
    with pytest.raises(InputError, match="conflicts with matrices"):
        plbar.Case(model="fe", matrices=str(f))


def test_a_case_file_names_its_structure_file_relative_to_itself(tmp_path):
    _chain_file(tmp_path)
    (tmp_path / "case.toml").write_text('[bar]\nmodel = "matrices"\nmatrices = "chain.npz"\nrestitution = 0.5\n')
    case, _ = load_case(tmp_path / "case.toml")
    assert case.model == "matrices" and Path(case.matrices) == (tmp_path / "chain.npz").resolve()
    assert case.restitution == 0.5
    (tmp_path / "again.toml").write_text(dump_case(case))
    assert load_case(tmp_path / "again.toml")[0] == case


def test_run_and_survey_of_the_default_case_from_its_matrices_write_the_same_tables(tmp_path):
    f = _chain_file(tmp_path)
    cmd = [sys.executable, "-m", "plbar"]
    common = ["--quiet", "--no-plot"]
    for args, name in ((["run", "--signatures", "paper"], "paths.csv"),
                       (["survey", "--T-list", "10", "12", "--periods", "200", "--no-paths"], "survey.csv")):
        a, b = tmp_path / f"a-{args[0]}", tmp_path / f"b-{args[0]}"
        subprocess.run(cmd + args + common + ["--out", str(a)], check=True, cwd=tmp_path)
        subprocess.run(cmd + args + common + ["--model", "matrices", "--matrices", str(f), "--out", str(b)],
                       check=True, cwd=tmp_path)
        assert (a / name).read_bytes() == (b / name).read_bytes()
    out = subprocess.run(cmd + ["run", "--model", "matrices", "--matrices", str(f), "--load-node", "2", "--out",
                                str(tmp_path / "c")], capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode != 0 and "load_nodes does not apply to model = 'matrices'" in out.stderr


def test_the_amplitude_scales_the_file_s_load(tmp_path):
    """--amplitude A (load_scale) multiplies q: at zero gap the responses scale by A, their losses by A^2 and
    xi_eq not at all (the system is linear in the load between its switches)."""
    f = _chain_file(tmp_path)
    a = plbar.solve(plbar.Case(model="matrices", matrices=str(f), signatures="paper"))
    b = plbar.solve(plbar.Case(model="matrices", matrices=str(f), signatures="paper", load_scale=2.5))
    assert np.array_equal(b.case.structure.q, 2.5 * a.case.structure.q)
    for x, y in zip(a.branches, b.branches):
        assert np.allclose(y.T, x.T, rtol=1e-10, atol=0)    # the scan's roots: 1.2e-12 seen with numpy 2.x
        # to round-off of the largest (the grazing ends' losses are round-off themselves)
        assert np.allclose(y.dPL, 6.25 * x.dPL, rtol=1e-9, atol=1e-11 * y.dPL.max())
        assert np.allclose(y.xi, x.xi, rtol=1e-9, atol=1e-11 * y.xi.max())
    assert plbar.Case(**b.case.to_dict()) == b.case
    with pytest.raises(InputError, match="applies to model = 'matrices' only"):
        plbar.Case(load_scale=2.0)
