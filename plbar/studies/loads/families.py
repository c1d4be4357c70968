"""Branch families: which branch is "path 1" / "path 2" in any case.

``plbar.solve`` returns every admissible branch it finds, numbered by their
smallest period; the numbers change with the grid, the load and the mesh.  To
compare cases (load positions, mesh sizes) the branches are grouped into
*families* by the rule below, which uses only the fundamental periods of the
case and the period range of each branch:

1. Anchors: ``"T0_I"`` at ``T0^I`` (the paper's path 1, "near the base period
   of state I") and ``"T0_II/2"`` at ``T0^II / 2`` (path 2, "near half of the
   base period of state II").
2. For a branch with at least ``min_points`` points and period range
   ``[T_min, T_max]``, its distance to anchor ``A`` is
   ``d_A = max(0, T_min - A, A - T_max) / A`` (0 if the range contains ``A``).
   The branch is a *candidate* of its nearest anchor if ``d_A <= tol``.
3. The *main* branch of a family is its candidate with the smallest ``d_A``
   (ties: more points, then lower id).
4. The family is the main branch plus every other candidate of the same anchor
   whose period range overlaps the main one's widened by ``join * A`` (pieces
   of one curve cut by an inadmissible or under-resolved stretch).
5. Every other branch is ``"other"`` (constant-``T`` fragments, far branches).

For the chain ``N = 5`` this gives path 1 = ``T in [9.90, 10.81]`` and path 2
= ``T in [11.33, 12.58]`` for every load position.  The anchors approach each
other as the mesh is refined (``T0^I -> T0^II / 2`` for a uniform bar without
tip mass), so for fine FE meshes the split into two families is only as good
as the gap between the branches; :mod:`plbar.refine` also reports the
family-free maximum of ``xi_eq`` over all branches.
"""

from __future__ import annotations

__all__ = ["FAMILIES", "OTHER", "anchors", "assign_families"]

FAMILIES = ("T0_I", "T0_II/2")
OTHER = "other"


def anchors(T0_I: float, T0_II: float) -> dict[str, float]:
    """Anchor period of each family."""
    return {"T0_I": float(T0_I), "T0_II/2": 0.5 * float(T0_II)}


def _dist(lo: float, hi: float, a: float) -> float:
    return max(0.0, lo - a, a - hi) / a


def assign_families(ranges, npoints, T0_I: float, T0_II: float, tol: float = 0.1,
                    min_points: int = 4, join: float = 0.005) -> list[str]:
    """Family label of each branch (see the module docstring for the rule).

    Parameters
    ----------
    ranges : sequence of (T_min, T_max)
        Period range of each branch.
    npoints : sequence of int
        Points per branch.
    T0_I, T0_II : float
        Fundamental periods of the case.
    tol, min_points, join : float, int, float
        Rule parameters.

    Returns
    -------
    list of str
        One of :data:`FAMILIES` or :data:`OTHER` per branch.
    """
    anc = anchors(T0_I, T0_II)
    labels = [OTHER] * len(ranges)
    cand: dict[str, list[tuple[float, int, int]]] = {f: [] for f in anc}
    for i, ((lo, hi), n) in enumerate(zip(ranges, npoints)):
        if n < min_points:
            continue
        d = {f: _dist(lo, hi, a) for f, a in anc.items()}
        f = min(d, key=lambda k: (d[k], FAMILIES.index(k)))
        if d[f] <= tol:
            cand[f].append((d[f], -int(n), i))
    for f, cs in cand.items():
        if not cs:
            continue
        _, _, main = min(cs)
        lo, hi = ranges[main]
        w = join * anc[f]
        for _, _, i in cs:
            a, b = ranges[i]
            if i == main or (a <= hi + w and b >= lo - w):
                labels[i] = f
    return labels
