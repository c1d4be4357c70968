"""The compiled kernel (plbar.motion.kernel) against the numpy closed forms, brute force and its own promises."""

import subprocess
import sys
from math import cos, sin
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

import plbar
from plbar.motion import FREE, Start, padded, run
from plbar.motion.kernel import closed, data, integrals, jit
from plbar.motion.kernel.certify import ZERO, bracket, decide_step, polynomial_step, taylor
from plbar.motion.kernel.locate import locate
from plbar.motion.kernel.loop import work_space
from plbar.motion.kernel.split import particular, split_step
from plbar.util.jit import python_twin
from twins import Twins

# the kernel's helpers have no wrapper for Python callers: the tests call their twins (the same source)
closed, integrals = Twins(closed), Twins(integrals)
bracket, decide_step, polynomial_step, taylor, locate, work_space, particular, split_step = map(
    python_twin, (bracket, decide_step, polynomial_step, taylor, locate, work_space, particular, split_step))
from plbar.response import Forcing, Modes, psi, segment, segment_work

RNG = np.random.default_rng(20261125)


def _random_case(rng, large=False):
    if not large and rng.random() < 0.4:
        n = int(rng.integers(3, 7))
        return plbar.Case(n=n, load_nodes=((int(rng.integers(1, n + 1)), 1.0),), end_mass=float(rng.choice([0, 0.3])))
    el, ms = rng.choice(["P1", "P2"]), rng.choice(["lumped", "consistent"])
    n = int(rng.integers(12, 40)) if large else int(rng.integers(3, 8))
    return plbar.Case(model="fe", n=n, element=str(el), mass=str(ms), end_mass=float(rng.choice([0.0, 0.5])),
                      load_points=((float(rng.uniform(0.1, 1.0)), 1.0),))


# --- the closed forms, one mode at a time, against the batched numpy functions of plbar.response -------------

@pytest.mark.parametrize("zeta", [None, 0.02, 0.999999, 1.0, 1.5, 40.0])
def test_flow_psi_and_work_equal_the_numpy_closed_forms(zeta):
    w = np.array([0.3, 0.7, 1.0, 2.5, 9.0])
    f, e0, v0 = RNG.normal(size=5), RNG.normal(size=5), RNG.normal(size=5)
    damping = None if zeta is None else np.zeros(1)
    z = 0.0 if zeta is None else zeta
    for W, ts, u, phi in ((0.7, 1.3, 2.9, 0.4), (1.0, 0.0, 5.0, 2.0), (2.5 + 1e-9, 0.2, 1e-7, 5.0),
                          (0.45, 3.0, 0.0, 1.0)):
        c0, s0, cp, sp = cos(W * ts), sin(W * ts), cos(phi), sin(phi)
        ld, hf = data.Forcing(W, c0, s0, cp, sp), closed.half(W, u)
        ref_e, ref_v = segment(w, f, W, ts, u, e0, v0, cp, sp, zeta=zeta)
        ref_p = psi(Modes(w, f, zeta), Forcing(W, cp, sp), ts, u, e0, v0)[0]
        ref_w = segment_work(Modes(w, f, zeta), Forcing(W, cp, sp), ts, u, e0, v0)
        for j in range(5):
            mode, at = data.Mode(w[j], f[j], z, 0.0), data.ModeState(e0[j], v0[j])
            e, v = closed.mode_flow(mode, ld, u, at, hf, damping)
            size = abs(e0[j]) + abs(v0[j]) / w[j] + abs(f[j]) * (1 + u * u)
            assert e == pytest.approx(ref_e[j], abs=1e-13 * size)
            assert v == pytest.approx(ref_v[j], abs=1e-13 * size * w[j])
            p = integrals.psi(mode, ld, u, at, damping, hf)
            wk = integrals.work(mode, ld, u, at, damping, hf)
            assert p == pytest.approx(ref_p[j], rel=1e-11, abs=1e-13)
            assert wk == pytest.approx(ref_w[j], rel=1e-10, abs=1e-12 * size * size * w[j])


def test_exact_resonance_is_finite_and_right():
    """W = w exactly: the flow keeps its limit (t sin), Psi and the work fall back to quadrature, no nan."""
    w, f, W, u = 0.8, 1.3, 0.8, 7.0
    mode, ld, rest = data.Mode(w, f, 0.0, 0.0), data.Forcing(W, 1.0, 0.0, 1.0, 0.0), data.ModeState(0.0, 0.0)
    hf = closed.half(W, u)
    e, v = closed.mode_flow(mode, ld, u, rest, hf, None)
    assert e == pytest.approx(f * u * np.sin(w * u) / (2 * w), rel=1e-13)
    p = integrals.psi(mode, ld, u, rest, None, hf)
    wk = integrals.work(mode, ld, u, rest, None, hf)
    assert np.isfinite(p) and np.isfinite(wk)
    assert wk == pytest.approx(0.5 * (v * v + (w * e) ** 2), rel=1e-12)          # work = energy gained


# --- the certified step, against brute force -------------------------------------------------------------------

def _state(rng, pad, s):
    m = pad.m if s == FREE else pad.m - 1
    eta, vel = np.zeros(pad.m), np.zeros(pad.m)
    eta[:m] = rng.normal(size=m) / pad.w[s, :m] / (1 + np.arange(m)) ** 2
    vel[:m] = rng.normal(size=m) / (1 + np.arange(m)) ** 2
    return eta, vel


def _margin(pad, s, eta, vel, W, t, phi, u):
    """The margin at local times u after t, from the numpy closed form (brute force)."""
    e, v = segment(pad.w[s], pad.f[s], W, t, u[:, None], eta, vel, np.cos(phi), np.sin(phi))
    return e @ pad.c[s] + pad.rq[s] * np.cos(W * (t + u) - phi)


def _certified(pad, s, eta, vel, W, t, phi, cap, K=8):
    d, scale, work = np.zeros(44), np.zeros(44), np.zeros(90)
    rem, Om = taylor(_modes(pad, s), None, eta, vel, _load(pad, s, W, t, phi), cap, K, d, scale)
    event, v, found = decide_step(d, rem, scale, K, Om * cap, pad.size[s], work)
    return event, v / Om, found, scale[0]


def _modes(pad, s):
    return data.Modes(pad.w[s], pad.f[s], pad.c[s], pad.g[s])


def _load(pad, s, W, t, phi):
    """The margin's load term at ``t`` (:class:`plbar.motion.kernel.data.LoadTerm`)."""
    return data.LoadTerm(W, cos(W * t - phi), sin(W * t - phi), pad.rq[s], 0.0, pad.g0[s])


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_certified_step_never_steps_over_a_crossing(seed):
    """The margin sampled densely over a certified step never goes below its round-off level."""
    rng = np.random.default_rng(seed)
    pad = padded(_random_case(rng).problem())
    s = int(rng.integers(0, 2))
    eta, vel = _state(rng, pad, s)
    W = float(rng.uniform(0.3, 2.0) * pad.w[s, 0])
    t, phi, cap = float(rng.uniform(0, 3)), float(rng.uniform(0, 6)), float(rng.uniform(0.5, 3.0) / pad.w[s, 0])
    if _margin(pad, s, eta, vel, W, t, phi, np.array([0.0]))[0] < 0:
        eta, vel = -eta, -vel
    event, step, found, level = _certified(pad, s, eta, vel, W, t, phi, cap)
    if event or not found:
        return
    g = _margin(pad, s, eta, vel, W, t, phi, np.linspace(0.0, step, 4001))
    level = max(level, pad.size[s])
    assert g.min() >= -ZERO * level - 1e-14 * level
    assert 0 < step <= cap * (1 + 1e-12)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_split_step_never_steps_over_a_crossing(seed):
    """The split model (fast modes bounded by their free amplitude) against brute force, on FE bars of 12-40
    elements with states whose fast modes carry a random share of the motion."""
    rng = np.random.default_rng(seed)
    pad = padded(_random_case(rng, large=True).problem())
    md = data.model(pad)
    s = int(rng.integers(0, 2))
    eta, vel = _state(rng, pad, s)
    eta[pad.m // 3:] *= rng.uniform(0, 30)
    W = float(rng.uniform(0.3, 2.0) * pad.w[s, 0])
    t, phi, cap = float(rng.uniform(0, 3)), float(rng.uniform(0, 6)), float(rng.uniform(0.5, 3.0) / pad.w[s, 0])
    if _margin(pad, s, eta, vel, W, t, phi, np.array([0.0]))[0] < 0:
        eta, vel = -eta, -vel
    wk = work_space(pad.m)
    wk.e[:], wk.v[:] = eta, vel
    particular(md, None, W, wk.P, wk.fast)
    step = split_step(md, s, W, cos(W * t - phi), sin(W * t - phi), cap, wk, None)
    if step <= 0:
        return
    u = np.linspace(0.0, step, 20001)
    g = _margin(pad, s, eta, vel, W, t, phi, u)
    assert g.min() > 0
    assert step <= cap * (1 + 1e-12)


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_a_certified_bracket_holds_the_first_crossing_and_locate_finds_it(seed):
    """Where the model certifies a bracket [step, hi] of one decreasing crossing, brute force agrees: the margin
    sampled densely is positive before the step, changes sign exactly once in the bracket, is decreasing there;
    Newton on the closed form (locate) lands on that crossing (brentq on the numpy closed form) to round-off."""
    rng = np.random.default_rng(seed)
    pad = padded(_random_case(rng).problem())
    md = data.model(pad)
    s = int(rng.integers(0, 2))
    eta, vel = _state(rng, pad, s)
    W = float(rng.uniform(0.3, 2.0) * pad.w[s, 0])
    t, phi, cap = float(rng.uniform(0, 3)), float(rng.uniform(0, 6)), float(rng.uniform(0.5, 6.0) / pad.w[s, 0])
    if _margin(pad, s, eta, vel, W, t, phi, np.array([0.0]))[0] < 0:
        eta, vel = -eta, -vel
    d, scale, work = np.zeros(44), np.zeros(44), np.zeros(90)
    rem, Om = taylor(_modes(pad, s), None, eta, vel, _load(pad, s, W, t, phi), cap, 8, d, scale)
    event, v, found = decide_step(d, rem, scale, 8, Om * cap, pad.size[s], work)
    if event or not found or not (0 < v < Om * cap) or not d[0] > ZERO * max(scale[0], pad.size[s]):
        return
    hi, guess = bracket(d, 8, rem, v, Om * cap, scale, work)
    if not hi > 0:
        return
    lo, hi, guess = v / Om, hi / Om, guess / Om
    level = ZERO * max(scale[0], pad.size[s])
    assert _margin(pad, s, eta, vel, W, t, phi, np.linspace(0.0, lo, 20001)).min() > -level   # nothing before
    inside = _margin(pad, s, eta, vel, W, t, phi, np.linspace(lo, hi, 20001))
    assert inside[0] > -level and inside[-1] < level
    signs = np.sign(inside[np.abs(inside) > level])
    changes = np.count_nonzero(np.diff(signs))
    # one crossing in the bracket; or none above the round-off: the margin starts within it (and goes down, or
    # stays there): the crossing is at the bracket's start, to round-off
    assert changes == 1 or (changes == 0 and abs(inside[0]) <= level and (not signs.size or signs[0] < 0))
    assert np.all(np.diff(inside) <= 1e-2 * level)     # decreasing through it (to the round-off of its terms)
    z0 = np.stack([eta, vel])
    wk = work_space(pad.m)
    seg = data.Segment(data.Forcing(W, cos(W * t), sin(W * t), cos(phi), sin(phi)), t, phi)
    x = locate(md, s, seg, lo, hi, guess, z0, wk, None)
    e = wk.e
    if changes == 0:                                   # no sign to bracket: locate stays inside, on round-off
        assert lo <= x <= hi and abs(_margin(pad, s, eta, vel, W, t, phi, np.array([x]))[0]) <= 2 * level
        return
    root = brentq(lambda x: _margin(pad, s, eta, vel, W, t, phi, np.array([x]))[0], lo, hi, xtol=1e-15)
    h = 1e-6 * max(hi, 1.0)
    slope = abs(np.diff(_margin(pad, s, eta, vel, W, t, phi, np.array([root - h, root + h])))[0]) / (2 * h)
    # to round-off, or to where the margin is round-off (locate stops at |g| < level: a shallow crossing's time
    # is known only to level / |slope|)
    assert abs(x - root) <= 1e-12 * max(hi, 1.0) + 1e-9 * abs(root - guess) + 2 * level / max(slope, 1e-300)
    ref_e, _ = segment(pad.w[s], pad.f[s], W, t, x, eta, vel, np.cos(phi), np.sin(phi))
    assert np.allclose(e, ref_e, rtol=0, atol=1e-12 * np.abs(eta).max() + 1e-12)


def test_a_grazing_bump_narrower_than_any_step_is_found():
    """A gap that dips below zero for a sliver of time between two samples of any sampled search: a fast mode's
    trough pokes through a slowly varying gap.  The certified search stops in the dip; a grid of the step the
    of 0.3 periods of the fast mode sees nothing."""
    case = plbar.Case(model="fe", n=24, end_mass=0.5, load_points=((0.05, 1e-9),))
    pad = padded(case.problem())
    T, phi, h = 40.0, 0.0, 17
    W = 2 * np.pi / T
    eta, vel = np.zeros(pad.m), np.zeros(pad.m)
    eta[0] = 0.3 / pad.c[FREE, 0]                        # the bar held off the wall: gap 0.3, slowly varying
    a = -1.0005 * 0.3 / pad.c[FREE, h]                    # a fast mode whose trough reaches 0.05 % below zero
    vel[h] = a * pad.w[FREE, h]                           # eta_h = a sin(w_h t): its trough at t = pi / (2 w_h)
    t = np.linspace(0.0, 2 * np.pi / pad.w[FREE, h], 200001)
    g = _margin(pad, FREE, eta, vel, W, 0.0, phi, t)
    neg = t[g < 0]
    assert neg.size and neg[-1] - neg[0] < 0.03 * (2 * np.pi / pad.w[FREE, h])   # a narrow dip
    r = run(pad, [T], [phi], periods=1, record=1, start=Start(np.array([FREE]), eta[None], vel[None]),
            accounts=False)
    dt = t[1] - t[0]
    root = brentq(lambda x: _margin(pad, FREE, eta, vel, W, 0.0, phi, np.array([x]))[0], neg[0] - dt, neg[0],
                  xtol=1e-15)
    assert r.events["kind"][0] == 2 and abs(r.events["time"][0] - root) <= 1e-12 * T
    step = 0.3 * (2 * np.pi / pad.w[FREE, h])
    grid = np.arange(0.0, neg[-1] + step, step)
    assert _margin(pad, FREE, eta, vel, W, 0.0, phi, grid).min() > 0          # a sampled search steps over it


def test_polynomial_step_reaches_the_first_root():
    """q(v) = (1 - v)(2 - v)(1 + v^2): the certified steps approach v = 1, never beyond, and reach it to round-off
    in a few calls (each re-expands q about where it stops: the next call goes on from there)."""
    s = np.zeros(10)                                                   # room for 2 (n + 1) entries: work space
    s[:5] = np.polynomial.polynomial.polyfromroots([1.0, 2.0, 1j, -1j]).real
    total = 0.0
    for _ in range(4):
        total += polynomial_step(s, 4, 5.0 - total)
        assert total <= 1.0
    assert total > 1 - 1e-13
    assert polynomial_step(np.array([1.0, 0.0, 1.0, 0.0, 0.0, 0.0]), 2, 3.0) == 3.0     # no root: the whole step


# --- the compiled entry point: cache keyed by every source, no numba where no simulation runs --------------------

def test_the_cache_key_covers_every_source_the_kernel_is_built_from():
    """numba keys a cached function by its own file; the kernel's entry closes over a hash of every file the
    kernel is compiled from.  Every module it imports from (numba freezes imported constants) must be one."""
    from kernel_sources import assert_imports_covered

    assert_imports_covered(jit.SOURCES[0].parent, jit.SOURCES)


def test_solving_the_paper_class_loads_the_chain_not_the_simulator():
    """The paper's class alone (``--signatures paper``) makes each of its points an exact orbit of the chain (the
    one periodic core: the chain's kernel), and needs no simulator: after an install it compiles one kernel
    package, not two (it imported no numba before the one branch record, issue 40)."""
    code = ("import sys, plbar; plbar.solve(plbar.Case(signatures='paper')); "
            "from plbar.motion.kernel import loop; from plbar.periodic.kernel import walk; "
            "assert walk.chain.signatures, 'no chain'; "
            "assert not loop.advance.signatures, 'the simulator was loaded'")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_a_compiled_specialisation_is_marked_per_sources_numba_and_kind(tmp_path):
    """The note 'compiling the simulator' is said only before a specialisation's first compile: a marker per
    kernel sources (stamp), numba version and kind, in numba's own cache folder; a read-only cache is no error."""
    entry = type("E", (), {"_cache": type("C", (), {"_cache_path": str(tmp_path / "cache")})()})()
    assert not jit.is_compiled(entry, "replay-undamped-small")
    jit.mark_compiled(entry, "replay-undamped-small")
    assert jit.is_compiled(entry, "replay-undamped-small")
    assert not jit.is_compiled(entry, "accounts-undamped-small")
    assert not jit.is_compiled(entry, "replay-undamped-small", stamp=jit.STAMP + 1)     # an edited kernel compiles
    assert jit.is_compiled(object(), "anything")                                      # no cache: nothing to say
    (tmp_path / "ro").mkdir()
    (tmp_path / "ro").chmod(0o500)
    ro = type("E", (), {"_cache": type("C", (), {"_cache_path": str(tmp_path / "ro")})()})()
    jit.mark_compiled(ro, "x")                                                        # no exception


def test_nothing_compiles_elsewhere_when_the_kernel_is_in_the_cache():
    from plbar.motion import compile_elsewhere, compiled

    pad = padded(plbar.Case().problem())
    run(pad, [8.0], periods=1, record=1, accounts=False)                 # in the cache now
    assert compiled(pad, accounts=False)
    with compile_elsewhere(pad, accounts=False) as other:
        assert other.proc is None and other.wait()


@pytest.mark.slow
def test_a_compile_in_another_process_fills_the_cache_this_process_loads(tmp_path):
    """With an empty numba cache: not compiled; another process compiles the replay kernel while this one waits;
    then this process finds it compiled and its first simulation takes well under the compile's time.  This
    process's plbar is a copy (as an installed one is) and its working directory holds another (a checkout): the
    other process compiles this process's plbar, not the one its working directory would put first."""
    import shutil

    here = Path(plbar.__file__).resolve().parent
    site = tmp_path / "site"
    shutil.copytree(here, site / "plbar", ignore=shutil.ignore_patterns("__pycache__"))
    (site / "driver.py").write_text("""
import time, plbar
from pathlib import Path
from plbar.motion import compile_elsewhere, compiled, padded, run
assert Path(plbar.__file__).parent.parent == Path(__file__).parent, plbar.__file__
pad = padded(plbar.Case().problem())
assert not compiled(pad, accounts=False)
t = time.perf_counter()
with compile_elsewhere(pad, accounts=False) as other:
    assert other.proc is not None
    assert other.wait()
took = time.perf_counter() - t
assert compiled(pad, accounts=False)
t = time.perf_counter()
run(pad, [8.0], periods=2, record=1, accounts=False)
assert time.perf_counter() - t < 0.25 * took, (time.perf_counter() - t, took)
""")
    env = dict(__import__("os").environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    env.pop("PYTHONPATH", None)
    r = subprocess.run([sys.executable, str(site / "driver.py")], env=env, cwd=here.parent, capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
