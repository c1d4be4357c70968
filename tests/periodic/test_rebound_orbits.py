"""Periodic responses with rebounds (restitution e > 0, issue 31): signatures with ``R``, chattering as ``R...RP``.

Every orbit is checked by the certified simulator (:func:`plbar.motion.run`, not the chain): its events at the
predicted times (1e-9 of ``m T``), its return after ``m`` periods (1e-9), its loss per period, and its Floquet
multipliers against a finite-difference Jacobian of the simulator's ``m``-period map (the stability verdict
confirmed by simulation).
"""

from __future__ import annotations

import numpy as np
import pytest

import plbar
from plbar.errors import InputError
from plbar.periodic import (ONE_REBOUND, Signature, admissible, expected_events, find_branches, from_motion,
                            monodromy, multipliers, orbit_series, signature, zero_dwell)
from plbar.periodic.chain import layout
from plbar.periodic.verify import start_of
from plbar.motion import FREE, STUCK, Start, padded, run, steady

E = 0.3
WINDOW = (8.15, 11.5)


@pytest.fixture(scope="module")
def prob():
    return plbar.Case(restitution=E).problem()


@pytest.fixture(scope="module")
def branches(prob):
    """The branches reached from the periodic motions of a simulation from rest across the window."""
    T = np.linspace(*WINDOW, 24)
    r = run(padded(prob), T, 0.0, 500, 40, accounts=False)
    s = steady(r, tol=1e-4)
    seeds = []
    for b in np.flatnonzero(s.kind == 0):
        try:
            seeds.append(from_motion(prob, r, int(b), int(s.m[b])))
        except (plbar.periodic.NotConverged, ValueError):
            pass
    assert len(seeds) >= 5
    return find_branches(prob, WINDOW, (), seeds, kinds="default", m_max=4)


def _sample(branches, per=3):
    """A few points of every branch (its ends and middle)."""
    out = []
    for b in branches:
        for i in sorted({0, len(b) // 2, len(b) - 1})[:per]:
            out.append(b.orbits[i])
    return out


def test_signatures_with_rebounds():
    s = signature("1PR9")
    assert s.letters == "P" + "R" * 9 and str(s) == "1PR9" and s.k == 10 and s.rebounds == 9
    assert s.durations == 11                                   # one dwell, ten free phases
    assert signature("2RR") == Signature(2, (False, False), (True, True))
    assert str(signature("1RPRR").canonical()) == "1PR3"          # rotations: P < R < Z
    assert str(ONE_REBOUND) == "1R"
    # a chattering sequence (rebounds, then the contact sticks) is one family whatever its count of rebounds
    assert signature("1PR9").family == signature("1PR10").family == "1PC"
    assert signature("7PR10PR13").family == "7PCPC" and signature("2RR").family == "2RR"
    assert signature("2R10PR").family == "2PC" and signature("1P").family == "1P"
    for bad in ("1R0", "1Q", "R"):
        with pytest.raises(InputError):
            signature(bad)
    with pytest.raises(InputError, match="restitution"):
        layout(plbar.Case().problem(), signature("1R"))       # a rebound needs e > 0
    with pytest.raises(InputError, match="restitution"):
        plbar.solve(plbar.Case(restitution=0.5, signatures="paper"))


def test_branches_have_rebounds_and_chattering(branches):
    labels = {b.label for b in branches}
    assert any(set(lb[1:]) == {"R"} or lb[1:].startswith("R") for lb in labels)        # rebounds only
    assert any("P" in lb and "R" in lb for lb in labels)                                 # chatter, then stuck
    assert sum(int(b.stable.sum()) for b in branches) > 0
    assert sum(int((~b.stable).sum()) for b in branches) > 0


def _modal(prob, state, x, v):
    """Physical ``x, v`` as the modal state of ``state`` (stuck: state I, the contact held; free: state II)."""
    sy = prob.system
    M = np.asarray(sy.M, float)
    if state == STUCK:
        return np.concatenate([sy.V1.T @ M[:-1, :-1] @ x[:-1], sy.V1.T @ M[:-1, :-1] @ v[:-1]])
    return np.concatenate([sy.V2.T @ M @ x, sy.V2.T @ M @ v])


def _section(o, frac=0.37):
    """The orbit's state at ``t0 = frac T`` from its own segments (exact flows): ``(t0, state, modal y)``; the
    simulator started there with the load's phase ``phi - W t0`` follows the orbit from ``t0``."""
    x, v, st = orbit_series(o).response([frac * o.T])
    state = STUCK if st[0] == 1 else FREE
    return frac * o.T, state, _modal(o.prob, state, x[0], v[0])


def _simulate(prob, o, t0, state, Y, periods, accounts=False):
    """The simulator from the modal states ``Y`` (rows) of ``state`` at the orbit's time ``t0``."""
    pad = padded(prob)
    n = Y.shape[1] // 2
    eta, vel = np.zeros((len(Y), pad.m)), np.zeros((len(Y), pad.m))
    eta[:, :n], vel[:, :n] = Y[:, :n], Y[:, n:]
    W = 2 * np.pi / o.T
    return run(pad, np.full(len(Y), o.T), np.full(len(Y), o.phi - W * t0), periods, periods,
               Start(np.full(len(Y), state), eta, vel), accounts=accounts)


def test_replayed_by_the_simulator(prob, branches):
    """Events at the predicted times (1e-9 m T); from a section inside the orbit the simulator comes back to the
    same state after m periods (1e-9) and loses what the orbit loses."""
    orbs = _sample(branches)
    assert admissible(orbs, tol=1e-9).all()
    pad = padded(prob)
    st = np.zeros(len(orbs), int)
    eta, vel = np.zeros((len(orbs), pad.m)), np.zeros((len(orbs), pad.m))
    for b, o in enumerate(orbs):
        st[b], eta[b], vel[b] = start_of(o, pad.m)
    mmax = max(o.sig.m for o in orbs)
    T = np.array([o.T for o in orbs])
    r = run(pad, T, np.array([o.phi for o in orbs]), mmax + 1, mmax + 1, Start(st, eta, vel), accounts=False)
    worst_t = worst_x = worst_loss = 0.0
    for b, o in enumerate(orbs):
        m = o.sig.m
        sel = r.events["traj"] == b
        te, ke = r.events["time"][sel], r.events["kind"][sel]
        et, ek = expected_events(o)
        assert np.array_equal(ke[:et.size], ek)
        worst_t = max(worst_t, float(np.abs(te[:et.size] - et).max()) / (m * T[b]))
        t0, state, y = _section(o)
        rs = _simulate(prob, o, t0, state, y[None], m, accounts=True)
        assert rs.strobe_state[0, m] == state
        back = _modal(prob, state, rs.strobe_x[0, m], rs.strobe_v[0, m])
        worst_x = max(worst_x, float(np.abs(back - y).max() / np.abs(y).max()))
        loss = rs.loss[0].sum() / m
        w = (prob.system.w1 if state == STUCK else prob.system.w2)
        energy = 0.5 * float(np.sum((w * y[:w.size]) ** 2 + y[w.size:] ** 2))     # the bar's, at the section
        # relative to the loss, or to the energy in the bar where the loss is tiny (orbits whose last rebounds
        # graze: xi_eq ~ 1e-8, the loss 1e-9 of the energy that flows)
        worst_loss = max(worst_loss, abs(loss - o.loss_per_T) / max(o.loss_per_T, 1e-3 * energy))
    assert worst_t <= 1e-9
    assert worst_x <= 1e-9
    assert worst_loss <= 1e-9


def _fd_map(prob, o, h=1e-7):
    """The Jacobian of the simulator's m-period map at a section inside the orbit, by central differences in the
    modal coordinates of the state there (stuck or free)."""
    t0, state, y = _section(o)
    n = y.size
    d = h * max(np.abs(y).max(), 1.0)
    rr = _simulate(prob, o, t0, state, np.concatenate([y + d * np.eye(n), y - d * np.eye(n)]), o.sig.m)
    m = o.sig.m
    assert (rr.strobe_state[:, m] == state).all()
    out = np.array([_modal(prob, state, rr.strobe_x[i, m], rr.strobe_v[i, m]) for i in range(2 * n)])
    return (out[:n] - out[n:]).T / (2 * d)


def test_stability_confirmed_by_simulation(prob, branches):
    """The multipliers from the saltation matrices of Newton's impact law = those of the simulator's map."""
    orbs = [o for o in _sample(branches, per=2) if o.sig.m <= 2][:12]
    verdicts = set()
    worst = 0.0
    for o in orbs:
        mu = multipliers(monodromy(prob, o.sig, o.T, o.phi, o.chain))
        fd = multipliers(_fd_map(prob, o))
        big = np.abs(mu) > 1e-3
        k = int(big.sum())
        assert np.allclose(np.abs(fd[:k]), np.abs(mu[:k]), rtol=1e-4, atol=1e-5), (o.sig, o.T, mu[:k], fd[:k])
        worst = max(worst, float(np.abs(np.abs(fd[0]) - np.abs(mu[0]))))
        stable = np.abs(mu[0]) < 1
        if abs(np.abs(mu[0]) - 1) > 1e-5:        # a verdict the map's accuracy can confirm (not a neutral orbit's)
            assert stable == (np.abs(fd[0]) < 1)
            verdicts.add(bool(stable))
    assert verdicts == {True, False}                             # both verdicts met and confirmed
    assert worst <= 1e-5


def test_one_rebound_closed_form(prob):
    """The class 1R at a period: the closed form's orbits are exact roots of the chain (both phase roots)."""
    orbs = zero_dwell(prob, 6.2, ONE_REBOUND)
    assert orbs and all(o.residual <= 1e-12 for o in orbs)
    assert all(o.free_start and o.z0.size == 2 * prob.system.w2.size for o in orbs)
    ok = admissible(orbs)
    assert ok.any()
    # loss = (1 - e^2) S v_c^2 / 2 (Newton's law), the simulator's loss over a period
    o = [x for x, a in zip(orbs, ok) if a][0]
    S = prob.system.impact_mass
    assert o.dPL == pytest.approx(0.5 * (1 - E * E) * S * o.v_impact[0] ** 2, rel=1e-14)
    pad = padded(prob)
    s0, e0, v0 = start_of(o, pad.m)
    assert s0 == FREE
    r = run(pad, [o.T], [o.phi], 2, 2, Start(np.array([s0]), e0[None], v0[None]))
    assert r.loss[0, 1] == pytest.approx(o.loss_per_T, rel=1e-9)


@pytest.mark.slow
def test_cli_run_with_restitution(tmp_path, capsys):
    """``plbar run --restitution 0.3``: the responses with rebounds in paths.csv and the summary, exported by row."""
    import csv
    import json

    from plbar.cli import main

    out = tmp_path / "run"
    assert main(["run", "--restitution", "0.3", "--out", str(out), "-q", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["summary"]["n_paper_branches"] == 0                 # no paper's class with rebounds
    labels = {b["signature"] for b in got["summary"]["branches"]}
    assert "1R" in labels and any(lb.startswith("1PR") for lb in labels)
    rows = list(csv.DictReader(open(out / "paths.csv")))
    assert rows and all("R" in r["signature"] for r in rows)
    row = next(r for r in rows if r["signature"].startswith("1PR"))
    assert main(["export", "--from", str(out), "--branch", row["branch"], "--index", "0", "--steps", "8", "-q",
                 "--json"]) == 0
    info = json.loads(capsys.readouterr().out)["summary"]
    assert info["signature"] == row["signature"] and info["dPL"] == pytest.approx(float(row["loss_per_T"]), rel=1e-9)


def test_studies_of_the_papers_class_refuse_rebounds(tmp_path, capsys):
    """sweep-loads and refine follow the paper's class (a plastic impact): with e > 0 they refuse in one line and
    name the survey that takes a restitution (refine had silently solved the plastic case)."""
    from plbar.cli import main

    for cmd, hint in ((["sweep-loads"], "survey --positions"), (["refine", "-N", "3", "4"], "survey -N")):
        assert main(cmd + ["--restitution", "0.3", "--out", str(tmp_path / cmd[0]), "-q"]) == 2
        err = capsys.readouterr().err
        assert "restitution = 0.3" in err and hint in err
        assert not (tmp_path / cmd[0]).exists()
