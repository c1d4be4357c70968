"""Linking the scan's crossings into curves by the marching-squares topology."""

from __future__ import annotations

import numpy as np

__all__ = ["link", "curves_grid", "GRID_END"]

GRID_END = "grid chain end"   #: how a marching-squares chain ends (no continuation)


def link(G: np.ndarray, hmask: np.ndarray, vmask: np.ndarray) -> list[list[int]]:
    """Chains of crossing edges by marching-squares topology.

    Edges are numbered as in :class:`plbar.paths.scan.Scan`.  A cell with four
    crossing edges (a saddle) is resolved by the sign of the centre value.
    Returns a list of edge-id lists.
    """
    n1, n2 = G.shape
    H = (n1 - 1) * n2
    pos = G >= 0
    bottom = hmask[:, :-1]
    top = hmask[:, 1:]
    left = vmask[:-1, :]
    right = vmask[1:, :]
    cnt = bottom.astype(int) + top + left + right
    I, J = np.meshgrid(np.arange(n1 - 1), np.arange(n2 - 1), indexing="ij")
    eb = I * n2 + J
    et = I * n2 + J + 1
    el = H + I * (n2 - 1) + J
    er = H + (I + 1) * (n2 - 1) + J
    pairs = []
    for i, j in zip(*np.nonzero(cnt == 2)):
        es = [e[i, j] for e, m in ((eb, bottom), (et, top), (el, left), (er, right)) if m[i, j]]
        pairs.append((es[0], es[1]))
    for i, j in zip(*np.nonzero(cnt == 4)):
        centre = (G[i, j] + G[i + 1, j] + G[i, j + 1] + G[i + 1, j + 1]) >= 0
        if centre == pos[i, j]:
            pairs += [(eb[i, j], er[i, j]), (el[i, j], et[i, j])]
        else:
            pairs += [(eb[i, j], el[i, j]), (er[i, j], et[i, j])]
    adj: dict[int, list[int]] = {}
    for a, b in pairs:
        adj.setdefault(int(a), []).append(int(b))
        adj.setdefault(int(b), []).append(int(a))
    nodes = set(int(e) for e in np.flatnonzero(hmask.ravel())) | \
        set(int(H + e) for e in np.flatnonzero(vmask.ravel()))
    seen: set[int] = set()
    chains = []
    for start in sorted(nodes, key=lambda e: (len(adj.get(e, [])), e)):
        if start in seen:
            continue
        chain = [start]
        seen.add(start)
        cur = start
        while True:
            nxt = [e for e in adj.get(cur, []) if e not in seen]
            if not nxt:
                break
            cur = nxt[0]
            seen.add(cur)
            chain.append(cur)
        chains.append(chain)
    return chains


def curves_grid(sc) -> list:
    """Marching-squares chains of a :class:`~plbar.paths.scan.Scan` as curves: list of (indices into ``P``, ends)."""
    where = {int(e): k for k, e in enumerate(sc.ids)}
    out = []
    for chain in link(sc.G, sc.hmask, sc.vmask):
        out.append(([where[e] for e in chain if e in where], (GRID_END, GRID_END)))
    return out
