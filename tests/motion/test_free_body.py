"""A free body: a free state with rigid-body modes (``w = 0``), started from a given state, with or without a load.

* Siconos' ``ImpactingBar`` (siconos-tutorials, examples/mechanics/FEM/ImpactingBar, its parameters of
  ``UserDefinedParameter-ref.hpp`` and its reference output ``ImpactingBar.ref``, stored as
  tests/data/peers/siconos_impacting_bar.npz): a free-free P1 bar with consistent mass, thrown at a rigid wall
  at 0.1 m/s, plastic impact on its first node.  Siconos integrates it by Moreau-Jean's time stepping
  (theta = 1/2, h = 2e-6); plbar exactly between events.  The comparison goes through a replica of that scheme
  written here: it reproduces Siconos' output to round-off, and as ``h -> 0`` its energy after the first impact and
  its release time tend to plbar's (the difference of the two discretisations is the time step's).
* An independent route: the test's solve_ivp integrator (tests/event_integrator.py) on a free-free chain thrown at
  the stop, with and without a harmonic load, plastic and with rebounds: event times 1e-9, energy 1e-12.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import plbar
from plbar.errors import InputError
from plbar.model.structure import contact_coordinates
from plbar.motion import given, run

from tests.event_integrator import motion

REF = Path(__file__).parents[1] / "data" / "peers" / "siconos_impacting_bar.npz"
N, E, A, L, RHO = 100, 210e9, 0.000314, 1.0, 7800.0     # UserDefinedParameter-ref.hpp (l = L / nDof)
T0, X0, V0 = 1e-8, 5e-5, -0.1                            # its start time, initial position and velocity


def _siconos_matrices():
    """Siconos' matrices as its ImpactingBar.cpp builds them: nDof nodes, nDof - 1 elements of length L / nDof."""
    l = L / N
    M, K = np.zeros((N, N)), np.zeros((N, N))
    for e in range(N - 1):
        i = [e, e + 1]
        M[np.ix_(i, i)] += RHO * A * l * np.array([[1 / 3, 1 / 6], [1 / 6, 1 / 3]])
        K[np.ix_(i, i)] += E * A / l * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return M, K


def _moreau_jean(M, K, h, t_end, theta=0.5):
    """Moreau-Jean's scheme as Siconos' MoreauJeanOSI(theta, gamma = 0) with an LCP at velocity level, e = 0:
    ``(M + h^2 theta^2 K) v+ = M v - h K q - h^2 theta (1 - theta) K v + p e_0``, the contact active where
    ``q_0 <= 0``, ``v+_0 >= 0 _|_ p >= 0``; ``q+ = q + h (theta v+ + (1 - theta) v)``.
    Returns rows ``(t, q_0, v_0, energy, p)``."""
    q, v = np.full(N, X0), np.full(N, V0)
    Wi = np.linalg.inv(M + h * h * theta * theta * K)
    out = [(T0, q[0], v[0], 0.5 * (q @ K @ q + v @ M @ v), 0.0)]
    for k in range(1, int(np.floor((t_end - T0) / h))):
        vf = Wi @ (M @ v - h * K @ q - h * h * theta * (1 - theta) * K @ v)
        p = -vf[0] / Wi[0, 0] if q[0] <= 0 and vf[0] < 0 else 0.0
        vn = vf + Wi[:, 0] * p
        q, v = q + h * (theta * vn + (1 - theta) * v), vn
        out.append((T0 + k * h, q[0], v[0], 0.5 * (q @ K @ q + v @ M @ v), p))
    return np.array(out)


def _siconos_bar():
    M, K = _siconos_matrices()
    r = np.zeros(N)
    r[0] = -1.0                          # Siconos' y = q_0 >= 0 is plbar's u = -q_0 <= 0
    st = plbar.Structure(M, K, r, np.zeros(N))
    B = contact_coordinates(st).B
    y0, yv = np.linalg.solve(B, np.full(N, X0)), np.linalg.solve(B, np.full(N, V0))
    return st, plbar.problem(st), y0, yv


def test_the_free_state_of_a_free_bar_has_one_rigid_body_mode():
    st, prob, _, _ = _siconos_bar()
    s = prob.system
    assert s.rigid == 1 and s.w2[0] == 0.0 and s.w1[0] > 0
    Z = s.V2[:, 0]
    assert np.max(np.abs(s.K @ Z)) < 1e-9 * np.max(np.abs(s.K)) * np.max(np.abs(Z))
    assert abs(Z @ s.M @ Z - 1.0) < 1e-12
    assert np.allclose(np.abs(st.physical(Z)), np.sqrt(1 / np.sum(st.M)), rtol=1e-10)   # a translation


def test_the_replica_of_moreau_jean_is_siconos_reference_output():
    ref = np.load(REF)
    M, K = _siconos_matrices()
    mj = _moreau_jean(M, K, 2e-6, 0.0015)
    assert mj.shape[0] == ref["t"].size
    assert np.max(np.abs(mj[:, 0] - ref["t"])) < 1e-15
    assert np.max(np.abs(mj[:, 1] - ref["q0"])) < 1e-15
    assert np.max(np.abs(mj[:, 2] - ref["v0"])) < 1e-11
    assert np.max(np.abs(mj[:, 3] - ref["energy"])) < 1e-11 * ref["energy"][0]   # Siconos checks its own to 1e-11


def test_siconos_impacting_bar_energy_after_the_first_impact_and_release():
    """plbar's exact motion against Siconos' reference and the replica's limit ``h -> 0``."""
    ref = np.load(REF)
    st, prob, y0, yv = _siconos_bar()
    sim = plbar.simulate(prob, T=1.5e-3, phi=0.0, x0=y0, v0=yv, state=2, n_periods=1.0, t0=T0)
    ev = sim.events
    assert list(ev["kind"]) == [2, 1]                           # one plastic impact, one release, in 1.5 ms
    t_hit, t_open = ev["time"]
    assert abs(t_hit - (T0 + X0 / -V0)) < 1e-15                 # a rigid translation up to the wall
    S = 1.0 / np.linalg.inv(st.M)[0, 0]                         # the impact mass (Eq. (14))
    loss = ev["loss"][0]
    assert abs(loss - 0.5 * S * V0 ** 2) < 1e-12 * loss
    E0 = 0.5 * V0 ** 2 * np.sum(st.M)
    assert abs(sim.energy0 - E0) < 1e-14 * E0 and abs(sim.energy - (E0 - loss)) < 1e-13 * E0
    # Siconos at h = 2e-6 (its reference): the same energy before, 2.06 x plbar's loss at its impact step (the
    # element modes, w_max h = 3.6, are not resolved), released 7 us later
    assert abs(ref["energy"][0] - E0) < 1e-12 * E0
    sic_loss = ref["energy"][0] - ref["energy"][-1]
    assert 2.0 < sic_loss / loss < 2.1
    sic_open = ref["t"][np.flatnonzero(ref["lam"] > 0)[-1] + 1]
    assert 0 < sic_open - t_open < 1e-5
    # the replica's limit: its loss and release tend to plbar's as h -> 0
    M, K = _siconos_matrices()
    gaps = []
    for h in (2e-6, 2e-7, 5e-8):
        mj = _moreau_jean(M, K, h, 9.2e-4)
        opened = mj[np.flatnonzero(mj[:, 4] > 0)[-1] + 1, 0]
        gaps.append((abs(mj[0, 3] - mj[-1, 3] - loss) / loss, abs(opened - t_open)))
    assert gaps[-1][0] < 2e-3 and gaps[-1][1] < 2e-7
    assert gaps[0][0] > gaps[1][0] > gaps[2][0]
    # the compiled simulator (from t = 0: the same motion shifted by T0)
    r = run(prob, np.array([1.5e-3]), periods=1, record=1, start=given(prob, y0, yv))
    real = r.events[r.events["loss"] > 1e-20 * loss]
    assert abs(real["time"][0] + T0 - t_hit) < 1e-15 and abs(real["loss"][0] - loss) < 1e-12 * loss
    opens = r.events[r.events["kind"] == 1]["time"]
    assert abs(opens[-1] + T0 - t_open) < 1e-12
    assert abs(r.losses[0] - loss) < 1e-12 * loss and abs(r.energy_residual[0]) < 1e-13


def _free_chain(n=6, e=0.0, q=None):
    """A free-free chain of ``n`` unit masses and springs (no support), the stop on its last mass at ``u <= 0``."""
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[0, 0] = K[-1, -1] = 1.0
    r = np.zeros(n)
    r[-1] = 1.0
    return plbar.Structure(np.eye(n) * np.linspace(1.0, 1.5, n), 3.0 * K, r, np.zeros(n) if q is None else q,
                           restitution=e)


@pytest.mark.parametrize("e, loaded", [(0.0, False), (0.0, True), (0.6, True)])
def test_a_free_chain_thrown_at_the_stop_is_the_test_integrator_s_motion(e, loaded):
    n = 6
    q = 0.4 * np.linspace(1, -1, n) if loaded else None
    st = _free_chain(n, e, q)
    prob = plbar.problem(st)
    assert prob.system.rigid == 1
    x0, v0 = -np.linspace(0.3, 0.1, n), np.full(n, 0.5)
    T, periods = 5.0, 8
    times, kinds, losses, x_end, v_end = motion(st, T, periods * T, x0, v0, True)
    assert np.sum(kinds == 2) + np.sum(kinds == 3) >= 2 and (e > 0 or np.sum(kinds == 1) >= 1)
    r = run(prob, np.array([T]), periods=periods, record=periods, start=given(prob, x0, v0))
    assert r.status[0] == 0
    ev = r.events
    if e > 0:       # the rebounds accumulate (chattering, plbar's kind 4 ends them), which the test's integrator
        t_stick = ev["time"][ev["kind"] == 4][0]           # does not follow: compare what comes before
        keep = times < t_stick - 1e-3
        times, kinds, losses = times[keep], kinds[keep], losses[keep]
        ev = ev[:times.size]
        assert times.size >= 10
    assert np.array_equal(ev["kind"], kinds)
    assert np.max(np.abs(ev["time"] - times)) < 1e-9
    assert np.max(np.abs(ev["loss"] - losses)) < 1e-9 * losses.max()
    if e == 0:
        assert np.max(np.abs(r.strobe_x[0, -1] - x_end)) < 1e-8 * np.abs(x_end).max()
    work_scale = max(abs(r.work[0]), r.energy0[0])
    assert abs(r.work[0] - r.losses[0] - (r.energy_end[0] - r.energy0[0])) < 1e-12 * work_scale
    if e > 0:
        return      # plbar.simulate, the independent replay, is plastic only (the paper's impact law)
    sim = plbar.simulate(prob, T, 0.0, x0, v0, state=2, n_periods=periods)
    assert np.array_equal(sim.events["kind"][:kinds.size], kinds)
    assert np.max(np.abs(sim.events["time"][:kinds.size] - times)) < 1e-9


def test_a_free_state_with_mass_proportional_damping_is_refused():
    st = _free_chain()
    with pytest.raises(InputError, match="rigid body"):
        plbar.problem(plbar.Structure(st.M, st.K, st.contact, st.q, rayleigh=(0.1, 0.0)))


def test_a_constant_load_that_pushes_the_rigid_body_accelerates_it_one_it_can_hold_is_held():
    """A load on the rigid motion moves it with ``g_r = v_r^T q_s`` (tests/motion/test_falling_bar.py follows it);
    the elastic part's equilibrium holds the rest: ``K x2 = q_s - M v_r g_r``, with no rigid-body part."""
    st = _free_chain()
    push = np.ones(st.n)
    p = plbar.problem(plbar.Structure(st.M, st.K, st.contact, st.q, q_s=push))
    Z, g = p.system.V2[:, 0], p.statics.accel
    assert g[0] == pytest.approx(Z @ push, rel=1e-14) and np.all(g[1:] == 0.0)
    assert np.allclose(st.K @ p.statics.x2, push - st.M @ Z * g[0], atol=1e-12)
    assert abs(Z @ st.M @ p.statics.x2) < 1e-12
    held = np.array([1.0, 0, 0, 0, 0, -1.0])            # a self-equilibrated pair: the chain stretched
    p = plbar.problem(plbar.Structure(st.M, st.K, st.contact, st.q, q_s=held))
    x2 = p.statics.x2
    assert p.statics.accel is None
    assert np.allclose(st.K @ x2, held, atol=1e-12)


def test_a_start_past_the_stop_is_refused():
    st, prob, y0, yv = _siconos_bar()
    bad = y0.copy()
    bad[-1] = 1e-5
    with pytest.raises(InputError, match="past the stop"):
        given(prob, bad, yv)


def test_a_bar_under_no_load_moves_freely_from_a_given_start():
    """The issue's example ``plbar.problem(bar, plbar.point(0.5, 0.0))`` is taken: a clamped bar released
    stretched away from the stop; both simulators agree, and the energy is the start's less the impact losses."""
    bar = plbar.Bar(np.linspace(0.0, 1.0, 9))
    prob = plbar.problem(bar, plbar.point(0.5, 0.0))
    n = prob.system.n
    x0, v0 = -0.01 * np.linspace(0.0, 1.0, n + 1)[1:], np.zeros(n)
    sim = plbar.simulate(prob, 1.0, 0.0, x0, v0, state=2, n_periods=3)
    r = run(prob, np.array([1.0]), periods=3, record=3, start=given(prob, x0, v0))
    assert sim.work == 0.0 and r.work[0] == 0.0
    assert np.array_equal(sim.events["kind"], r.events["kind"]) and sim.events.size >= 3
    assert np.max(np.abs(sim.events["time"] - r.events["time"])) < 1e-10
    lost = sim.events["loss"][sim.events["kind"] == 2].sum()
    assert lost > 0 and abs(sim.energy0 - lost - sim.energy) < 1e-12 * sim.energy0
    assert abs(r.energy_residual[0]) < 1e-13
