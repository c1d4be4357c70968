"""The task function of the studies: solve one case, return its branches as JSON.

A task is ``{"case": {Case fields}, ...}``; extra keys (labels, positions)
are carried along untouched.
"""

from __future__ import annotations

import numpy as np

from ...app import Case
from ...paths import find_paths

__all__ = ["case_from_task", "solve_task", "branch_arrays"]


def case_from_task(task: dict):
    """The :class:`plbar.Case` of a task."""
    return Case(**task["case"])


def _floats(a) -> list:
    return [float(v) for v in np.asarray(a, float).ravel()]


def solve_task(task: dict) -> dict:
    """Solve the case of ``task``.

    Returns
    -------
    dict
        ``T0_I``, ``T0_II``, ``length``, ``dofs``, ``domain`` and
        ``branches``: per branch ``id`` and the lists ``T1``, ``T2``,
        ``phi`` (mod ``2 pi``), ``dPL``, ``xi``, ``grazing``.  Plain floats,
        so the JSON file round-trips exactly.
    """
    case = case_from_task(task)
    prob = case.problem()
    dom = case.domain(prob)
    paths = find_paths(prob, dom, case.grid)
    T0I, T0II = prob.system.T0
    return {
        "T0_I": float(T0I), "T0_II": float(T0II), "length": float(prob.bar.length), "dofs": int(prob.system.n),
        "domain": {"T1": list(dom.T1), "T2": list(dom.T2)},
        "branches": [{"id": int(b.id), "T1": _floats(b.T1), "T2": _floats(b.T2),
                      "phi": _floats(np.mod(b.phi, 2 * np.pi)), "dPL": _floats(b.dPL), "xi": _floats(b.xi),
                      "grazing": [int(g) for g in np.asarray(b.grazing).ravel()]}
                     for b in paths.branches],
    }


def branch_arrays(br: dict) -> dict[str, np.ndarray]:
    """A stored branch as numpy arrays (adds ``T = T1 + T2``)."""
    out = {k: np.asarray(br[k], float) for k in ("T1", "T2", "phi", "dPL", "xi")}
    out["grazing"] = np.asarray(br["grazing"], int)
    out["T"] = out["T1"] + out["T2"]
    return out
