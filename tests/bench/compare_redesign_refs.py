"""Compare today's outputs with the redesign references in ``tests/data/redesign`` (regression snapshots).

    python tests/bench/compare_redesign_refs.py [--keep DIR]

Runs the four commands of ``tests/data/redesign/README.md`` into a temporary folder and prints, per file, whether
the rows are the same and the largest relative difference of each numeric column (relative to the column's largest
value).  ``paths.csv`` rows are matched by point, not by order (a redesign may renumber the branches): signature,
``T`` and ``T1`` to 8 and 6 decimals; rows without a match are counted.  ``survey.csv`` rows are matched in order.
Where the points differ, ``tests/bench/compare_curves.py`` says whether they lie on the same curves.
"""

from __future__ import annotations

import csv
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
REF = ROOT / "tests" / "data" / "redesign"
RUNS = {
    "default_run_paths.csv": (["run", "--no-plot"], "paths.csv"),
    "restitution_0.3_paths.csv": (["run", "--restitution", "0.3", "--no-plot"], "paths.csv"),
    "fe_p2_consistent_paths.csv": (["run", str(ROOT / "examples/cases/fe_p2_consistent.toml"), "--no-plot"],
                                   "paths.csv"),
    "default_survey.csv": (["survey", "--no-plot", "--no-paths"], "survey.csv"),
}


def _read(path: Path) -> tuple[list[str], list[list[str]]]:
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]


def _by_point(h0, r0, h1, r1):
    """The matched row pairs of ``r0`` and ``r1`` (by signature, T, T1) and the count of rows without a match."""
    cols = ("signature", "T", "T1")
    k0, k1 = [h0.index(c) for c in cols], [h1.index(c) for c in cols]

    def key(r, k):
        return r[k[0]], round(float(r[k[1]]), 8), round(float(r[k[2]]), 6)

    at: dict = {}
    for j, r in enumerate(r1):
        at.setdefault(key(r, k1), []).append(j)
    a, b, missing = [], [], 0
    for r in r0:
        js = at.get(key(r, k0))
        if js:
            a.append(r)
            b.append(r1[js.pop(0)])
        else:
            missing += 1
    return a, b, missing + sum(len(v) for v in at.values())


def compare(ref: Path, new: Path) -> list[str]:
    """Lines saying how ``new`` differs from ``ref``."""
    h0, r0 = _read(ref)
    h1, r1 = _read(new)
    out = []
    if h0 != h1:
        out.append(f"  header differs: {sorted(set(h0) ^ set(h1))}")
    if "durations" in h0 and "durations" in h1:                 # paths.csv
        r0, r1, unmatched = _by_point(h0, r0, h1, r1)
        if unmatched:
            out.append(f"  {unmatched} rows without a match ({len(r0)} matched)")
        j0, j1 = h0.index("branch"), h1.index("branch")
        r0 = [r[:j0] + ["0"] + r[j0 + 1:] for r in r0]              # branch ids: renumbered, not compared
        r1 = [r[:j1] + ["0"] + r[j1 + 1:] for r in r1]
    if len(r0) != len(r1):
        return out + [f"  rows {len(r0)} -> {len(r1)}"]
    for j, name in enumerate(h0):
        if name not in h1:
            continue
        k = h1.index(name)
        a, b = [r[j] for r in r0], [r[k] for r in r1]
        try:
            x, y = np.array([float(v or "nan") for v in a]), np.array([float(v or "nan") for v in b])
        except ValueError:
            if a != b:
                out.append(f"  {name}: {sum(u != v for u, v in zip(a, b, strict=True))} text cells differ")
            continue
        scale = np.nanmax(np.abs(x)) if np.isfinite(x).any() else 1.0
        same_nan = np.isnan(x) == np.isnan(y)
        d = np.nanmax(np.abs(x - y)) / (scale or 1.0) if np.isfinite(x - y).any() else 0.0
        if not same_nan.all() or d > 0:
            out.append(f"  {name}: max |diff| / max |ref| = {d:.3g}, blank cells differ: {int((~same_nan).sum())}")
    return out


def main(argv: list[str]) -> int:
    keep = Path(argv[argv.index("--keep") + 1]) if "--keep" in argv else Path(tempfile.mkdtemp())
    worst = 0
    for ref, (args, produced) in RUNS.items():
        out = keep / ref.removesuffix(".csv")
        subprocess.run([sys.executable, "-m", "plbar", *args, "--out", str(out), "--quiet", "--overwrite"],
                       check=True)
        lines = compare(REF / ref, out / produced)
        print(f"{ref}: {'identical' if not lines else 'differs'}")
        print("\n".join(lines)) if lines else None
        worst = max(worst, bool(lines))
    return worst


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
