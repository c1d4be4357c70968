"""The grid scan of ``G(T^I, T^II)`` and the refinement of its sign changes (paper Sec. 4.1, FORMULATION §4).

The paper scans the 3D space ``(T^I, T^II, phi)``; with ``phi`` eliminated
exactly the paths are the zero set of the one scalar field
:func:`plbar.response.scan_function` on the ``(T^I, T^II)`` plane.  This module
evaluates it on a grid (in memory-bounded chunks on a thread pool) and
refines every grid edge with a sign change to machine precision with the one
bracketed root finder, :func:`plbar.util.roots.solve`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Problem
from ..response import Coefficients, coefficients, scan_G
from ..response.onemap import bytes_per_point
from ..util.blas import single_thread_blas
from ..util.progress import progress_bar
from ..util.roots import solve
from ..util.threads import map_chunks

__all__ = ["Scan", "scan", "scan_field", "grid_axes", "chunked_G", "chunked_coefficients", "PAR_CHUNK"]

CHUNK_BYTES = 32e6  #: temporaries per batch of the chunked evaluations (bytes)
PAR_CHUNK = 2000    #: smallest batch of points worth a thread of its own


def _chunks(prob: Problem, T1, T2, fun, done=None) -> list:
    step = max(1, int(CHUNK_BYTES // bytes_per_point(prob)))
    with single_thread_blas:
        return map_chunks(lambda a, b: fun(prob, T1[a:b], T2[a:b]), T1.size, PAR_CHUNK, step, done)


def chunked_G(prob: Problem, T1, T2, done=None) -> np.ndarray:
    """:func:`plbar.response.scan_G` at 1D arrays ``T1, T2``, in batches of about ``CHUNK_BYTES``
    (``done``: called with the points of each batch as it comes in, see :func:`plbar.util.threads.map_chunks`)."""
    return np.concatenate(_chunks(prob, T1, T2, scan_G, done))


def chunked_coefficients(prob: Problem, T1, T2) -> Coefficients:
    """:func:`plbar.response.coefficients` at 1D arrays ``T1, T2``, in batches."""
    parts = _chunks(prob, T1, T2, coefficients)
    if len(parts) == 1:
        return parts[0]
    return Coefficients(*[np.concatenate([getattr(p, f) for p in parts]) for f in Coefficients.__dataclass_fields__])


def grid_axes(domain, grid: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Grid axes over ``domain`` (an open lower end 0 is left out: the scan starts at ``high / n``)."""
    axes = []
    for (lo, hi), n in zip((domain.T1, domain.T2), grid):
        axes.append(np.linspace(lo, hi, n + 1)[1:] if lo == 0 else np.linspace(lo, hi, n))
    return axes[0], axes[1]


def scan_field(prob: Problem, domain, grid: tuple[int, int], progress: bool = False):
    """Grid axes and ``G`` on the grid, shape ``(n1, n2)`` (with a progress bar counting the batches; the
    batches, and so every bit of ``G``, are the same without it)."""
    t1, t2 = grid_axes(domain, grid)
    G1, G2 = np.meshgrid(t1, t2, indexing="ij")
    with progress_bar(t1.size * t2.size, progress, "scanning", "point") as bar:
        return t1, t2, chunked_G(prob, G1.ravel(), G2.ravel(), bar.update).reshape(t1.size, t2.size)


def refine_edges(prob: Problem, Pa, Pb, Ga, Gb, progress: bool = False):
    """Exact zeros of ``G`` on the segments ``Pa -> Pb`` (each (E, 2)); returns the points and the rounds used.

    With ``progress``, a bar counts the crossings refined to round-off (a round evaluates every open one).
    """
    span = np.abs(Pb - Pa).max(axis=1)
    scale = np.maximum(np.abs(Pa).max(axis=1), np.abs(Pb).max(axis=1))
    with progress_bar(len(Pa), progress, "refining crossings", "crossing") as bar:
        left = [len(Pa)]

        def f(idx, s):
            bar.update(left[0] - idx.size)                 # the brackets closed since the last round
            left[0] = idx.size
            P = Pa[idx] + s[:, None] * (Pb[idx] - Pa[idx])
            return chunked_G(prob, P[:, 0], P[:, 1])

        r = solve(f, 0.0, 1.0, Ga, Gb, 4 * np.finfo(float).eps * scale / span)
        bar.update(left[0])
    return Pa + r.x[:, None] * (Pb - Pa), r.iterations


@dataclass(frozen=True)
class Scan:
    """A grid scan: axes, ``G`` on the grid, the sign-change edges and their refined zeros.

    Edges are numbered: horizontal ``(i, j)-(i+1, j)`` as ``i n2 + j``; vertical
    ``(i, j)-(i, j+1)`` as ``(n1-1) n2 + i (n2-1) + j``.  ``P[k]`` is the zero on
    edge ``ids[k]``.
    """

    t1: np.ndarray
    t2: np.ndarray
    G: np.ndarray
    hmask: np.ndarray
    vmask: np.ndarray
    ids: np.ndarray
    P: np.ndarray
    iterations: int


def scan(prob: Problem, domain, grid: tuple[int, int], progress: bool = False) -> Scan:
    """Scan ``G`` on the grid and refine every sign-change edge."""
    n1, n2 = grid
    t1, t2, Gg = scan_field(prob, domain, grid, progress)
    neg = Gg < 0
    hmask = neg[:-1, :] != neg[1:, :]
    vmask = neg[:, :-1] != neg[:, 1:]
    hi, hj = np.nonzero(hmask)
    vi, vj = np.nonzero(vmask)
    Pa = np.concatenate([np.c_[t1[hi], t2[hj]], np.c_[t1[vi], t2[vj]]])
    Pb = np.concatenate([np.c_[t1[hi + 1], t2[hj]], np.c_[t1[vi], t2[vj + 1]]])
    Ga = np.concatenate([Gg[hi, hj], Gg[vi, vj]])
    Gb = np.concatenate([Gg[hi + 1, hj], Gg[vi, vj + 1]])
    ids = np.concatenate([hi * n2 + hj, (n1 - 1) * n2 + vi * (n2 - 1) + vj]).astype(int)
    P, its = refine_edges(prob, Pa, Pb, Ga, Gb, progress) if ids.size else (np.zeros((0, 2)), 0)
    return Scan(t1, t2, Gg, hmask, vmask, ids, P, its)
