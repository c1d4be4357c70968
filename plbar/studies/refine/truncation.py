"""Convergence of the modal truncation: paths with the lowest modes against a finer model.

Modal truncation keeps the path geometry but is not to be used for ``xi_eq``:
the impact projects the velocities onto the kept state I modes, and the
kinetic energy outside them is counted as lost (README, Speed).
"""

from __future__ import annotations

import time

import numpy as np

from ...model import Bar, Load, bar_structure, problem
from ...paths import default_domain, find_paths

__all__ = ["truncation_check"]


def _match(br, bt) -> dict:
    """The branch of ``bt`` that overlaps ``br`` most in ``T``, and their differences in ``T`` range and ``xi``."""
    lo, hi = float(br.T.min()), float(br.T.max())
    best, ov = None, -1.0
    for b in bt:
        o = min(hi, float(b.T.max())) - max(lo, float(b.T.min()))
        if o > ov or (best is None and o == ov):
            best, ov = b, o
    if best is None or ov < 0:
        return {"ref_branch": br.id, "T": [lo, hi], "match": None}
    dT = max(abs(float(best.T.min()) - lo), abs(float(best.T.max()) - hi)) / hi
    dxi = np.nan
    xa, ta = np.asarray(br.xi), np.asarray(br.T)
    xb, tb = np.asarray(best.xi), np.asarray(best.T)
    if len(ta) > 1 and len(tb) > 1 and np.all(np.diff(ta) > 0) and np.all(np.diff(tb) > 0):
        tt = ta[(ta >= tb[0]) & (ta <= tb[-1])]
        if tt.size:
            dxi = float(np.max(np.abs(np.interp(tt, tb, xb) - np.interp(tt, ta, xa)))
                        / max(float(np.abs(xa).max()), 1e-300))
    return {"ref_branch": br.id, "branch": best.id, "T": [lo, hi], "T_trunc": [float(best.T.min()),
            float(best.T.max())], "xi_range": [float(xa.min()), float(xa.max())],
            "xi_range_trunc": [float(xb.min()), float(xb.max())], "rel_T": dT, "rel_xi": dxi}


def truncation_check(bar: Bar, load: Load, modes, grid: tuple[int, int] = (200, 200), domain=None,
                     method: str = "continuation", ref_modes="double") -> dict:
    """Convergence of the modal truncation: the paths with ``modes`` modes against a finer model.

    Solves the paths with ``modes`` modes and with ``ref_modes`` (default
    ``2 * modes``; ``None`` for the full model) on the same domain and grid
    (the domain of the finer model by default), and compares the branches
    by their ``T`` ranges: each branch of the reference is matched with the
    branch of the truncated model that overlaps it most in ``T``; for the
    matched pairs, ``xi`` is interpolated at common ``T`` values (only
    monotone stretches in ``T``).

    Returns
    -------
    dict
        ``modes``, ``ref_modes``, the branch counts, ``max_rel_T`` (largest
        relative difference of the ``T`` range ends), ``max_rel_xi`` (largest
        difference of ``xi`` relative to the branch's largest ``xi``), the
        times of both solves, and per matched branch ``rows``.
    """
    if ref_modes == "double":
        m = (modes, modes) if np.ndim(modes) == 0 else tuple(modes)
        ref_modes = (2 * int(m[0]), 2 * int(m[1]))
    out = {"modes": modes, "ref_modes": ref_modes}
    st = bar_structure(bar, load)
    res = {}
    for key, mm in (("ref", ref_modes), ("trunc", modes)):
        t0 = time.perf_counter()
        prob = problem(st, modes=mm)
        if domain is None:
            domain = default_domain(prob)
        res[key] = find_paths(prob, domain, grid, method=method)
        out[f"time_{key}"] = time.perf_counter() - t0
    bt = list(res["trunc"].branches)
    rows = [_match(br, bt) for br in res["ref"].branches]
    out["branches_ref"] = len(res["ref"].branches)
    out["branches_trunc"] = len(bt)
    m = [r for r in rows if r.get("match", 1) is not None]
    out["max_rel_T"] = max((r["rel_T"] for r in m), default=np.nan)
    out["max_rel_xi"] = max((r["rel_xi"] for r in m if np.isfinite(r["rel_xi"])), default=np.nan)
    out["rows"] = rows
    out["paths"] = res
    return out
