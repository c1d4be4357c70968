"""Short reprs: every result object prints its class, sizes and ranges, never whole matrices."""

import dataclasses

import numpy as np
import pytest

import plbar
from plbar.check import simulate
from plbar.paths import Trace
from plbar.response import coefficients, find_response, period_map
from plbar.util.reprs import arr, build, listing, rng, value

LIMIT = 2000


def test_helpers():
    assert arr(np.array([3.0, -1.0, 2.0])) == "shape (3,) in [-1, 3]"
    assert arr(np.zeros((2, 4))) == "shape (2, 4) in [0, 0]"
    assert arr(np.array([True, False, True])) == "shape (3,), 2 true"
    assert arr(np.array([1j, -2.0])) == "shape (2,) complex, |.| in [1, 2]"
    assert arr(np.zeros(0)) == "shape (0,)"
    assert rng([np.nan, 1.0, 2.5]) == "[1, 2.5]" and rng([]) == "[]"
    assert value(np.eye(500)) == "shape (500, 500) in [0, 1]"
    assert value(0.1 + 0.2) == "0.3" and value(3) == "3" and value(None) == "None" and value("a") == "'a'"
    assert value(tuple(range(1000))) == "<tuple, len 1000>"
    assert build("X", {"a": 1, "b": "[0, 1]"}) == "X(a=1, b=[0, 1])"
    assert build("X", {}, ["l1", "l2"]) == "X()\n  l1\n  l2"
    assert listing(map(str, range(8)), 3) == ["0", "1", "2", "... 5 more"]
    assert listing(["a"], 3) == ["a"]


@pytest.fixture(scope="module")
def fe8():
    return plbar.solve(plbar.Case(signatures="paper", model="fe", n=8, grid=(60, 60)))


def _check(obj, name, *parts):
    r = repr(obj)
    assert r.startswith(name + "("), r[:200]
    assert len(r) < LIMIT, (name, len(r))
    assert "array(" not in r
    for p in parts:
        assert p in r, (name, p, r)
    return r


def test_reprs_of_the_fe_solve(fe8):
    p = fe8.paths
    b = max(fe8.paths.branches, key=len)
    s = p.prob.system
    n = s.n
    _check(p, "Paths", f"branches={len(p.branches)}", f"points={sum(len(x) for x in p.branches)}",
           "grid=(60, 60)", f"... {len(p.branches) - 5} more")
    _check(p.prob, "Problem", f"n={n}", f"T0=({s.T0[0]:.6g}, {s.T0[1]:.6g})", p.prob.bar.describe(),
           p.prob.load.describe())
    _check(s, "TwoStateSystem", f"n={n}", f"modes=({n - 1}, {n})", "lumped=True")
    _check(p.prob.asm, "Assembled", f"n={n}", f"K=({n}, {n})", "CellBasis")
    _check(b, "Branch", f"id={b.id}", f"points={len(b)}", f"T={rng(b.T)}", f"xi={rng(b.xi)}", repr(b.ends))
    _check(b.orbits, "Orbits", f"P={len(b)}", f"n={n}", f"T={rng(b.T)}", f"phi={rng(b.phi)}")
    _check(b.damping, "Damping", f"P={len(b)}", f"xi={rng(b.xi)}", f"dPL={rng(b.dPL)}")
    _check(b.adm, "Admissibility", f"P={len(b)}", f"ok={int(b.adm.ok.sum())}/{len(b)}")
    pm = period_map(p.prob, b.T1, b.T2)
    _check(pm, "PeriodMap", f"B={len(b)}", f"T1={rng(b.T1)}", f"Z=({len(b)}, {2 * (n - 1)}, 2)")
    _check(coefficients(p.prob, b.T1, b.T2), "Coefficients", f"B={len(b)}", f"T2={rng(b.T2)}")
    j = len(b) // 2
    r = find_response(p.prob, T=float(b.T[j]), T1_guess=float(b.T1[j]))
    _check(r, "Response", f"T={r.T:.6g}", f"xi={r.xi:.6g}", f"n={n}")
    rec = np.linspace(0.0, 3 * r.T, 3000)
    sim = simulate(p.prob, r.T, r.phi, r.x0, r.xdot0, n_periods=3, record=rec)
    _check(sim, "Simulation", "impacts=3", "strobes=3", "history=3000 samples", f"n={n}")
    _check(sim.history, "History", "samples=3000", f"n={n}")


def test_paths_repr_stays_short_with_600_branches(fe8):
    p = fe8.paths
    many = dataclasses.replace(p, branches=tuple(p.branches) * (600 // len(p.branches) + 1))
    r = _check(many, "Paths", f"branches={len(many.branches)}", f"... {len(many.branches) - 5} more")
    assert len(many.branches) >= 600 and len(r) < 1500
    assert len(r.splitlines()) == 7


def test_trace_repr():
    P = np.c_[np.linspace(0.1, 0.9, 5000), np.linspace(1.0, 2.0, 5000)]
    t = Trace(P, {k: k for k in range(3000)}, ("domain edge", "closed loop"), 123)
    _check(t, "Trace", "points=5000", "T1=[0.1, 0.9]", "T2=[1, 2]", "grid_edges=3000", "nevals=123")


def test_response_data_and_files_reprs(fe8, tmp_path):
    pytest.importorskip("pyvista")
    from plbar import io as pio

    b = max(fe8.paths.branches, key=lambda b: b.xi.max())
    d = pio.response_data(b.orbits.take([0]), {"branch": b.id, "index": 0}, periods=2, steps=40)
    _check(d, "ResponseData", f"points={fe8.prob.system.n + 1}", "cells=8 line", "steps=80", "displacement",
           "stress_nodal", f"branch: {b.id}")
    f = pio.write_data(d, tmp_path, format="pvd")
    _check(f, "ResponseFiles", "vtus=80", "response.pvd", "response_steps.csv")
