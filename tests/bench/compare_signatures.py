"""Are the branches of every signature of this checkout the same curves as a baseline's?

A speed-up of the hybrid solver may change which points are computed, not the curves.  ``save``
solves the default case (``Case(signatures="default")``, or damped with ``--damping-ratio Z``:
Rayleigh ``Z`` at ``T = 6`` and ``14``) with the ``plbar`` on ``PYTHONPATH`` and stores every hybrid
branch (signature, ``T``, ``loss_per_T``, ``xi``, ``stable``, unknowns ``X``) in a json file;
``compare`` checks a result against a baseline both ways, on the curves.  For every point ``P`` of a
branch of one side:

* the other side's branches of the same canonical signature whose ``T`` range covers ``P``'s ``T``
  (within :data:`COVER`) are candidates; ``P`` is written in a candidate's rotation of the signature;
* from the candidate's point nearest ``P`` (scaled as the continuation scales: within :data:`NEAR`, else
  the candidate does not reach ``P``) Newton finds the candidate curve's point on the hyperplane through
  ``P`` normal to that curve's tangent (:func:`plbar.periodic.follow.correct`; at fixed ``T`` where the curve
  is not vertical this is :func:`plbar.periodic.polish` at ``P``'s ``T``, and it stays well posed where the
  curve turns vertical in ``T``);
* the point *matches* when it is ``P`` to :data:`DIST` (largest scaled difference of the unknowns) and its
  ``loss_per_T`` and ``xi`` are ``P``'s to :data:`TOL` relative to the largest of all branches on its
  side (near grazing, ``v_c -> 0``, a loss is the square of a small number: two orbits at the same point
  with residuals at round-off differ there by up to 1e-7 relative; the relative differences are reported
  too); its stability is recomputed (Floquet multipliers) and compared.

A branch is *found* when every point matches; whether one branch of the other side
covers its whole ``T`` range is reported too (a curve can be cut into admissible runs differently).

    PYTHONPATH=<base checkout> python tests/bench/compare_signatures.py save /tmp/hybrid_baseline.json
    python tests/bench/compare_signatures.py compare /tmp/hybrid_baseline.json [/tmp/new.json]

  Without a
second file ``compare`` solves with this checkout.  Exits 1 if a branch of either side is not found.
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np

import plbar
from plbar.periodic import NotConverged, evaluate, monodromy, multipliers, orbit_at, polish, signature
from plbar.periodic.follow import correct, scale_of

TOL = 1e-9          #: largest relative difference of loss_per_T and xi between the curves
COVER = 0.03        #: a branch covers a point within this fraction of its T beyond its ends
DIST = 1e-8         #: largest scaled distance of a matched point
NEAR = 0.5          #: largest scaled distance from a point to a candidate's nearest point (3 longest steps)
STABLE_TOL = 1e-9   #: as plbar.periodic.branches (a multiplier within this of the unit circle is unstable)


def case_of(argv) -> plbar.Case:
    """The default case, damped with ``--damping-ratio Z`` (Rayleigh ``Z`` at ``T = 6`` and ``14``)."""
    if "--damping-ratio" in argv:
        from plbar.model import rayleigh_from_ratio

        z = float(argv[argv.index("--damping-ratio") + 1])
        return plbar.Case(signatures="default", rayleigh=rayleigh_from_ratio(z, 6.0, 14.0))
    return plbar.Case(signatures="default")


def branches_of(res) -> list[dict]:
    """The hybrid branches of a result as plain data."""
    return [{"label": b.label, "sig": str(b.sig), "T": b.T.tolist(), "loss_per_T": b.loss_per_T.tolist(),
             "xi": b.xi.tolist(), "stable": b.stable.astype(int).tolist(), "X": [o.X.tolist() for o in b.orbits]}
            for b in [b for b in res.branches if not b.paper]]


def save(path, argv) -> None:
    t = time.perf_counter()
    res = plbar.solve(case_of(argv))
    others = [b for b in res.branches if not b.paper]
    print(f"solved in {time.perf_counter() - t:.2f} s with {plbar.__file__}: {len(others)} branches, "
          f"{sum(len(b) for b in others)} points")
    with open(path, "w") as fh:
        json.dump(branches_of(res), fh)


def _rel(a, b) -> float:
    return abs(a - b) / max(abs(b), 1e-300)


def rotated(prob, sig, T: float, X, target):
    """The unknowns of the orbit ``(sig, T, X)`` written from the rotation ``target`` of its signature (or None)."""
    if target == sig:
        return np.asarray(X, float)
    for r in range(1, sig.k):
        if sig.dwell[r:] + sig.dwell[:r] != target.dwell:
            continue
        o = orbit_at(prob, sig, T, np.asarray(X, float))
        free = [s for s in o.chain.segments if s.state == 2]
        G = np.asarray(prob.system.Q21, float)
        P = np.asarray(prob.system.P21, float)
        m2 = prob.system.w2.size
        z1 = free[r - 1].z1
        z = np.concatenate([P @ z1[:m2], G @ z1[m2:]])          # the state just after impact r - 1
        d = np.concatenate([o.durations[2 * r:], o.durations[:2 * r]])
        var = [x for i, x in enumerate(d) if i % 2 or target.dwell[i // 2]]
        t_r = float(np.sum(o.durations[:2 * r]))
        X2 = np.concatenate([z, var, [np.mod(o.phi - 2 * np.pi / T * t_r, 2 * np.pi)]])
        try:
            return polish(prob, target, T, X2).X
        except NotConverged:
            return None
    return None


def _tangent(prob, sig, Y, S):
    """Unit tangent of the curve at ``Y = (X, T)`` in scaled coordinates (exact Jacobian in X, central difference
    in T)."""
    X, T = Y[:-1], Y[-1]
    h = 1e-6 * T
    dT = (evaluate(prob, sig, T + h, X, jac=False).F - evaluate(prob, sig, T - h, X, jac=False).F) / (2 * h)
    A = np.hstack([evaluate(prob, sig, T, X).J, dT[:, None]]) * S[None, :]
    return np.linalg.svd(A)[2][-1]


def match_point(prob, sig, T, X, cands):
    """``(orbit, distance)``: the candidates' curve point on the plane through ``(X, T)`` normal to its tangent,
    from the nearest candidate point (None where no candidate reaches it)."""
    best, dist = None, np.inf
    for c in cands:
        Ts = np.asarray(c["T"])
        if not Ts.min() - COVER * T <= T <= Ts.max() + COVER * T:
            continue
        csig = signature(c["sig"])
        Xr = rotated(prob, sig, T, X, csig)
        if Xr is None:
            continue
        Yb = np.concatenate([Xr, [T]])
        S = scale_of(prob, csig, Xr, T)
        Ys = np.array([np.concatenate([x, [t]]) for x, t in zip(c["X"], c["T"])])
        d = np.max(np.abs(Ys - Yb) / S, axis=1)
        i = int(np.argmin(d))
        if d[i] > NEAR:
            continue
        if d[i] < 1e-13:
            o = orbit_at(prob, csig, T, Xr)
        else:
            t = _tangent(prob, csig, Ys[i], S)
            o = correct(prob, csig, Ys[i] + (t @ ((Yb - Ys[i]) / S)) * t * S, t, S)
        if o is None:
            continue
        dd = float(np.max(np.abs(np.concatenate([o.X, [o.T]]) - Yb) / S))
        if dd < dist:
            best, dist = o, dd
    return best, dist


def check_side(prob, ours, theirs, name: str) -> int:
    """Match every branch of ``ours`` on ``theirs``; print one line per branch; the number not found."""
    missing, worst = 0, np.zeros(5)
    Lmax, xmax = max(max(np.abs(c["loss_per_T"])) for c in ours), max(max(np.abs(c["xi"])) for c in ours)
    for k, b in enumerate(ours):
        cands = [c for c in theirs if c["label"] == b["label"]]
        lo, hi = min(b["T"]), max(b["T"])
        whole = any(min(c["T"]) - COVER * lo <= lo and hi <= max(c["T"]) + COVER * hi for c in cands)
        ok, fl, w = 0, 0, np.zeros(5)
        for T, L, xi, st, X in zip(b["T"], b["loss_per_T"], b["xi"], b["stable"], b["X"]):
            o, dist = match_point(prob, signature(b["sig"]), T, np.asarray(X), cands)
            if o is None:
                continue
            e = np.array([_rel(o.loss_per_T, L), _rel(o.xi, xi), abs(o.loss_per_T - L) / Lmax,
                          abs(o.xi - xi) / max(xmax, 1e-300), dist])
            w = np.maximum(w, e)
            if e[2] <= TOL and e[3] <= TOL and dist <= DIST:
                ok += 1
                mu = np.abs(multipliers(monodromy(prob, o.sig, o.T, o.phi, o.chain))).max()
                fl += int(bool(mu < 1 - STABLE_TOL) != bool(st))
        n = len(b["T"])
        missing += ok != n
        worst = np.maximum(worst, w)
        print(f"  {name} {k:3d} {b['label']:8s} T {lo:8.4f}..{hi:8.4f} {n:4d} pts: matched {ok:4d}  relative loss "
              f"{w[0]:.1e} xi {w[1]:.1e}, to the largest {w[2]:.1e} {w[3]:.1e}, distance {w[4]:.1e}, "
              f"stability flips {fl}  {'one branch covers' if whole else 'SPLIT'}{'' if ok == n else '  NOT FOUND'}")
    print(f"{name}: {len(ours) - missing}/{len(ours)} branches found; max relative loss {worst[0]:.2e}, xi "
          f"{worst[1]:.2e}; to the largest {worst[2]:.2e}, {worst[3]:.2e}; scaled distance {worst[4]:.2e}")
    return missing


def compare(base_path, new_path, argv) -> int:
    with open(base_path) as fh:
        base = json.load(fh)
    if new_path is None:
        res = plbar.solve(case_of(argv))
        new, prob = branches_of(res), res.prob
    else:
        with open(new_path) as fh:
            new = json.load(fh)
        prob = case_of(argv).problem()
    print(f"baseline {len(base)} branches ({sum(len(b['T']) for b in base)} points), new {len(new)} branches "
          f"({sum(len(b['T']) for b in new)} points)")
    print("baseline branches on the new curves:")
    lost = check_side(prob, base, new, "baseline")
    print("new branches on the baseline's curves:")
    extra = check_side(prob, new, base, "new")
    return 1 if lost or extra else 0


def main(argv) -> int:
    if len(argv) >= 2 and argv[0] == "save":
        save(argv[1], argv[2:])
        return 0
    if len(argv) >= 2 and argv[0] == "compare":
        files = [a for a in argv[1:3] if a.endswith(".json")]
        return compare(files[0], files[1] if len(files) > 1 else None, argv)
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
