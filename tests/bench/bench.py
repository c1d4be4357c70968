"""plbar speed benchmark (issue "Speed").

Run::

    python tests/bench/bench.py            # full, about 40 min (FE full model to N = 100, truncated to N = 400)
    python tests/bench/bench.py --quick    # about 10 min: fewer repeats, FE full to N = 20, truncated to N = 100

Measures, side by side in one process (timings) and in child processes
(peak memory, FE runs with a timeout guard):

1. one periodic response (state + residuals + xi_eq) of the N = 5 chain:
   ``plbar.find_response`` from a nearby guess (also with the full
   admissibility check), a single evaluation at a known (T1, T2), a batched
   evaluation, vs event-driven shooting (``baselines.Shooting``);
2. the default case end to end: ``plbar.solve()`` vs the paper's 3D scan
   (``baselines.scan3d``, 200 x 200 x 50) at the same (T1, T2) resolution;
3. FE P1 lumped bars: the full model for N = 5 ... 100 and the model
   truncated to ``--modes`` modes per state (default 20) for N = 50 ... 400,
   solver time vs N with fitted exponents (each N in a subprocess with a
   timeout; "timeout" is reported), and ``plbar.studies.truncation_check``
   at N = 20 (10 modes vs the full model) and N = 100 (20 vs 40 modes);
4. peak memory of each target (ru_maxrss of a child process, and the
   tracemalloc peak of the task itself where cheap enough);

prints a table and writes it to ``tests/bench/results.json`` (atomically).
``--profile`` (default on) writes a pyinstrument profile of the default case
to ``tests/bench/profile_default.txt``.

Targets (issue "Speed"): one response >= 1000x faster than shooting; default
case >= 30x faster than the 3D scan and < 1 s; FE N = 100 < 60 s; FE N = 400
< 10 min.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import plbar  # noqa: E402
from plbar.response import admissible  # noqa: E402
from plbar.response import coefficients, phase  # noqa: E402

from baselines import Shooting, branch_coverage, modal, scan3d  # noqa: E402

PY = sys.executable
CPU_LOG: list[float] = []   # CPU time (process_time) medians of the last timeit calls


# ----------------------------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------------------------


def timeit(fn, repeat=5, warmup=1):
    """Median (and all) wall times of ``fn()`` after ``warmup`` calls; returns (median, times, last)."""
    out = None
    for _ in range(warmup):
        out = fn()
    ts = []
    cs = []
    for _ in range(repeat):
        c0 = time.process_time()
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
        cs.append(time.process_time() - c0)
    CPU_LOG.append(statistics.median(cs))
    return statistics.median(ts), ts, out


def timeit_small(fn, inner=100, repeat=7):
    """Median per-call wall time of a sub-millisecond ``fn`` (``inner`` calls per sample); returns (median, times,
    last)."""
    box = []

    def many():
        for _ in range(inner):
            box.append(fn())
            box.pop(0) if len(box) > 1 else None
        return box[-1]
    t, ts, out = timeit(many, repeat=repeat, warmup=1)
    CPU_LOG[-1] /= inner
    return t / inner, [x / inner for x in ts], out


def maxrss_mb() -> float:
    """Peak RSS of this process in MB: VmHWM (reset at exec, unlike ru_maxrss, which a child inherits)."""
    try:
        for line in open("/proc/self/status"):
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return r / 1024.0 if sys.platform != "darwin" else r / 2 ** 20


def write_json_atomic(path: Path, data) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(data, f, indent=1, default=_jsonable)
            f.write("\n")
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _jsonable(o):
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, np.bool_):
        return bool(o)
    return str(o)


def fmt_t(t):
    if t is None or (isinstance(t, float) and not np.isfinite(t)):
        return "-"
    if t < 1e-3:
        return f"{t * 1e6:.0f} us"
    if t < 1:
        return f"{t * 1e3:.1f} ms"
    return f"{t:.2f} s"


# ----------------------------------------------------------------------------------------------
# the tasks
# ----------------------------------------------------------------------------------------------


def reference_point(res):
    """Middle point of the longest branch of the default case, with its physical state."""
    prob = res.prob
    s = prob.system
    b = max(res.branches, key=len)
    k = len(b) // 2
    o = b.orbits.take([k])
    return dict(prob=prob, branch=int(b.id), k=k, T1=float(o.T1[0]), T2=float(o.T2[0]), phi=float(o.phi[0]),
                T=float(o.T[0]), xi=float(b.xi[k]), dPL=float(b.dPL[k]),
                x0=s.V1 @ o.eta0[0], v0=s.V1 @ o.v0[0], orbit=o)


def plbar_find(prob, T, T1_guess):
    """One periodic response with plbar from a nearby guess at fixed period T (``plbar.find_response``).

    One batched evaluation at Chebyshev points around the guess, the root of the
    interpolant, the phase, the state, the switch residuals recomputed from the
    flow, the periodicity defect and xi_eq (checked at round-off, else direct steps).
    """
    r = plbar.find_response(prob, T, T1_guess)
    return dict(orb=r.orbit, ok=True, e1=r.e1, e2=r.e2, xi=r.xi, dPL=r.dPL, r=r)


def plbar_find_checked(prob, T, T1_guess):
    """:func:`plbar_find` plus the full admissibility check (no premature switch on (0, T))."""
    d = plbar_find(prob, T, T1_guess)
    d["ok"] = bool(admissible.check(d["orb"]).ok[0])
    return d


def plbar_eval(prob, T1, T2):
    """State + residuals + xi_eq at known (T1, T2) on a path (phase exact)."""
    co = coefficients(prob, T1, T2)
    orb = plbar.orbits(prob, T1, T2, phase(co), co=co)
    e1, e2 = orb.residuals()
    d = plbar.damping(orb)
    return orb, e1, e2, d


def periodicity_defect(orb):
    """Closed-form periodicity defect max|z(T+) - z(0)| / max|z(0)| per orbit."""
    e, v = orb.after_impact()
    z1 = np.c_[e, v]
    z0 = np.c_[orb.eta0, orb.v0]
    return np.abs(z1 - z0).max(1) / np.abs(z0).max(1)


def task_one_response(quick: bool) -> dict:
    res = plbar.solve(plbar.Case())            # warm-up + reference solution
    ref = reference_point(res)
    prob = ref["prob"]
    s = prob.system
    out = dict(point=dict(branch=ref["branch"], T1=ref["T1"], T2=ref["T2"], phi=ref["phi"], T=ref["T"],
                          xi=ref["xi"], dPL=ref["dPL"]))
    # plbar: find from a guess perturbed by 1e-3 (relative) in T1 at fixed T
    T1g = ref["T1"] * (1 + 1e-3)
    t_find, ts, fr = timeit_small(lambda: plbar_find(prob, ref["T"], T1g), repeat=7 if quick else 21)
    cpu_find = CPU_LOG[-1]
    o = fr["orb"]
    scale = np.abs(o.reaction_margin(np.linspace(0, o.T1[0], 65)[None])).max(), \
        np.abs(o.gap(np.linspace(0, o.T2[0], 65)[None])).max()
    sh = Shooting(s.M, s.K, prob.q)
    x_pl, v_pl = s.V1 @ o.eta0[0], s.V1 @ o.v0[0]
    # independent check of plbar's state: integrate it with the event-driven integrator
    r = sh.period(x_pl, v_pl, float(o.phi[0]), ref["T"])
    ind = max(np.abs(np.r_[r[0] - x_pl, r[1] - v_pl]).max() / np.abs(np.r_[x_pl, v_pl]).max(),
              abs(r[3] - ref["T"]) / ref["T"])
    t_chk, _, frc = timeit_small(lambda: plbar_find_checked(prob, ref["T"], T1g), inner=20, repeat=7 if quick else 21)
    out["plbar_find_single"] = dict(
        time=t_find, cpu_time=cpu_find, times=ts, admissible=frc["ok"], time_with_admissibility_check=t_chk,
        evaluations=fr["r"].evaluations, T1_error_vs_reference=abs(o.T1[0] - ref["T1"]),
        e1_rel=abs(fr["e1"]) / scale[0], e2_rel=abs(fr["e2"]) / scale[1],
        periodicity_defect_closed_form=float(periodicity_defect(o)[0]),
        periodicity_defect_ivp_check=float(ind), ivp_T1_minus_plbar_T1=float(r[2] - o.T1[0]),
        xi=fr["xi"], xi_ivp_check=float(r[4] / (2 * r[5])))
    # plbar: evaluate at a known point (single) and batched
    t_ev1, ts1, _ = timeit_small(lambda: plbar_eval(prob, [ref["T1"]], [ref["T2"]]), inner=50,
                                 repeat=7 if quick else 21)
    b_all = res.paths.points()
    reps = max(1, int(np.ceil(1000 / len(b_all))))
    T1b, T2b = np.tile(b_all.T1, reps), np.tile(b_all.T2, reps)
    t_evB, tsB, (orbB, e1B, e2B, dB) = timeit(lambda: plbar_eval(prob, T1b, T2b), repeat=3 if quick else 7)
    cpu_evB = CPU_LOG[-1]
    out["plbar_eval_single"] = dict(time=t_ev1, cpu_time=CPU_LOG[-2])
    out["plbar_eval_batched"] = dict(time_per_response=t_evB / T1b.size, cpu_per_response=cpu_evB / T1b.size,
                                     batch=int(T1b.size), time_batch=t_evB,
                                     max_periodicity_defect=float(periodicity_defect(orbB).max()))
    # shooting from the reference state perturbed by ~1e-3
    rng = np.random.default_rng(1)
    amp = np.abs(np.r_[ref["x0"], ref["v0"]]).max()
    g = rng.standard_normal(2 * ref["x0"].size)
    g *= 1e-3 * amp / np.abs(g).max()
    m = ref["x0"].size
    guess = (ref["x0"] + g[:m], ref["v0"] + g[m:], ref["phi"] + 1e-3, ref["T"])
    shots, cpus = [], []
    sh.solve(*guess)                                            # warm-up
    for _ in range(1 if quick else 3):
        c0 = time.process_time()
        shots.append(sh.solve(*guess))
        cpus.append(time.process_time() - c0)
    t_sh = statistics.median([q.time for q in shots])
    q = shots[-1]
    phi_pl = float(np.mod(o.phi[0], 2 * np.pi))
    dist = np.abs(np.r_[q.x0 - x_pl, q.v0 - v_pl]).max() / np.abs(np.r_[x_pl, v_pl]).max()
    out["shooting"] = dict(
        time=t_sh, cpu_time=statistics.median(cpus), times=[z.time for z in shots], success=q.success,
        message=q.message, nfev=q.nfev,
        periodicity_residual=q.residual, state_distance_to_plbar=float(dist),
        phi_distance=float(abs(np.angle(np.exp(1j * (q.phi - phi_pl))))), T1_distance=float(abs(q.T1 - o.T1[0])),
        xi=q.xi, xi_rel_diff=float(abs(q.xi - fr["xi"]) / fr["xi"]), dPL=q.dPL,
        method=sh.method, rtol=sh.rtol, atol=sh.atol)
    out["ratio_shooting_over_plbar_find"] = t_sh / t_find
    out["ratio_shooting_over_plbar_find_checked"] = t_sh / t_chk
    # the machine's speed drifts by tens of percent over minutes (shared VM): interleave the two, round by
    # round (100 finds, then one shooting solve), and take the median of the per-round ratios
    rounds = []
    for _ in range(5 if quick else 9):
        tf, _, _ = timeit_small(lambda: plbar_find(prob, ref["T"], T1g), inner=100, repeat=1)
        t0 = time.perf_counter()
        sh.solve(*guess)
        ts_ = time.perf_counter() - t0
        rounds.append(dict(find=tf, shooting=ts_, ratio=ts_ / tf))
    out["interleaved"] = dict(rounds=rounds, median_ratio=statistics.median(r["ratio"] for r in rounds),
                              min_ratio=min(r["ratio"] for r in rounds), max_ratio=max(r["ratio"] for r in rounds))
    out["ratio_cpu_shooting_over_plbar_find"] = statistics.median(cpus) / cpu_find
    out["ratio_shooting_over_plbar_eval_single"] = t_sh / t_ev1
    out["ratio_shooting_over_plbar_batched"] = t_sh / (t_evB / T1b.size)
    return out


def task_default_case(quick: bool) -> dict:
    case = plbar.Case()
    plbar.solve(case)                                           # warm-up
    ts, cs = [], []
    res = None
    for _ in range(3 if quick else 7):
        c0 = time.process_time()
        res = plbar.solve(case)
        cs.append(time.process_time() - c0)
        ts.append(res.solver_time)
    t_pl = statistics.median(ts)
    c_pl = statistics.median(cs)
    prob = res.prob
    s = prob.system
    T0I, T0II = s.T0
    md = modal(s.M, s.K, prob.q)
    out = dict(plbar=dict(solver_time=t_pl, cpu_time=c_pl, times=ts, stats=res.paths.stats, branches=len(res.branches),
                          points=int(sum(len(b) for b in res.branches))))
    grid = (200, 200, 50)
    scans = {}
    for share in ((True,) if quick else (True, False)):
        tag = "shared_lu" if share else "per_triplet"
        c0 = time.process_time()
        t0 = time.perf_counter()
        sc = scan3d(md, (0.0, T0I / 2), (0.0, T0II / 2), grid=grid, share_lu=share)
        el = time.perf_counter() - t0
        scans[tag] = (el, sc)
        out[f"scan3d_{tag}"] = dict(time=el, cpu_time=time.process_time() - c0, timings=sc.timings,
                                    triplets=sc.n_triplets, candidates=sc.candidates,
                                    admissible_points=int(len(sc.points)))
    el, sc = scans["shared_lu"]
    h = (T0I / 2 / grid[0], T0II / 2 / grid[1], np.pi / (grid[2] - 1))
    rows, stray = branch_coverage(res.branches, sc.points, h)
    _, stray10 = branch_coverage(res.branches, sc.points, h, near=10.0)
    out["coverage"] = dict(branches=rows, stray_points_gt_1p5_cells=stray, stray_points_gt_10_cells=stray10,
                           branches_outside_phi_range=[int(b.id) for b in res.branches
                                                       if not np.all(np.mod(b.phi, 2 * np.pi) >= np.pi)],
                           median_rel_residual_scan=np.median(np.abs(sc.e_rel), axis=0).tolist())
    plb_in = [r["plbar_points"] for r in rows]
    out["points_in_paper_phi_range"] = dict(plbar=int(sum(plb_in)), scan=int(sum(r["scan_points"] for r in rows)))
    out["ratio_scan_over_plbar"] = min(v[0] for v in scans.values()) / t_pl
    out["ratio_cpu_scan_over_plbar"] = out["scan3d_shared_lu"]["cpu_time"] / c_pl
    return out


FE_CODE = r"""
import json, resource, sys, time
sys.path.insert(0, sys.argv[2])
import plbar
from bench import maxrss_mb
n = int(sys.argv[1])
modes = int(sys.argv[3]) if len(sys.argv) > 3 and sys.argv[3] != "none" else None
r0 = maxrss_mb()
c0 = time.process_time()
case = plbar.Case(model="fe", n=n, element="P1", mass="lumped", modes=modes)
res = plbar.solve(case)
st = {k: v for k, v in res.paths.stats.items()}
xi = [float(b.xi.max()) for b in res.branches if len(b)]
print(json.dumps(dict(n=n, modes=modes, solver_time=res.solver_time, stats=st, branches=len(res.branches),
                      points=int(sum(len(b) for b in res.branches)), max_xi=max(xi, default=0.0),
                      cpu_time=time.process_time() - c0, maxrss_mb=maxrss_mb(), rss_after_import_mb=r0)))
"""


def run_fe(n: int, timeout: float, modes: int | None = None) -> dict:
    t0 = time.perf_counter()
    try:
        p = subprocess.run([PY, "-c", FE_CODE, str(n), str(HERE), "none" if modes is None else str(modes)],
                           capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return dict(n=n, status="timeout", timeout=timeout, wall=time.perf_counter() - t0)
    if p.returncode != 0:
        return dict(n=n, status="error", stderr=p.stderr[-2000:], wall=time.perf_counter() - t0)
    d = json.loads(p.stdout.strip().splitlines()[-1])
    d["status"] = "ok"
    d["wall"] = time.perf_counter() - t0
    return d


def fe_scan_cost(n: int, points: int) -> dict:
    """Cost per (T1, T2) grid point of plbar.periodic.coefficients for the FE P1 lumped bar with n elements.

    Extrapolated to the 200 x 200 grid this is a lower bound of the scan alone
    (the Illinois refinement then re-evaluates the crossings many times).
    """
    prob = plbar.Case(model="fe", n=n).problem()
    T0I, T0II = prob.system.T0
    rng = np.random.default_rng(0)
    T1 = rng.uniform(0.05, 0.5, points) * T0I
    T2 = rng.uniform(0.05, 0.5, points) * T0II
    t, _, _ = timeit(lambda: coefficients(prob, T1, T2), repeat=2, warmup=1)
    return dict(n=n, dim=2 * (prob.system.n - 1), points=points, time_per_point=t / points,
                extrapolated_grid_scan=t / points * 200 * 200)


TRUNC_CODE = r"""
import json, sys, warnings
import numpy as np
warnings.simplefilter("ignore")
sys.path.insert(0, sys.argv[2])
import plbar
from plbar.studies import truncation_check
n, m = int(sys.argv[1]), int(sys.argv[3])
ref = None if sys.argv[4] == "full" else (int(sys.argv[4]), int(sys.argv[4]))
case = plbar.Case(model="fe", n=n)
out = truncation_check(case.bar(), case.load(), m, ref_modes=ref)
out.pop("paths")
rows = out.pop("rows")
out["branches_unmatched"] = sum(1 for r in rows if r.get("match", 1) is None)
out["rel_xi_quantiles"] = [float(q) for q in np.nanquantile([r["rel_xi"] for r in rows if "rel_xi" in r] or [np.nan],
                                                            [0.5, 0.9, 1.0])]
print(json.dumps(dict(n=n, **out), default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o)))
"""


def run_trunc(n: int, modes: int, ref, timeout: float) -> dict:
    """:func:`plbar.studies.truncation_check` of ``modes`` against ``ref`` modes ("full": the full model)."""
    t0 = time.perf_counter()
    try:
        p = subprocess.run([PY, "-c", TRUNC_CODE, str(n), str(HERE), str(modes), str(ref)], capture_output=True,
                           text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return dict(n=n, modes=modes, ref=ref, status="timeout", wall=time.perf_counter() - t0)
    if p.returncode != 0:
        return dict(n=n, modes=modes, ref=ref, status="error", stderr=p.stderr[-2000:])
    d = json.loads(p.stdout.strip().splitlines()[-1])
    d.update(status="ok", wall=time.perf_counter() - t0)
    return d


MEM_CODE = r"""
import json, resource, sys, time, tracemalloc
sys.path.insert(0, sys.argv[2])
import numpy as np, plbar
from bench import reference_point, plbar_find, plbar_eval, maxrss_mb
from baselines import Shooting, modal, scan3d
task = sys.argv[1]
res = plbar.solve(plbar.Case())
ref = reference_point(res)
prob = ref["prob"]; s = prob.system
r0 = maxrss_mb()
tracemalloc.start()
if task == "plbar_find":
    plbar_find(prob, ref["T"], ref["T1"] * (1 + 1e-3))
elif task == "plbar_eval_batched":
    b = res.paths.points(); reps = int(np.ceil(1000 / len(b)))
    plbar_eval(prob, np.tile(b.T1, reps), np.tile(b.T2, reps))
elif task == "shooting":
    Shooting(s.M, s.K, prob.q).solve(ref["x0"] * (1 + 1e-3), ref["v0"] * (1 + 1e-3), ref["phi"] + 1e-3, ref["T"])
elif task == "plbar_default":
    plbar.solve(plbar.Case())
elif task == "scan3d":
    T0I, T0II = s.T0
    scan3d(modal(s.M, s.K, prob.q), (0, T0I / 2), (0, T0II / 2))
peak = tracemalloc.get_traced_memory()[1]
tracemalloc.stop()
print(json.dumps(dict(task=task, tracemalloc_peak_mb=peak / 2**20, rss_before_mb=r0,
                      maxrss_mb=maxrss_mb())))
"""


def run_mem(task: str) -> dict:
    p = subprocess.run([PY, "-c", MEM_CODE, task, str(HERE)], capture_output=True, text=True, timeout=1800)
    if p.returncode != 0:
        return dict(task=task, status="error", stderr=p.stderr[-1500:])
    return json.loads(p.stdout.strip().splitlines()[-1])


def profile_default(path: Path) -> list[str]:
    """pyinstrument profile of the default solve, on one thread (the profiler samples the calling thread only)."""
    from pyinstrument import Profiler

    old = os.environ.get("PLBAR_THREADS")
    os.environ["PLBAR_THREADS"] = "1"
    try:
        plbar.solve(plbar.Case())
        prof = Profiler(interval=0.0005)
        prof.start()
        plbar.solve(plbar.Case())
        prof.stop()
    finally:
        if old is None:
            os.environ.pop("PLBAR_THREADS")
        else:
            os.environ["PLBAR_THREADS"] = old
    txt = "(PLBAR_THREADS=1: the work of the thread pool is shown inline)\n" + \
        prof.output_text(unicode=False, color=False, show_all=False)
    path.write_text(txt)
    return txt.splitlines()


# ----------------------------------------------------------------------------------------------
# main
# ----------------------------------------------------------------------------------------------


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats, FE N <= 20, no per-triplet scan")
    ap.add_argument("--fe-timeout", type=float, default=900.0, help="timeout per FE run in s (default 900)")
    ap.add_argument("--fe-n", type=int, nargs="*", default=None, help="FE sizes of the full model (default 5 10 20 50)")
    ap.add_argument("--modes", type=int, default=20,
                    help="modes per state of the truncated FE runs (N = 50 ... 400; default 20)")
    ap.add_argument("--smoke", action="store_true", help="tiny FE sizes (checks that the script runs end to end)")
    ap.add_argument("--no-profile", action="store_true")
    ap.add_argument("--out", default=str(HERE / "results.json"))
    a = ap.parse_args(argv)
    R = dict(meta=dict(python=platform.python_version(), numpy=np.__version__, machine=platform.machine(),
                       cpus=os.cpu_count(), quick=a.quick, date=time.strftime("%Y-%m-%d %H:%M:%S"),
                       loadavg_start=os.getloadavg()))
    print("[1/5] one periodic response ...", flush=True)
    R["one_response"] = task_one_response(a.quick)
    print("[2/5] default case vs 3D scan ...", flush=True)
    R["default_case"] = task_default_case(a.quick)
    print("[3/5] FE scaling ...", flush=True)

    def series(ns, modes):
        runs, timed_out = [], None
        for n in ns:
            if timed_out is not None:
                runs.append(dict(n=n, modes=modes, status=f"skipped (N={timed_out} timed out)"))
                continue
            d = run_fe(n, a.fe_timeout, modes)
            d.setdefault("modes", modes)
            print(f"      N = {n}, modes = {modes or 'all'}: {d['status']} "
                  f"{fmt_t(d.get('solver_time', d.get('wall')))}", flush=True)
            runs.append(d)
            if d["status"] == "timeout":
                timed_out = n
        ok = [d for d in runs if d["status"] == "ok" and d["n"] >= 10]
        expo = None
        if len(ok) >= 2:
            expo = float(np.polyfit(np.log([d["n"] for d in ok]), np.log([d["solver_time"] for d in ok]), 1)[0])
        return dict(runs=runs, fitted_exponent=expo, fit_over=[d["n"] for d in ok], modes=modes)

    full_ns = a.fe_n or ([5] if a.smoke else [5, 10, 20] if a.quick else [5, 10, 20, 50, 100])
    trunc_ns = [10, 12] if a.smoke else [50, 100] if a.quick else [50, 100, 200, 400]
    R["fe"] = dict(timeout=a.fe_timeout, full=series(full_ns, None), truncated=series(trunc_ns, a.modes))
    print("      truncation checks ...", flush=True)
    R["fe"]["truncation_checks"] = ([run_trunc(8, 4, "full", a.fe_timeout), run_trunc(12, 4, 8, a.fe_timeout)]
                                    if a.smoke else [run_trunc(20, 10, "full", a.fe_timeout),
                                                     run_trunc(100, a.modes, 2 * a.modes, a.fe_timeout)])
    R["fe"]["scan_cost"] = [fe_scan_cost(n, p) for n, p in ((20, 2000), (50, 600), (100, 150), (200, 40), (400, 12))
                            if (not a.quick or n <= 100) and (not a.smoke or n <= 20)]
    print("[4/5] peak memory (child processes) ...", flush=True)
    R["memory"] = {t: run_mem(t) for t in ("plbar_find", "plbar_eval_batched", "shooting", "plbar_default", "scan3d")}
    if not a.no_profile:
        print("[5/5] profile ...", flush=True)
        lines = profile_default(HERE / "profile_default.txt")
        R["profile_file"] = str(HERE / "profile_default.txt")
        R["profile_head"] = lines[:40]
    R["meta"]["loadavg_end"] = os.getloadavg()
    write_json_atomic(Path(a.out), R)
    print_table(R)
    return R


def print_table(R):
    o, d, fe, mem = R["one_response"], R["default_case"], R["fe"], R["memory"]
    L = []
    L.append("=" * 104)
    L.append(f"plbar speed benchmark  ({R['meta']['date']}, {R['meta']['cpus']} CPUs, numpy {R['meta']['numpy']}, "
             f"load avg start/end {R['meta']['loadavg_start'][0]:.1f}/{R['meta']['loadavg_end'][0]:.1f})")
    L.append("=" * 104)
    p = o["point"]
    L.append(f"1. ONE PERIODIC RESPONSE, chain N=5, branch {p['branch']} point T1={p['T1']:.6f} T2={p['T2']:.6f} "
             f"phi={p['phi']:.6f} (xi={p['xi']:.5f})")
    f, sh = o["plbar_find_single"], o["shooting"]
    L.append(f"   {'method':44s}{'time':>12s}  accuracy")
    L.append(f"   {'plbar.find_response from guess (single)':44s}{fmt_t(f['time']):>12s}  "
             f"e1/e2 rel {f['e1_rel']:.1e}/{f['e2_rel']:.1e}, periodicity {f['periodicity_defect_closed_form']:.1e}"
             f" (closed form) {f['periodicity_defect_ivp_check']:.1e} (DOP853 check)")
    L.append(f"   {'  + full admissibility check':44s}{fmt_t(f['time_with_admissibility_check']):>12s}  "
             f"admissible: {f['admissible']}; {f['evaluations']} (T1, T2) evaluations")
    L.append(f"   {'plbar evaluate known (T1,T2), single':44s}{fmt_t(o['plbar_eval_single']['time']):>12s}")
    b = o["plbar_eval_batched"]
    L.append(f"   {'plbar evaluate, batched (per response)':44s}{fmt_t(b['time_per_response']):>12s}  "
             f"batch {b['batch']}, max periodicity defect {b['max_periodicity_defect']:.1e}")
    L.append(f"   {'shooting solve_ivp DOP853 1e-12 + root hybr':44s}{fmt_t(sh['time']):>12s}  "
             f"periodicity {sh['periodicity_residual']:.1e}, |x-x_plbar| {sh['state_distance_to_plbar']:.1e}, "
             f"|dphi| {sh['phi_distance']:.1e}, |dT1| {sh['T1_distance']:.1e}, xi rel diff {sh['xi_rel_diff']:.1e}, "
             f"{sh['nfev']} periods")
    il = o["interleaved"]
    tgt = "PASS" if il["median_ratio"] >= 1000 else "FAIL"
    L.append(f"   CPU time (process_time, less sensitive to machine load): plbar find {fmt_t(f['cpu_time'])}, shooting "
             f"{fmt_t(sh['cpu_time'])}, ratio {o['ratio_cpu_shooting_over_plbar_find']:.0f}x")
    L.append(f"   interleaved rounds (100 finds, 1 shooting solve) x {len(il['rounds'])}: ratio median "
             f"{il['median_ratio']:.0f}x (min {il['min_ratio']:.0f}x, max {il['max_ratio']:.0f}x) "
             f"[target >= 1000x: {tgt}]")
    L.append("   ratio shooting / plbar (medians of the blocks above): "
             f"find {o['ratio_shooting_over_plbar_find']:.0f}x, "
             f"find + admissibility {o['ratio_shooting_over_plbar_find_checked']:.0f}x, "
             f"eval single {o['ratio_shooting_over_plbar_eval_single']:.0f}x, "
             f"batched {o['ratio_shooting_over_plbar_batched']:.0f}x")
    L.append("-" * 104)
    pl = d["plbar"]
    L.append("2. DEFAULT CASE END TO END (chain N=5, grid 200x200) vs PAPER 3D SCAN 200x200x50, phi in [pi, 2pi]")
    tgt = "PASS" if pl["solver_time"] < 1 else "FAIL"
    L.append(f"   plbar.solve()            {fmt_t(pl['solver_time']):>10s}  [target < 1 s: {tgt}]  "
             f"{pl['branches']} branches, {pl['points']} points; scan {fmt_t(pl['stats'].get('t_scan'))}, "
             f"refine+admissibility {fmt_t(pl['stats'].get('t_total', 0) - pl['stats'].get('t_scan', 0))}")
    for tag in ("shared_lu", "per_triplet"):
        k = f"scan3d_{tag}"
        if k in d:
            s = d[k]
            tm = s["timings"]
            L.append(f"   3D scan ({tag:11s})   {fmt_t(s['time']):>10s}  {s['triplets']} triplets: residuals "
                     f"{fmt_t(tm['residuals'])} (solves {fmt_t(tm['linear_solves'])}), filter {fmt_t(tm['filter'])}, "
                     f"admissibility {fmt_t(tm['admissibility'])}; {s['candidates']} candidates -> "
                     f"{s['admissible_points']} points")
    L.append(f"   CPU time: plbar {fmt_t(pl['cpu_time'])}, 3D scan {fmt_t(d['scan3d_shared_lu']['cpu_time'])}, "
             f"ratio {d['ratio_cpu_scan_over_plbar']:.1f}x")
    tgt = "PASS" if d["ratio_scan_over_plbar"] >= 30 else "FAIL"
    L.append(f"   ratio 3D scan (fastest) / plbar = {d['ratio_scan_over_plbar']:.1f}x [target >= 30x: {tgt}]")
    c = d["coverage"]
    L.append("   point density along the branches in the paper's phi range (plbar points / scan points near it, "
             "coverage = share of the branch with a scan point within 1.5 cells, median distance in cells):")
    for r in c["branches"]:
        md = r["median_dist_cells"]
        L.append(f"     branch {r['branch']:3d}  T {r['T'][0]:8.4f}..{r['T'][1]:8.4f}  plbar {r['plbar_points']:4d}  "
                 f"scan {r['scan_points']:4d}  coverage {r['coverage']:5.2f}  median dist "
                 f"{'-' if md is None else f'{md:.2f}'}")
    pr = d["points_in_paper_phi_range"]
    L.append(f"     total: plbar {pr['plbar']} points, scan {pr['scan']} near them; scan points > 1.5 cells from any "
             f"branch: {c['stray_points_gt_1p5_cells']}, > 10 cells: {c['stray_points_gt_10_cells']}; "
             f"plbar branches with phi outside [pi, 2pi] (not in the paper's scan): "
             f"{len(c['branches_outside_phi_range'])}")
    L.append(f"     scan points are O(grid step) off the curves: median relative residuals |e1|, |e2| = "
             f"{c['median_rel_residual_scan'][0]:.1e}, {c['median_rel_residual_scan'][1]:.1e} (plbar: <= 1e-7, "
             f"typically round-off)")
    L.append("-" * 104)
    L.append("3. FE P1 LUMPED, plbar.solve (grid 200x200, stability included), each N in a subprocess "
             f"(timeout {fe['timeout']:.0f} s)")
    L.append(f"   {'N':>5s} {'modes':>6s} {'status':>8s} {'solver time':>12s} {'scan':>10s} {'crossings':>10s} "
             f"{'branches':>9s} {'points':>7s} {'max xi':>9s} {'maxrss':>9s}")
    allruns = fe["full"]["runs"] + fe["truncated"]["runs"]
    for r in allruns:
        md = "all" if not r.get("modes") else str(r["modes"])
        if r["status"] == "ok":
            st = r["stats"]
            L.append(f"   {r['n']:5d} {md:>6s} {'ok':>8s} {fmt_t(r['solver_time']):>12s} "
                     f"{fmt_t(st.get('t_scan')):>10s} "
                     f"{st.get('crossings', 0):10d} {r['branches']:9d} {r['points']:7d} {r.get('max_xi', 0):9.2e} "
                     f"{r['maxrss_mb']:7.0f}MB")
        else:
            L.append(f"   {r['n']:5d} {md:>6s} {r['status']:>8s}")
    for key, lab in (("full", "full model"), ("truncated", f"{fe['truncated']['modes']} modes")):
        f_ = fe[key]
        if f_["fitted_exponent"] is not None:
            L.append(f"   log-log fit, {lab}: time ~ N^{f_['fitted_exponent']:.2f} over N = {f_['fit_over']}")
    for n, lim in ((100, 60), (400, 600)):
        for r in [r for r in allruns if r["n"] == n and r["status"] == "ok"]:
            v = r["solver_time"]
            L.append(f"   target N={n} < {lim} s, modes = {r.get('modes') or 'all'}: "
                     + ("PASS" if v < lim else "FAIL") + f" ({fmt_t(v)})")
    L.append("   truncation check (plbar.studies.truncation_check: branches matched by their T range; xi compared at "
             "common T, relative to the branch's max xi):")
    for c in fe.get("truncation_checks", []):
        if c.get("status") != "ok":
            L.append(f"     N={c['n']} modes {c['modes']} vs {c['ref']}: {c.get('status')}")
            continue
        ref = "full" if c["ref_modes"] is None else c["ref_modes"][0]
        L.append(f"     N={c['n']:4d}  {c['modes']} modes vs {ref}: branches {c['branches_trunc']} vs "
                 f"{c['branches_ref']} ({c['branches_unmatched']} unmatched), max rel dT {c['max_rel_T']:.2e}, "
                 f"rel dxi median/90%/max {c['rel_xi_quantiles'][0]:.2e}/{c['rel_xi_quantiles'][1]:.2e}/"
                 f"{c['rel_xi_quantiles'][2]:.2e}; times {fmt_t(c['time_trunc'])} vs {fmt_t(c['time_ref'])}")
    L.append("   per-grid-point cost of periodic.coefficients (dense (2(n-1))^2 solve + slogdet), x 40000 = full-model "
             "scan alone:")
    for c in fe.get("scan_cost", []):
        L.append(f"     N={c['n']:4d}  dim {c['dim']:4d}  {fmt_t(c['time_per_point']):>9s}/point  -> 200x200 scan "
                 f"{fmt_t(c['extrapolated_grid_scan'])}")
    L.append("-" * 104)
    L.append("4. PEAK MEMORY (child process; ru_maxrss includes the interpreter + numpy/scipy/skfem + a default solve "
             "for the reference point; tracemalloc = the task's own peak)")
    for t, m in mem.items():
        if "maxrss_mb" in m:
            L.append(f"   {t:22s} tracemalloc peak {m['tracemalloc_peak_mb']:8.1f} MB   "
                     f"maxrss {m['maxrss_mb']:7.0f} MB "
                     f"(before task {m['rss_before_mb']:.0f} MB)")
        else:
            L.append(f"   {t:22s} error")
    for r in fe["full"]["runs"] + fe["truncated"]["runs"]:
        if r["status"] == "ok":
            L.append(f"   fe N={r['n']:<5d} modes {str(r.get('modes') or 'all'):>4s}  maxrss {r['maxrss_mb']:7.0f} MB "
                     f"(after import {r['rss_after_import_mb']:.0f} MB)")
    L.append("=" * 104)
    print("\n".join(L))
    return L


if __name__ == "__main__":
    if sys.argv[1:2] == ["--table"]:          # re-print the table of a results file
        print_table(json.load(open(sys.argv[2] if len(sys.argv) > 2 else HERE / "results.json")))
    else:
        main()
