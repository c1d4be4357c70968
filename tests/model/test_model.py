"""The FE model: the paper's chain through the FE path, loads, eigenfrequency convergence."""

import numpy as np
import pytest

import plbar
from plbar.model import assemble
from plbar.errors import InputError
from plbar.model import two_state


@pytest.mark.parametrize("n", [3, 4, 5, 6])
@pytest.mark.parametrize("m,k", [(1.0, 1.0), (2.5, 0.4)])
def test_chain_matrices_are_eqs_23_24(n, m, k):
    a = assemble(plbar.chain(n, m, k))
    K = k * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    K[-1, -1] = k                                      # Eq. (24): last row (-k, k)
    np.testing.assert_allclose(a.M, m * np.eye(n), rtol=0, atol=1e-15 * m)  # Eq. (24) M^II
    np.testing.assert_allclose(a.K, K, rtol=0, atol=1e-14 * k)
    np.testing.assert_allclose(a.M[:-1, :-1], m * np.eye(n - 1), rtol=0, atol=1e-15 * m)  # Eq. (23) M^I
    np.testing.assert_allclose(a.K[:-1, :-1], K[:-1, :-1], atol=1e-14)  # Eq. (23) K^I = tridiag(-k, 2k, -k)
    np.testing.assert_allclose(a.x, np.arange(1, n + 1))


def test_paper_fundamental_periods():
    s = plbar.problem(plbar.chain(5), plbar.node(1)).system
    T0I, T0II = s.T0
    assert T0I == pytest.approx(10.166, abs=5e-4)
    assert T0II == pytest.approx(22.075, abs=5e-4)
    # closed form for the chain: w = 2 sqrt(k/m) sin(j pi / (2N)) (state I), sin((2j-1) pi / (2(2N+1))) (state II)
    assert T0I == pytest.approx(2 * np.pi / (2 * np.sin(np.pi / 10)), rel=1e-13)
    assert T0II == pytest.approx(2 * np.pi / (2 * np.sin(np.pi / 22)), rel=1e-13)


@pytest.mark.parametrize("n,T", [(3, 14.12), (4, 18.09), (5, 22.07), (6, 26.06)])
def test_state_II_periods_n3_to_6(n, T):
    s = plbar.problem(plbar.chain(n), plbar.node(1)).system
    assert s.T0[1] == pytest.approx(T, abs=5e-3)


def test_modes_mass_normalised_and_switch_maps():
    for bar in (plbar.chain(5), plbar.uniform_bar(6, element="P2", mass="consistent")):
        a = assemble(bar)
        s = two_state(a.M, a.K, a.x)
        np.testing.assert_allclose(s.V2.T @ s.M @ s.V2, np.eye(s.n), atol=1e-12)
        np.testing.assert_allclose(s.V1.T @ s.M[:-1, :-1] @ s.V1, np.eye(s.n - 1), atol=1e-12)
        # II -> I -> II of a state-I vector is the identity (P21 P12 = I)
        np.testing.assert_allclose(s.P21 @ s.P12, np.eye(s.n - 1), atol=1e-12)
    # lumped: the momentum-conserving velocity map equals the paper's truncation (P = Q, Eq. (9))
    a = assemble(plbar.chain(5))
    s = two_state(a.M, a.K, a.x)
    np.testing.assert_allclose(s.Q21, s.P21, atol=1e-14)


def test_reaction_general_form_reduces_to_paper():
    """Lumped chain: -R = k x_{N-1} (h^I = e_{N-1}, Eq. (4)); consistent mass couples more DOFs."""
    p = plbar.problem(plbar.chain(5, m=1.3, k=0.7), plbar.node(2))
    s = p.system
    np.testing.assert_allclose(-s.r_eta, 0.7 * s.V1[-1, :], atol=1e-14)
    assert p.r_q == 0.0
    pc = plbar.problem(plbar.uniform_bar(4, element="P1", mass="consistent"), plbar.point(0.8))
    assert pc.r_q != 0.0 and not pc.system.lumped


def test_point_load_linear_split_p1():
    bar = plbar.chain(5)
    p = plbar.problem(bar, plbar.point(1.25))
    np.testing.assert_allclose(p.q, [0.75, 0.25, 0, 0, 0], atol=1e-15)
    p = plbar.problem(bar, plbar.point(1.25, 2.0) + plbar.node(4, -1.0))
    np.testing.assert_allclose(p.q, [1.5, 0.5, 0, -1.0, 0], atol=1e-15)
    # a load on a node equals the nodal force
    np.testing.assert_allclose(plbar.problem(bar, plbar.point(3.0)).q, plbar.problem(bar, plbar.node(3)).q)


def test_point_load_p2_shape_functions():
    bar = plbar.uniform_bar(2, element="P2")          # DOFs at 0.25, 0.5, 0.75, 1.0
    q = plbar.problem(bar, plbar.point(0.3)).q
    xi = (0.3 - 0.0) / 0.5                              # local coordinate in element [0, 0.5]
    phi = [xi * (2 * xi - 1), 4 * xi * (1 - xi)]       # vertex at 0.5, midside at 0.25
    np.testing.assert_allclose(q[[1, 0]], phi, atol=1e-14)
    # partition of unity: the clamped vertex takes (1 - xi)(1 - 2 xi) < 0 here
    assert q.sum() == pytest.approx(1.0 - (1 - xi) * (1 - 2 * xi), abs=1e-14)


@pytest.mark.parametrize("bad", [0.0, -0.5, 1.5])
def test_load_outside_bar(bad):
    with pytest.raises(InputError, match="outside the bar"):
        plbar.problem(plbar.uniform_bar(4), plbar.point(bad))


# --- convergence of the FE eigenfrequencies to the analytic bar values --------------------------

def _rel_err(element, mass, n, which):
    a = assemble(plbar.uniform_bar(n, element=element, mass=mass))
    s = two_state(a.M, a.K, a.x)
    if which == "free":     # clamped-free (state II): w_j = (2j - 1) pi / 2
        exact = (2 * np.arange(1, 4) - 1) * np.pi / 2
        w = s.w2[:3]
    else:                   # clamped-clamped (state I): w_j = j pi
        exact = np.arange(1, 4) * np.pi
        w = s.w1[:3]
    return np.abs(w - exact) / exact


RATES = {("P1", "consistent"): 2, ("P1", "lumped"): 2, ("P2", "consistent"): 4, ("P2", "lumped"): 4}


@pytest.mark.parametrize("element,mass", list(RATES))
@pytest.mark.parametrize("which", ["free", "clamped"])
def test_eigenfrequency_convergence_rates(element, mass, which):
    ns = np.array([8, 16, 32, 64])
    errs = np.array([_rel_err(element, mass, n, which)[0] for n in ns])
    rate = -np.polyfit(np.log(1.0 / ns) * -1, np.log(errs), 1)[0]
    assert rate == pytest.approx(RATES[element, mass], abs=0.15)
    assert errs[-1] < (1e-3 if element == "P1" else 1e-7)


def test_consistent_mass_bounds_from_above_lumped_p1_from_below():
    e_c = assemble(plbar.uniform_bar(10, mass="consistent"))
    e_l = assemble(plbar.uniform_bar(10, mass="lumped"))
    w_c = two_state(e_c.M, e_c.K, e_c.x).w2[0]
    w_l = two_state(e_l.M, e_l.K, e_l.x).w2[0]
    assert w_l < np.pi / 2 < w_c


def test_graded_and_per_element_properties():
    x = plbar.graded_nodes(10, 2.0, ratio=0.25)
    assert x[0] == 0 and x[-1] == pytest.approx(2.0) and np.all(np.diff(x) > 0)
    assert (x[-1] - x[-2]) / (x[1] - x[0]) == pytest.approx(0.25)
    # a two-material bar: doubling EA on every element scales the frequencies by sqrt(2)
    b1 = plbar.Bar(plbar.uniform_nodes(6), EA=np.ones(6))
    b2 = plbar.Bar(plbar.uniform_nodes(6), EA=2 * np.ones(6))
    s1 = plbar.problem(b1, plbar.node(1)).system
    s2 = plbar.problem(b2, plbar.node(1)).system
    np.testing.assert_allclose(s2.w2, np.sqrt(2) * s1.w2, rtol=1e-12)


def test_shipped_meshes_equal_generator(tmp_path):
    from pathlib import Path

    from plbar.io import SHIPPED, read_nodes, write_shipped

    shipped = Path(__file__).parents[2] / "meshes"
    write_shipped(tmp_path)
    for name, make in SHIPPED.items():
        assert (shipped / name).read_bytes() == (tmp_path / name).read_bytes(), name
        np.testing.assert_allclose(read_nodes(shipped / name), make(), rtol=0, atol=1e-15)


def test_mesh_file_case_matches_generated_bar():
    from pathlib import Path

    f = Path(__file__).parents[2] / "meshes" / "bar_uniform_8.msh"
    c = plbar.Case(model="fe", mesh_file=str(f))
    np.testing.assert_allclose(c.bar().nodes, plbar.uniform_nodes(8), atol=1e-15)


_M3, _K3, _X3 = np.eye(3), np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1]]), np.arange(1.0, 4.0)


def test_a_free_free_structure_has_a_rigid_body_mode_in_its_free_state():
    """A semi-definite free state (singular to round-off) is a free body (docs/free_body.md): ``w = 0`` exactly."""
    K = 7.1 * np.array([[1.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    s = two_state(3.3 * _M3, K, _X3)
    assert s.rigid == 1 and s.w2[0] == 0.0 and s.w2[1] > 0 and s.w1[0] > 0
    assert np.max(np.abs(K @ s.V2[:, 0])) < 1e-14 * np.abs(K).max()
    assert np.isfinite(s.T0[1])


@pytest.mark.parametrize("M,K,x,match", [
    (_M3, np.array([[2.0, -1, 0], [-1.5, 2, -1], [0, -1, 1]]), _X3, "K is not symmetric"),
    (_M3 + 1e-3 * np.triu(np.ones((3, 3)), 1), _K3, _X3, "M is not symmetric"),
    (_M3, np.ones((3, 2)), _X3, r"K must be a square matrix \(n, n\), got shape \(3, 2\)"),
    (np.ones(3), _K3, _X3, r"M must be a square matrix"),
    (np.eye(4), _K3, _X3, r"M and K must have the same shape, got \(4, 4\) and \(3, 3\)"),
    (_M3, np.where(np.eye(3) == 1, np.nan, _K3), _X3, "K has 3 non-finite entries"),
    (np.diag([1.0, np.inf, 1.0]), _K3, _X3, "M has 1 non-finite entry"),
    (_M3, _K3, _X3[:2], r"x must hold one position per DOF, shape \(3,\), got shape \(2,\)"),
    (_M3, _K3, [0.0, np.nan, 1.0], "x .* non-finite"),
    (np.diag([1.0, -1.0, 1.0]), _K3, _X3, "the mass matrix is not positive definite"),
    (np.diag([1.0, 0.0, 1.0]), _K3, _X3, "the mass matrix is not positive definite"),
    (_M3, np.array([[1.0, -1, 0], [-1, 1, 0], [0, 0, 1]]), _X3,
     "the state I stiffness matrix is not positive definite"),
    (_M3, np.array([[1.0, -1, 0], [-1, 2, -1], [0, -1, 0.1]]), _X3,   # a negative eigenvalue with the contact free
     "the state II stiffness matrix is indefinite"),
    ("M", _K3, _X3, "M must be a square array of numbers"),
])
def test_two_state_refuses_bad_matrices_in_one_line(M, K, x, match):
    """Issue 44: bad matrices give a one-line InputError, not a numpy/LAPACK error or a silent answer."""
    with pytest.raises(InputError, match=match) as err:
        two_state(M, K, x)
    assert "\n" not in str(err.value)


def test_two_state_accepts_round_off_asymmetry_and_symmetrises():
    a = assemble(plbar.uniform_bar(5, element="P2", mass="consistent"))
    K = a.K.copy()
    K[0, 1] *= 1 + 1e-12
    s, s0 = two_state(a.M, K, a.x), two_state(a.M, a.K, a.x)
    np.testing.assert_array_equal(s.K, s.K.T)
    np.testing.assert_allclose(s.w2, s0.w2, rtol=1e-10)
