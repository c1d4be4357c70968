"""Do two ``paths.csv`` of one case hold the same curves?  Every point of each on a curve of the other.

    python tests/bench/compare_curves.py OLD.csv NEW.csv [--restitution E | --case FILE.toml] [--tol 1e-10]

A redesign may change which points of a curve are computed, not the curves (issue 40).  A point ``P`` (one row:
signature, ``T``, durations, ``phi``) lies on a curve of the other table when, for a piece of one of its branches
(two neighbouring rows, same signature and rotation) whose scaled segment passes near ``P`` (the continuation's
scaling, within the piece's length), the orbit at ``P``'s ``T`` polished from the piece's interpolation
(:func:`plbar.periodic.polish`) is ``P`` itself: ``T1``, ``dPL`` and ``xi`` agree to ``--tol`` (relative to the
column's largest value).  Prints, per signature and direction, how many points lie on the other's curves and where
the others are (their ``T`` ranges).  Both tables' orbits are rebuilt from their rows
(:func:`plbar.periodic.from_row`).
"""

from __future__ import annotations

import argparse
import csv
import sys
from collections import defaultdict

import numpy as np


def _rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def _orbits(prob, rows):
    from plbar.periodic import NotConverged, from_row, signature

    out = []
    for r in rows:
        sig = signature(r["signature"])
        try:
            o = from_row(prob, sig, float(r["T"]), [float(x) for x in r["durations"].split(";")], float(r["phi"]))
        except (NotConverged, ValueError, np.linalg.LinAlgError):
            o = None
        out.append((int(r["branch"]), r, o))
    return out


def _pieces(orbs):
    """Per signature: a list of (orbit a, orbit b) of neighbouring rows of one branch."""
    by = defaultdict(list)
    for (ba, _, a), (bb, _, b) in zip(orbs[:-1], orbs[1:]):
        if ba == bb and a is not None and b is not None and a.sig == b.sig:
            by[a.sig].append((a, b))
    return by


def _on(prob, o, pieces, tol, scale):
    """Whether orbit ``o`` lies on one of ``pieces`` (see the module docstring)."""
    from plbar.periodic import NotConverged, polish
    from plbar.periodic.follow import scale_of

    Y = np.r_[o.X, o.T]
    S = scale_of(prob, o.sig, o.X, o.T)
    best = []
    for a, b in pieces:
        A, B = np.r_[a.X, a.T], np.r_[b.X, b.T]
        d, r = (B - A) / S, (Y - A) / S
        d[-2] = np.angle(np.exp(1j * d[-2]))
        r[-2] = np.angle(np.exp(1j * r[-2]))
        n2 = float(d @ d)
        u = float(np.clip(r @ d / n2, 0.0, 1.0)) if n2 > 0 else 0.0
        miss = float(np.linalg.norm(r - u * d))
        if miss <= np.sqrt(n2) + 1e-9:
            best.append((miss, a, b, u))
    for _, a, b, u in sorted(best, key=lambda x: x[0])[:4]:
        try:
            q = polish(prob, o.sig, o.T, (1 - u) * a.X + u * b.X)
        except (NotConverged, ValueError, np.linalg.LinAlgError):
            continue
        T1 = lambda x: float(x.durations[0::2].sum())  # noqa: E731
        if (abs(T1(q) - T1(o)) <= tol * scale["T1"] and abs(q.dPL - o.dPL) <= tol * scale["dPL"]
                and abs(q.xi - o.xi) <= tol * scale["xi"]):
            return True
    return False


def compare(prob, old, new, tol: float = 1e-10) -> int:
    oo, nn = _orbits(prob, _rows(old)), _orbits(prob, _rows(new))
    scale = {k: max(abs(float(r[k])) for _, r, _ in oo + nn) or 1.0 for k in ("T1", "dPL", "xi")}
    bad = 0
    for name, src, dst in (("old on new", oo, nn), ("new on old", nn, oo)):
        pieces = _pieces(dst)
        stats = defaultdict(lambda: [0, 0, []])
        for _, r, o in src:
            st = stats[r["signature"]]
            st[0] += 1
            if o is not None and _on(prob, o, pieces.get(o.sig, []), tol, scale):
                st[1] += 1
            else:
                st[2].append(float(r["T"]))
        print(f"{name}:")
        for lab, (n, k, miss) in sorted(stats.items(), key=lambda x: (len(x[0]), x[0])):
            where = ""
            if miss:
                m = np.sort(miss)
                cuts = np.flatnonzero(np.diff(m) > 0.02) + 1
                where = "; off: " + ", ".join(f"[{g[0]:.5g}, {g[-1]:.5g}] ({len(g)})" for g in np.split(m, cuts)[:8])
            print(f"  {lab:8s} {k}/{n} on a curve{where}")
            bad += n - k
    return bad


def main(argv) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--restitution", type=float, default=0.0)
    ap.add_argument("--case", default=None)
    ap.add_argument("--tol", type=float, default=1e-10)
    a = ap.parse_args(argv)
    import plbar
    from plbar.app import load_case

    case = load_case(a.case)[0] if a.case else plbar.Case(restitution=a.restitution)
    compare(case.problem(), a.old, a.new, a.tol)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
