"""The refinement table of issue 29: the FE bars under refinement against the exact continuum (plbar.continuum).

Bar L = c = 1, EA = rhoA = 1, end mass 0.5 at the contact, unit point force at s = 0.37, T/L = 2.5 and 3.5, from
rest.  The FE side is ``results_refinement_fe.json`` (``refinement_table.py``: P1 lumped, P2 consistent, P2
redistributed, N = 8 ... 256, undamped and with 1 % Rayleigh damping at T = 2 and 4).  This script adds

* the continuum's first 20 periods at two steps (n = 256 and 512 per L/c: their difference bounds its own error):
  the first impact times and the contact displacement at the FE side's 400 sample times;
* the continuum's long run: 1,000 periods, loss per period over the last 999 with its standard error (20 batch
  means), impacts per period, the energy residual;

and prints the table: per mesh, the first-20-periods errors (the first impacts' times while the sequences agree,
the contact displacement's largest error) with the observed orders between successive meshes, and the long run's
loss with its standard error and the z-score against the continuum.  The damped bar (a Kelvin-Voigt continuum:
no characteristics) is compared with :func:`plbar.continuum.simulate_modal` (``--damped`` computes it: exact modes
per contact state, the first 20 periods at K = 2048 and 4096, the long run at K = 512 and 1024;
``--damped --first`` / ``--damped --long`` recompute the first 20 periods / the long runs only).

Usage: ``python tests/bench/refinement_vs_continuum.py [--run] [--damped] [--table]`` (``--run`` computes the
continuum and writes ``results_refinement_continuum.json``, ``--damped`` adds the damped continuum to it;
``--table`` prints the table into ``results_refinement_table.md``).
"""

import json
import sys
import time
from pathlib import Path

import numpy as np

import plbar.continuum as pc
from plbar.continuum.accounts import gauss, _x_cuts
from plbar.continuum.fields import invariants

HERE = Path(__file__).parent
FE = HERE / "results_refinement_fe.json"
OUT = HERE / "results_refinement_continuum.json"
TABLE = HERE / "results_refinement_table.md"
TS = (2.5, 3.5)
BAR = pc.ContinuumBar(end_mass=0.5, s=0.37)
FIRST_STEPS = (256, 512)
LONG_STEPS = (32, 64)


def batch_se(x, nb=20):
    x = np.asarray(x, float)
    edges = np.linspace(0, x.size, nb + 1).round().astype(int)
    means = np.array([x[i:j].mean() for i, j in zip(edges[:-1], edges[1:])])
    return float(means.std(ddof=1) / np.sqrt(nb))


def u_end(ln, t):
    """``u(L, t)``: ``u_x`` integrated from the clamp along the stored line (exact for the line)."""
    ux = lambda y: 0.5 * np.subtract(*invariants(ln, y, t)[::-1]) / ln.c  # noqa: E731
    return float(gauss(ux, _x_cuts(ln, t)).sum())


def first(T, n, times):
    cr = pc.simulate(BAR, T, periods=20, steps_per_L=n, record=1)
    ev = cr.events
    return {"impact_times": ev["time"][ev["kind"] == 2][:10].tolist(),
            "u_c": [u_end(cr.line, t) for t in times], "seconds": round(cr.elapsed, 2)}


def long_run(T, n):
    t0 = time.perf_counter()
    cr = pc.simulate(BAR, T, periods=1000, steps_per_L=n, record=10)
    loss = cr.loss[1:]
    return {"loss_per_T": float(loss.mean()), "loss_se": batch_se(loss), "impacts_per_T": float(cr.impacts[1:].mean()),
            "energy_residual": float(cr.energy_residual), "xi_w_last10": float(cr.xi_omega),
            "seconds": round(time.perf_counter() - t0, 1)}


DAMPED_FIRST_MODES = (2048, 4096)
DAMPED_LONG_MODES = (512, 1024)


def rayleigh():
    import plbar
    return plbar.rayleigh_from_ratio(0.01, 2.0, 4.0)


def damped_first(T, K, times):
    from plbar.continuum.modal import simulate_modal
    mr = simulate_modal(BAR, T, 20, rayleigh(), modes=K)
    ev = mr.events
    return {"impact_times": ev["time"][ev["kind"] == 2][:10].tolist(),
            "impact_losses": ev["loss"][ev["kind"] == 2][:10].tolist(),
            "u_c": mr.contact(times).tolist(), "seconds": round(mr.elapsed, 2)}


def damped_long(T, K):
    from plbar.continuum.modal import simulate_modal
    mr = simulate_modal(BAR, T, 1000, rayleigh(), modes=K, keep=0, record=999)
    loss = mr.loss[1:]
    return {"loss_per_T": float(loss.mean()), "loss_se": batch_se(loss), "impacts_per_T": float(mr.impacts[1:].mean()),
            "xi_w": mr.xi_omega, "xi_eq": mr.xi_eq, "energy_residual": mr.energy_residual,
            "transfer_over_work": float(mr.transfer.sum() / mr.work.sum()), "seconds": round(mr.elapsed, 1)}


def run_damped(first_only=False, long_only=False):
    """The damped continuum (:mod:`plbar.continuum.modal`, 1 % Rayleigh at T = 2 and 4) into ``OUT["damped"]``
    (``first_only`` / ``long_only``: recompute the first 20 periods / the long runs only, keep the other)."""
    fe = json.loads(FE.read_text())
    out = json.loads(OUT.read_text())
    dd = out.setdefault("damped", {})
    for T in TS:
        times = next(r["first"]["t"] for r in fe if r["T"] == T and "t" in r["first"])
        old = dd.get(str(T), {}).get("long", {})
        old_first = dd.get(str(T), {}).get("first", {})
        d = {"first": old_first if long_only else {str(K): damped_first(T, K, times) for K in DAMPED_FIRST_MODES},
             "long": old}
        print(f"T = {T}: damped first 20 periods done", flush=True)
        for K in () if first_only else DAMPED_LONG_MODES:
            d["long"][str(K)] = damped_long(T, K)
            print(f"T = {T}, K = {K}: {d['long'][str(K)]}", flush=True)
        dd[str(T)] = d
        OUT.write_text(json.dumps(out, indent=1))


def run():
    fe = json.loads(FE.read_text())
    out = {}
    for T in TS:
        times = next(r["first"]["t"] for r in fe if r["T"] == T and "t" in r["first"])
        d = {"first": {str(n): first(T, n, times) for n in FIRST_STEPS}, "t": times}
        print(f"T = {T}: first 20 periods done", flush=True)
        d["long"] = {}
        for n in LONG_STEPS:
            d["long"][str(n)] = long_run(T, n)
            print(f"T = {T}, n = {n}: {d['long'][str(n)]}", flush=True)
            OUT.write_text(json.dumps(out | {str(T): d}, indent=1))
        out[str(T)] = d
    OUT.write_text(json.dumps(out, indent=1))


def _orders(errs, Ns):
    o = []
    for (e1, n1), (e2, n2) in zip(zip(errs, Ns), zip(errs[1:], Ns[1:])):
        o.append(np.log(e1 / e2) / np.log(n2 / n1) if e1 > 0 and e2 > 0 and np.isfinite(e1 * e2) else np.nan)
    return [np.nan] + o


def _first_errors(row, ref):
    """First impact's time error; the contact displacement's largest error over the first 2 and the 20 periods."""
    f = row["first"]
    if "error" in f:
        return np.nan, np.nan, np.nan
    ti, tc = np.array(f["impact_times"]), np.array(ref["impact_times"])
    # the reference's first impact against the mesh's nearest (P2 touches the wall before it: precursor flights of
    # its spurious fast waves, energies of 1e-35 to 1e-4, counted apart)
    e_t = float(np.abs(ti - tc[0]).min()) if ti.size and tc.size else np.nan
    d = np.abs(np.array(f["u_c"]) - np.array(ref["u_c"]))
    early = np.array(f["t"]) <= 2 * row["T"]
    return e_t, float(d[early].max()), float(d.max())


def table():
    fe = json.loads(FE.read_text())
    c = json.loads(OUT.read_text())
    lines = ["# Refinement table (issue 29): FE bars against the exact continuum", "",
             "Bar L = c = 1, end mass 0.5, unit force at s = 0.37, from rest. **First 20 periods**: the error of the "
             "first impact's time (the reference's first impact against the mesh's nearest; *precursors*: the mesh's "
             "impacts before it, among its first 10: P2's spurious fast waves lift the end off the wall before the "
             "load's front arrives, with energies of 1e-35 to 1e-4) and the contact displacement's largest error "
             "over the first 2 periods and over all 20 (400 "
             "samples), against the continuum at n = 512 steps per L/c (its own error: the n = 256 / 512 difference "
             "below), with the observed orders between successive meshes. **Long run**: 1,000 periods, loss per "
             "period over the last 999 +- its standard error (20 batch means), z-score against the continuum "
             "(n = 64). **Damped** (1 % Rayleigh at T = 2 and 4): the continuum is a Kelvin-Voigt bar with mass "
             "damping, which has no characteristics; its reference is `plbar.continuum.simulate_modal`, exact modes "
             "of each contact state (their number K: the first 20 periods at K = 4096, its error the K = 2048 / 4096 "
             "difference; the long run at K = 1024), xi_w = loss / (2 omega int v^T M v dt) over the last 999 "
             "periods.", ""]
    fe_t = {T: next(r["first"]["t"] for r in fe if r["T"] == T and "t" in r["first"]) for T in TS}
    for T in TS:
        d = c[str(T)]
        ref, coarse = d["first"][str(FIRST_STEPS[-1])], d["first"][str(FIRST_STEPS[0])]
        k = min(len(ref["impact_times"]), len(coarse["impact_times"]))
        self_t = float(np.abs(np.array(ref["impact_times"][:k]) - np.array(coarse["impact_times"][:k])).max())
        self_u = float(np.abs(np.array(ref["u_c"]) - np.array(coarse["u_c"])).max())
        lc = d["long"][str(LONG_STEPS[-1])]
        lc0 = d["long"][str(LONG_STEPS[0])]
        lines += [f"## T/L = {T}", "",
                  f"Continuum: first 20 periods, n = 256 vs 512: impact times {self_t:.1e}, u_c {self_u:.1e}; first "
                  f"impacts at {', '.join(f'{x:.4f}' for x in ref['impact_times'][:4])}; long run loss "
                  f"{lc['loss_per_T']:.4f} +- {lc['loss_se']:.4f} (n = 64), {lc0['loss_per_T']:.4f} +- "
                  f"{lc0['loss_se']:.4f} (n = 32), {lc['impacts_per_T']:.2f} impacts per period, energy residual "
                  f"{lc['energy_residual']:.1e}.", ""]
        for xi in (0.0, 0.01):
            rows = [r for r in fe if r["T"] == T and r["xi_rayleigh"] == xi]
            head = "undamped, against the continuum"
            if xi:
                dc = c["damped"][str(T)]
                K1, K2 = (str(K) for K in DAMPED_FIRST_MODES)
                fref, f1 = dc["first"][K2], dc["first"][K1]
                long1, long2 = (dc["long"][str(K)] for K in DAMPED_LONG_MODES)
                L0, S0 = long2["loss_per_T"], long2["loss_se"]
                k = min(len(fref["impact_times"]), len(f1["impact_times"]))
                head = "1 % Rayleigh damping, against the damped continuum"
                lines += [f"### {head}", "",
                          f"Damped continuum (modes per contact state; K = {K1} vs {K2} for the first 20 periods: "
                          "impact times "
                          f"{np.abs(np.subtract(fref['impact_times'][:k], f1['impact_times'][:k])).max():.1e}, "
                          f"u_c {np.abs(np.subtract(fref['u_c'], f1['u_c'])).max():.1e}, over the first 2 periods "
                          f"{np.abs(np.subtract(fref['u_c'], f1['u_c']))[np.array(fe_t[T]) <= 2 * T].max():.1e}; "
                          "after zero-loss touches just after an opening, which the truncation makes or not, the "
                          "trajectories part); first impacts at "
                          f"{', '.join(f'{x:.6f}' for x in fref['impact_times'][:4])}; long run (K = "
                          f"{DAMPED_LONG_MODES[1]}) loss {L0:.5f} +- {S0:.5f} (K = {DAMPED_LONG_MODES[0]}: "
                          f"{long1['loss_per_T']:.5f}), xi_eq {long2.get('xi_eq', np.nan):.5f}, xi_w "
                          f"{long2['xi_w']:.5f}, {long2['impacts_per_T']:.2f} impacts per "
                          f"period, energy residual {long2['energy_residual']:.0e}, truncation at the switches "
                          f"{long2['transfer_over_work']:.1e} of the work (K = {DAMPED_LONG_MODES[0]}: "
                          f"{long1['transfer_over_work']:.1e}).", ""]
            else:
                L0, S0, fref = lc["loss_per_T"], lc["loss_se"], ref
                lines += [f"### {head}", ""]
            lines += ["| mesh | N | motion | precursors | 1st impact err | order | u_c err, 2 periods | order | "
                      "u_c err, 20 periods | order | loss +- se | z | impacts / T |"
                      + (" xi_eq | xi_w |" if xi else ""),
                      "|---|---|---|---|---|---|---|---|---|---|---|---|---|" + ("---|---|" if xi else "")]
            for el, mass in (("P1", "lumped"), ("P2", "consistent"), ("P2", "redistributed")):
                sel = sorted((r for r in rows if r["element"] == el and r["mass"] == mass), key=lambda r: r["N"])
                if not sel:
                    continue
                errs = [_first_errors(r, fref) for r in sel]
                Ns = [r["N"] for r in sel]
                o = [_orders([e[i] for e in errs], Ns) for i in range(3)]
                for j, (r, e) in enumerate(zip(sel, errs)):
                    ok = r["status"] == 0
                    sd = np.hypot(r["loss_se"], S0)
                    z = (r["loss_per_T"] - L0) / sd if ok and sd else np.nan
                    f = lambda v, p=".1e": "-" if not np.isfinite(v) else format(v, p)  # noqa: E731
                    ti = np.array(r["first"].get("impact_times", []))
                    pre = int(np.sum(ti < fref["impact_times"][0] - 0.05)) if "impact_times" in r["first"] else -1
                    lines.append(f"| {el} {mass} | {r['N']} | {r['kind']} | {pre if pre >= 0 else '-'} | {f(e[0])} | "
                                 f"{f(o[0][j], '.2f')} | {f(e[1])} | {f(o[1][j], '.2f')} | {f(e[2])} | "
                                 f"{f(o[2][j], '.2f')} | "
                                 + (f"{r['loss_per_T']:.4f} +- {r['loss_se']:.4f}" if ok else "-")
                                 + f" | {f(z, '+.1f')} | "
                                 + f"{r['impacts_per_T']:.2f} |"
                                 + (f" {r['xi_eq']:.5f} | {r['xi_w']:.5f} |" if xi else ""))
            lines.append("")
    TABLE.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    if "--run" in sys.argv:
        run()
    if "--damped" in sys.argv:
        run_damped(first_only="--first" in sys.argv, long_only="--long" in sys.argv)
    if "--table" in sys.argv:
        table()
