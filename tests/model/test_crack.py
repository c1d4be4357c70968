"""A breathing crack in an FE bar (issue 41 item 3, plbar.model.crack).

* The split node, against assemblies written here: held (the faces tied) the cracked bar is the whole bar, its
  matrices exactly; open, it is its two parts, each assembled on its own by scikit-fem in the test, its
  frequencies theirs, the outer part's rigid mode constant on it and zero on the inner part.
* The theorem of :func:`plbar.model.modes.floats` (a free state whose rigid mode the contact pushes has no periodic
  motion with a contact) against brute force: the paper's scan over a wide window finds no admissible point, and
  the motion from rest (the test's solve_ivp integrator and plbar's simulator, agreeing event by event) leaves the
  crack for good: every contact impulse pushes the outer part away, its momentum never returns.
* An independent route for the crack between two clamps: plbar's motion from rest against the test's integrator
  (event times 1e-9, losses, end state, the energy budget 1e-12), plastic and with rebounds.
* The crack's xi_eq is a mesh artefact: it halves with the element size (the continuum's faces carry no mass).
"""

from __future__ import annotations

import numpy as np
import pytest

import plbar
from plbar.errors import InputError
from plbar.model import Bar, assemble, bar_structure, point
from plbar.motion import padded, run, steady

from event_integrator import IMPACT, REBOUND, assert_same_motion, motion


def _skfem_part(x, clamped: bool, element: str, mass: str):
    """A bar on the vertices ``x`` assembled by scikit-fem here: ``(K, M)`` over its DOFs sorted by position, the
    vertex at ``x[0]`` dropped when ``clamped``."""
    import skfem
    from skfem.helpers import dot, grad

    basis = skfem.Basis(skfem.MeshLine(np.asarray(x, float)),
                        skfem.ElementLineP1() if element == "P1" else skfem.ElementLineP2())
    K = skfem.asm(skfem.BilinearForm(lambda u, v, w: dot(grad(u), grad(v))), basis).toarray()
    M = skfem.asm(skfem.BilinearForm(lambda u, v, w: u * v), basis).toarray()
    if mass == "lumped":
        M = np.diag(M.sum(axis=1))
    order = np.argsort(basis.doflocs[0], kind="stable")
    keep = order[1:] if clamped else order
    return K[np.ix_(keep, keep)], M[np.ix_(keep, keep)]


@pytest.mark.parametrize("element", ["P1", "P2"])
@pytest.mark.parametrize("mass", ["lumped", "consistent"])
def test_the_crack_is_the_whole_bar_held_and_its_two_parts_open(element, mass):
    x = np.linspace(0.0, 1.0, 9)
    cracked, whole = assemble(Bar(x, element, mass, crack_at=0.375)), assemble(Bar(x, element, mass))
    i = cracked.crack
    assert cracked.n == whole.n + 1 and cracked.x[i] == cracked.x[i + 1] == 0.375
    r = cracked.contact_row()
    assert r[i] == 1.0 and r[i + 1] == -1.0 and np.count_nonzero(r) == 2
    tie = np.zeros((cracked.n, whole.n))                  # the faces tied: the outer face moves with the inner one
    tie[np.arange(cracked.n), np.r_[np.arange(i + 1), np.arange(i, whole.n)]] = 1.0
    assert np.array_equal(tie.T @ cracked.K @ tie, whole.K)
    assert np.max(np.abs(tie.T @ cracked.M @ tie - whole.M)) <= 1e-15 * np.abs(whole.M).max()
    inner, outer = np.arange(i + 1), np.arange(i + 1, cracked.n)
    assert not np.any(cracked.K[np.ix_(inner, outer)]) and not np.any(cracked.M[np.ix_(inner, outer)])
    for part, xs, clamped in ((inner, x[x <= 0.375], True), (outer, x[x >= 0.375], False)):
        K, M = _skfem_part(xs, clamped, element, mass)
        assert np.max(np.abs(cracked.K[np.ix_(part, part)] - K)) <= 1e-12 * np.abs(K).max()
        assert np.max(np.abs(cracked.M[np.ix_(part, part)] - M)) <= 1e-15 * np.abs(M).max()
    prob = plbar.problem(bar_structure(Bar(x, element, mass, crack_at=0.375), point(1.0)))
    s = prob.system
    assert s.rigid == 1 and s.floating
    phys = prob.structure.physical(s.V2[:, 0])            # the rigid mode, on the DOFs
    assert np.abs(phys[inner]).max() < 1e-13 * abs(phys[-1]) and np.ptp(phys[outer]) < 1e-13 * abs(phys[-1])
    w_parts = np.sort(np.concatenate([np.sqrt(np.abs(np.linalg.eigvals(np.linalg.solve(*_skfem_part(
        xs, c, element, mass)[::-1]))).real) for xs, c in ((x[x <= 0.375], True), (x[x >= 0.375], False))]))
    assert np.max(np.abs(s.w2 - w_parts)) < 1e-7 * w_parts.max()


def test_a_crack_between_two_clamps_is_held_in_both_states():
    bar = Bar(np.linspace(0.0, 1.0, 9), "P1", "consistent", crack_at=0.5, supports="clamped-clamped")
    a = assemble(bar)
    assert a.n == bar.n_dofs == 8 and a.x.max() < 1.0
    prob = plbar.problem(bar_structure(bar, point(0.25)))
    assert prob.system.rigid == 0 and not prob.system.floating
    K, M = (A[:-1, :-1] for A in _skfem_part(np.linspace(0.0, 1.0, 9), True, "P1", "consistent"))
    w_whole = np.sqrt(np.linalg.eigvals(np.linalg.solve(M, K)).real.min())   # held: the whole bar, both ends clamped
    assert abs(prob.system.T0[0] - 2 * np.pi / w_whole) < 1e-12 * prob.system.T0[0]
    assert not plbar.Case().problem().system.floating


@pytest.mark.parametrize("kw, match", [
    (dict(crack_at=0.3), "interior vertex"),
    (dict(crack_at=1.0), "interior vertex"),
    (dict(crack_at=0.5, mass="redistributed", point_masses=((1.0, 0.1),)), "redistributed"),
    (dict(crack_at=0.5, point_masses=((0.5, 0.1),)), "one face"),
    (dict(crack_at=0.5, supports="clamped-clamped", point_masses=((1.0, 0.1),)), "clamp"),
    (dict(supports="clamped-clamped"), "crack"),
    (dict(crack_at=0.5, supports="pinned-pinned"), "supports"),
])
def test_a_bad_crack_is_refused(kw, match):
    kw = {"mass": "lumped", **kw}
    with pytest.raises(InputError, match=match):
        Bar(np.linspace(0.0, 1.0, 9), **kw)


def test_loads_and_models_a_crack_does_not_take_are_refused():
    bar = Bar(np.linspace(0.0, 1.0, 9), crack_at=0.5)
    with pytest.raises(InputError, match="at the crack"):
        bar_structure(bar, point(0.5))
    with pytest.raises(InputError, match="clamped end"):
        bar_structure(Bar(np.linspace(0.0, 1.0, 9), crack_at=0.5, supports="clamped-clamped"), point(1.0))
    for model in ("chain", "continuum", "beam"):
        with pytest.raises(InputError, match="crack_at"):
            plbar.Case(model=model, crack_at=0.5)


def test_a_cracked_bars_loads_avoid_the_crack():
    """The default load moves off a crack at mid-bar (to the outer part's middle); the load study's positions skip
    the crack and a far clamp; sweep-loads (a bar against a stop at x = L) refuses a crack by name."""
    from plbar.studies.loads import sweep_loads
    from plbar.studies.survey.loads import load_positions

    c = plbar.Case(model="fe", n=8, crack_at=0.5, supports="clamped-clamped")
    assert c.load_points == ((0.75, 1.0),) and plbar.Case(model="fe").load_points == ((0.5, 1.0),)
    s = load_positions(c, 2)
    assert s.size == 16 - 2 and 0.5 not in s and 1.0 not in s and 0.4375 in s
    with pytest.raises(InputError, match="sweep-loads"):
        sweep_loads(c)


def test_the_case_of_a_crack_round_trips_and_the_default_has_none():
    c = plbar.Case(model="fe", crack_at=0.5, supports="clamped-clamped", load_points=((0.25, 1.0),))
    d = c.to_dict()
    assert d["crack_at"] == 0.5 and d["supports"] == "clamped-clamped"
    assert plbar.Case(**d).to_dict() == d
    assert "crack_at" not in plbar.Case().to_dict() and "crack_at" not in plbar.Case(model="fe").to_dict()
    assert c.bar().crack_at == 0.5 and c.dofs == 8


# -- the theorem: a floating free state has no periodic motion with a contact ------------------------------------------

def _floating():
    # consistent mass: the end force reaches the faces at once (a lumped chain feels it only as t^8, which an
    # integrator cannot tell from round-off at the start)
    return bar_structure(Bar(np.linspace(0.0, 1.0, 9), "P1", "consistent", crack_at=0.5), point(1.0))


def test_a_floating_crack_has_no_periodic_contact_by_brute_force():
    """The theorem's answer (plbar.solve refuses, by name) against the paper's scan over a window twice the
    default's each way: not one admissible point."""
    st = _floating()
    with pytest.raises(InputError, match="no periodic response with a contact"):
        plbar.solve(plbar.Case(structure=st))
    prob = plbar.problem(st)
    T0I, T0II = prob.system.T0
    paths = plbar.find_paths(prob, plbar.Domain((0.0, T0I), (0.0, T0II)), (120, 120))
    assert sum(len(b.T) for b in paths.branches) == 0


@pytest.mark.parametrize("T", [1.3, pytest.param(3.1, marks=pytest.mark.slow)])
def test_the_floating_part_leaves_the_crack_for_good(T):
    """From rest, held: the test's integrator and plbar's simulator agree event by event, every impact pushes the
    outer part away (its momentum along the rigid mode grows), and after a few contacts none comes again."""
    st = _floating()
    prob = plbar.problem(st)
    periods = 16
    times, kinds, losses, x_end, v_end = motion(st, T, periods * T, np.zeros(st.n), np.zeros(st.n), False)
    r = run(padded(prob), np.array([T]), 0.0, periods, periods)
    assert r.status[0] == 0 and np.array_equal(r.events["kind"], kinds)
    assert np.max(np.abs(r.events["time"] - times)) < 1e-9 and abs(r.energy_residual[0]) < 1e-12
    assert times.size and times.max() < 0.5 * periods * T         # none in the last half
    outer = np.flatnonzero(prob.structure.physical(prob.system.V2[:, 0]))
    p_end = float(np.sum((st.M @ v_end)[outer]))                  # the outer part's momentum at the end
    W = 2 * np.pi / T                                             # its share of the harmonic force's impulse
    f_out = float(np.sum(st.q[outer]))
    harmonic = f_out * np.sin(W * periods * T) / W
    assert p_end - harmonic > 0                                   # the contacts' net impulse: away from the clamp


# -- an independent route between two clamps -------------------------------------------------------------------------

@pytest.mark.parametrize("mass, e, gap", [("lumped", 0.0, 0.0), ("consistent", 0.0, 0.0), ("consistent", 0.8, 0.0),
                                          ("lumped", 0.0, 0.02), ("lumped", 0.0, -0.02)])
def test_a_crack_between_two_clamps_is_the_integrators(mass, e, gap):
    """Plastic and with rebounds; a crack open at rest (gap > 0) and one squeezed shut (gap < 0: held in its static
    equilibrium with a compressive reaction)."""
    st = bar_structure(Bar(np.linspace(0.0, 1.0, 7), "P1", mass, crack_at=0.5, supports="clamped-clamped"),
                       point(1 / 6), restitution=e, gap=gap)
    prob = plbar.problem(st)
    T, periods = 1.9, 6
    r = run(padded(prob), np.array([T]), 0.0, periods, periods)
    assert (r.events["kind"] == (REBOUND if e else IMPACT)).sum() >= periods
    assert_same_motion(st, r, T, periods, state=1 if gap > 0 else 0)


def test_the_cracks_xi_eq_halves_with_the_element_size():
    """The faces' plastic impact loses the relative kinetic energy of their nodes' shares of the element mass, O(h):
    xi_eq of the motion at T = 5 (Rayleigh beta = 0.005, settled on a periodic orbit) halves as N doubles."""
    xi = []
    for n in (16, 32, 64):
        c = plbar.Case(model="fe", n=n, crack_at=0.5, supports="clamped-clamped", load_points=((0.25, 1.0),),
                       rayleigh=(0.0, 0.005))
        s = steady(run(padded(c.problem()), np.array([5.0]), 0.0, 600, 100))
        assert s.kind[0] == 0
        xi.append(float(s.xi_eq[0]))
    ratios = np.array(xi[:-1]) / np.array(xi[1:])
    assert np.all((1.6 < ratios) & (ratios < 2.2)), (xi, ratios)


# -- the front door: export, CLI ---------------------------------------------------------------------------------------

def test_a_cracked_bars_export_opens_at_the_crack():
    """The exported mesh has the crack's two faces as two points of no common cell; the displacement on them is the
    DOFs' (x = B y of the contact coordinates), their difference the opening; the nodal kinetic energies sum to the
    kinetic energy."""
    from plbar import io as pio

    c = plbar.Case(model="fe", n=8, crack_at=0.5, supports="clamped-clamped", load_points=((0.25, 1.0),),
                   signatures="paper", grid=(60, 60))
    res = plbar.solve(c)
    b = max(res.paths.branches, key=lambda b: b.xi.max())
    d = pio.response_data(b.orbits.take([0]), {"branch": b.id, "index": 0}, steps=16)
    faces = np.flatnonzero(d.points == 0.5)
    assert faces.size == 2 and not any(set(faces) <= set(cell) for cell in d.cells.tolist())
    assert d.points[0] == 0.0 and d.points[-1] == 1.0                       # both clamps, held at 0
    u = d.point_data["displacement"]
    assert not np.any(u[:, [0, -1]])
    opening = u[:, faces[1]] - u[:, faces[0]]
    free = d.field_data["state"] == 2
    assert np.any(free) and np.allclose(opening[free], d.field_data["gap"][free], rtol=0, atol=1e-14)
    assert np.all(opening[~free] == 0.0) or np.max(np.abs(opening[~free])) < 1e-14
    ke = d.point_data["kinetic_energy_nodal"].sum(axis=1)
    assert np.allclose(ke, d.field_data["kinetic_energy"], rtol=1e-12, atol=1e-15)


def test_the_cli_takes_a_crack_and_answers_a_floating_one_by_the_theorem(tmp_path):
    from plbar.cli import main

    out = tmp_path / "run"
    assert main(["run", "--model", "fe", "-N", "6", "--crack-at", "0.5", "--supports", "clamped-clamped",
                 "--load-at", "0.25", "--signatures", "paper", "--grid", "60", "60", "--no-plot", "--quiet",
                 "--out", str(out)]) == 0
    import json

    summary = json.loads((out / "summary.json").read_text())
    assert summary["case"]["crack_at"] == 0.5 and summary["case"]["supports"] == "clamped-clamped"
    assert main(["run", "--model", "fe", "-N", "6", "--crack-at", "0.5", "--load-at", "1", "--no-plot", "--quiet",
                 "--out", str(tmp_path / "floating")]) == 2


def test_a_cracks_case_file_round_trips():
    from plbar.app.casefile import dump_case, loads_case

    c = plbar.Case(model="fe", n=8, crack_at=0.5, supports="clamped-clamped", load_points=((0.25, 1.0),), gap=0.01)
    text = dump_case(c)
    assert "crack_at = 0.5" in text and 'supports = "clamped-clamped"' in text
    back = loads_case(text)
    back = back[0] if isinstance(back, tuple) else back
    assert back.to_dict() == c.to_dict()
    with pytest.raises(InputError, match="supports"):
        plbar.Case(structure=c.problem().structure, supports="clamped-clamped")
