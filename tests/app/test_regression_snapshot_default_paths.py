"""Regression snapshot: the default run's ``paths.csv`` agrees with plbar's own stored past output to 1e-10.

This is a regression guard, not a check of correctness: the reference is plbar's own output.  What makes it right
is checked independently elsewhere (the chain's equations, the simulator's replay, the closed forms).

The reference (``tests/data/default_paths_reference.csv``) was written by
``plbar run --out DIR --no-plot`` before the speed work (issue "Speed"); every
optimisation of the core must leave the default result unchanged: the same
rows and branches, the numeric columns to a relative 1e-10 (with an absolute
floor of 1e-12 of the column's largest magnitude, for values that are zero
up to round-off), the flags ``grazing`` and ``stable`` exactly.

One documented exception: ``max_abs_multiplier`` at exactly grazing points
(reference ``dPL`` below ``1e-10`` of the column's largest value, i.e. an impact
velocity at round-off level).  The impact saltation matrix scales with
``1 / v_c``, so there the multipliers amplify round-off-level changes of the
path point (1e-12 relative) by ``1 / v_c`` (about 1e7); they are compared to
``GRAZING_MU_RTOL``.
"""

from pathlib import Path

import numpy as np

from plbar.app import CSV_HEADER, TEXT_COLUMNS, read_paths, write_results

REF = Path(__file__).parents[1] / "data" / "default_paths_reference.csv"
RTOL = 1e-10
ATOL_REL = 1e-12
EXACT = ("branch", "grazing", "stable")
GRAZING_MU_RTOL = 1e-6


def _read(path, paper_branches=None):
    """Header and the numeric columns of the paper's class as the scan finds it (the first ``paper_branches``
    branches: the others are a few branches of the paper's class found off its search domain, then the other
    signatures)."""
    if "signature" not in Path(path).read_text().split("\n", 1)[0]:      # the stored reference: numbers only
        with open(path) as fh:
            header = fh.readline().strip().split(",")
        return header, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    cols = read_paths(path)
    header = list(cols)
    keep = np.asarray(cols["branch"], float) < paper_branches
    data = np.column_stack([np.asarray(cols[c], float)[keep] for c in header if c not in TEXT_COLUMNS])
    return [c for c in header if c not in TEXT_COLUMNS], data


def test_default_paths_match_reference(default_run, tmp_path):
    """The default run (every signature) keeps the paper's class of the reference, row for row."""
    assert any(not b.paper for b in default_run.branches), "the default run finds the other signatures"
    write_results(default_run, tmp_path)
    h_new, new = _read(tmp_path / "paths.csv", len(default_run.paths.branches))
    h_ref, ref = _read(REF)
    assert h_new == [c for c in CSV_HEADER if c not in TEXT_COLUMNS] and h_new[:len(h_ref)] == h_ref  # added later
    assert new.shape[0] == ref.shape[0], f"{new.shape[0]} rows vs {ref.shape[0]} in the reference"
    col = {c: k for k, c in enumerate(h_ref)}
    assert np.unique(new[:, col["branch"]]).size == np.unique(ref[:, col["branch"]]).size
    for c in h_ref:
        a, b = new[:, col[c]], ref[:, col[c]]
        if c in EXACT:
            bad = np.flatnonzero(a != b)
            assert bad.size == 0, f"column {c} differs at rows {bad[:10]}"
        else:
            atol = ATOL_REL * np.abs(b).max()
            rtol = np.full(b.shape, RTOL)
            if c == "max_abs_multiplier":
                d = ref[:, col["dPL"]]
                rtol[d < 1e-10 * np.abs(d).max()] = GRAZING_MU_RTOL
            err = np.abs(a - b) - (atol + rtol * np.abs(b))
            k = int(np.argmax(err))
            assert err[k] <= 0, f"column {c} row {k}: {a[k]!r} vs reference {b[k]!r}"
