"""What a full solve will cost, from its size: the measured scaling of README "Speed", before the work starts.

The time of :func:`plbar.solve` is set by the modes it keeps (the degrees of freedom of the full model, or
``modes``) and the scan grid.  Measured on 2 cores (FE P1 lumped, 200 x 200 grid; the chain N = 5 for the
smallest size): :data:`MEASURED`.  Between the sizes measured the estimate interpolates on log-log axes;
beyond them it grows like ``n^2.1`` (time, the README's fit over N = 10..100) and ``n^0.56`` (memory, the last
measured slope).  An estimate, good to a factor of about 2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .case import Case

__all__ = ["Cost", "estimate_cost", "cost_note", "MEASURED", "MEMORY", "NOTE_SECONDS", "SIGNATURES"]

#: (modes per state, seconds) measured for a 200 x 200 grid (README "Speed"; the chain N = 5 for n = 5)
MEASURED = ((5, 0.7), (10, 5.0), (20, 29.0), (50, 239.0), (100, 583.0))
#: (modes per state, peak memory in GB), measured alike
MEMORY = ((10, 0.39), (20, 0.93), (100, 2.3))
#: (degrees of freedom, seconds) of the search for every other signature (``signatures="default"``), measured on
#: 2 cores (busy): the chain N = 5, FE P1 lumped N = 16 and 32 with an end mass
SIGNATURES = ((5, 2.0), (16, 70.0), (32, 220.0))
SIGNATURES_EXPONENT = 1.7    #: beyond the largest size measured
TIME_EXPONENT = 2.1      #: beyond the largest size measured
MEMORY_EXPONENT = 0.56   #: beyond the largest size measured
NOTE_SECONDS = 60.0      #: above this estimate ``plbar run`` says so before it starts
GRID = 200 * 200         #: the grid of the measurements


@dataclass(frozen=True)
class Cost:
    """An estimate of a full solve: ``seconds``, ``gigabytes``, and the size it rests on (``modes``, ``grid``)."""

    seconds: float
    gigabytes: float
    modes: int
    dofs: int
    grid: tuple[int, int]
    signatures: float = 0.0     #: of ``seconds``, the search for the other signatures


def _loglog(n: float, table, exponent: float) -> float:
    """``table`` interpolated on log-log axes at ``n``; beyond its ends its end slopes (``exponent`` above)."""
    x, y = np.log([m[0] for m in table]), np.log([m[1] for m in table])
    if n >= table[-1][0]:
        return float(np.exp(y[-1]) * (n / table[-1][0]) ** exponent)
    if n <= table[0][0]:
        return float(np.exp(y[0]) * (n / table[0][0]) ** ((y[1] - y[0]) / (x[1] - x[0])))
    return float(np.exp(np.interp(np.log(n), x, y)))


def estimate_cost(case: Case) -> Cost:
    """The estimated time and memory of ``plbar.solve(case)`` (see the module docstring)."""
    dofs = case.bar().n_dofs
    modes = dofs if case.modes is None else min(case.modes, dofs)
    g = case.grid[0] * case.grid[1] / GRID
    sig = 0.0 if case.signatures == "paper" else _loglog(modes, SIGNATURES, SIGNATURES_EXPONENT)
    return Cost(_loglog(modes, MEASURED, TIME_EXPONENT) * g + sig, _loglog(modes, MEMORY, MEMORY_EXPONENT), modes,
                dofs, tuple(case.grid), sig)


def _duration(s: float) -> str:
    for unit, size in (("days", 86400.0), ("hours", 3600.0), ("minutes", 60.0)):
        if s >= 2 * size:
            return f"{s / size:.0f} {unit}"
    return f"{s:.0f} s"


def cost_note(case: Case, threshold: float = NOTE_SECONDS) -> str | None:
    """One line: what a solve of ``case`` will cost and what to do instead, if above ``threshold`` s (else None)."""
    c = estimate_cost(case)
    if c.seconds <= threshold:
        return None
    kept = "the full model" if case.modes is None else f"{c.modes} modes per state"
    sig = (f", {_duration(c.signatures)} of it the search for every other signature (--signatures paper skips "
           "it)") if c.signatures > 0.25 * c.seconds else ""
    return (f"plbar: note: this solve ({c.dofs} DOFs, {kept}, grid {c.grid[0]} x {c.grid[1]}) will take about "
            f"{_duration(c.seconds)}{sig} and {c.gigabytes:.1f} GB (the time grows like DOFs^2.1: README 'Speed'); "
            "to follow one family to fine meshes use 'plbar refine', to locate paths fast use --modes M "
            "(never for xi_eq), or a coarser --grid")
