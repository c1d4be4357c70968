"""A base excitation (issue 41 item 4): the support shaken along the bar, the load ``-M t a_g cos(W t)``.

In coordinates relative to the support the structure obeys ``M x'' + C x' + K x = -M t a_g cos(W t - phi)``
(FORMULATION §9).  Checked here against what plbar did not compute: the effective load against the full mass
matrix assembled in the test with scikit-fem (clamp included) times ones; the transformation's premise, that a
rigid motion strains nothing (``K_full 1 = 0``); and the motion in absolute coordinates, integrated in the test
with the clamp moving (``u_g = -a_g cos(W t) / W^2``), against plbar's relative motion plus ``u_g``.  Then the way in
(``Case(base=...)``, ``[[load]] base``, ``--base``) and what refuses it by name.
"""

import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from skfem import Basis, BilinearForm, ElementLineP1, MeshLine, asm

import plbar
from plbar.app import dump_case, load_case
from plbar.errors import InputError
from plbar.motion import padded, run


def _full(n: int):
    """Consistent mass and stiffness of the unit bar (EA = rhoA = 1) over every node, the clamp's included."""
    basis = Basis(MeshLine(np.linspace(0.0, 1.0, n + 1)), ElementLineP1())
    M = asm(BilinearForm(lambda u, v, w: u * v), basis).toarray()
    K = asm(BilinearForm(lambda u, v, w: u.grad[0] * v.grad[0]), basis).toarray()
    order = np.argsort(basis.doflocs[0])
    return M[np.ix_(order, order)], K[np.ix_(order, order)]


def test_the_effective_load_is_the_mass_times_the_support_motion():
    c = plbar.Case(model="fe", n=6, mass="consistent", base=0.7)
    q = c.problem().structure.q
    M, K = _full(6)
    assert np.allclose(K @ np.ones(7), 0.0, atol=1e-12)                 # a rigid motion strains nothing
    assert np.allclose(q, -0.7 * (M @ np.ones(7))[1:], rtol=1e-13, atol=0)


def test_the_relative_motion_is_the_absolute_one_less_the_support():
    """No contact reached (a small shake): plbar's relative motion plus the support's is the absolute motion of
    the bar with its clamp moving, integrated here (DOP853) from the same start, to 1e-9."""
    a_g, T, periods = 0.01, 3.1, 3
    c = plbar.Case(model="fe", n=6, mass="consistent", base=a_g, gap=0.5)
    prob = c.problem()
    r = run(padded(prob), np.array([T]), 0.0, periods, periods)
    assert r.status[0] == 0 and r.events.size == 0                      # free all along: the gap is never closed
    M, K = _full(6)
    W = 2 * np.pi / T
    ug = lambda t: -a_g * np.cos(W * t) / W ** 2                          # noqa: E731 (acceleration a_g cos W t)
    vg = lambda t: a_g * np.sin(W * t) / W                                # noqa: E731
    Mff, Kff, Mfc, Kfc = M[1:, 1:], K[1:, 1:], M[1:, 0], K[1:, 0]
    Mi = np.linalg.inv(Mff)

    def f(t, z):                                                          # absolute DOFs, the clamp prescribed
        return np.concatenate([z[6:], Mi @ (-Kff @ z[:6] - Kfc * ug(t) - Mfc * a_g * np.cos(W * t))])

    # plbar's start: at rest relative to the support (x = 0, v = 0): absolutely at u_g(0) with velocity v_g(0)
    z0 = np.concatenate([np.full(6, ug(0.0)), np.full(6, vg(0.0))])
    sol = solve_ivp(f, (0.0, periods * T), z0, method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True)
    x_abs = sol.sol(periods * T)[:6]
    assert np.max(np.abs(r.strobe_x[0, -1] + ug(periods * T) - x_abs)) < 1e-9 * np.abs(x_abs).max()


def test_a_case_carries_its_base(tmp_path):
    c = plbar.Case(model="fe", n=6, base=0.5)
    assert c.load().base == 0.5 and not c.load_points and not c.load_nodes   # no default force beside it
    assert c.to_dict()["base"] == 0.5 and "base" not in plbar.Case().to_dict()
    p = tmp_path / "b.toml"
    p.write_text(dump_case(c))
    assert "base = 0.5" in p.read_text() and load_case(p)[0] == c
    both = plbar.Case(model="fe", n=6, base=0.5, load_points=((0.5, 2.0),))
    assert both.problem().structure.q[2] == pytest.approx(2.0 - 0.5 * (1 / 6), rel=1e-12)   # lumped: h at a node
    with pytest.raises(InputError, match="base"):
        plbar.Case(base=float("inf"))


def test_the_commands_take_it_or_say_why_not(tmp_path):
    cmd = [sys.executable, "-m", "plbar"]
    ok = subprocess.run(cmd + ["run", "--base", "1", "--no-plot", "--quiet", "--out", str(tmp_path / "r")],
                        capture_output=True, text=True)
    assert ok.returncode == 0, ok.stderr
    for args, why in ((["sweep-loads", "--base", "1"], "shaking support"),
                      (["survey", "--base", "1", "--positions", "1", "--T-list", "9"], "shaking support"),
                      (["run", "--model", "continuum", "--base", "1"], "no base excitation")):
        out = subprocess.run(cmd + args + ["--no-plot", "--out", str(tmp_path / "x")], capture_output=True,
                             text=True)
        assert out.returncode == 2 and why in out.stderr, (args, out.stderr)
