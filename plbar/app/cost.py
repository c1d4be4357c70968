"""What a full solve will cost, from its size: the measured scaling of docs/speed.md, before the work starts.

The time of :func:`plbar.solve` is set by the modes it keeps (the degrees of freedom of the full model, or
``modes``) and the scan grid.  Measured on 2 cores (FE P1 lumped, 200 x 200 grid; the chain N = 5 for the
smallest size): :data:`MEASURED`.  Between the sizes measured the estimate interpolates on log-log axes;
beyond them it grows like ``n^2.1`` (time, the README's fit over N = 10..100) and ``n^0.56`` (memory, the last
measured slope), and the memory is at least the dense eigenproblem's (:data:`DENSE_COPIES` arrays of n x n).  An
estimate, said as a range (:func:`duration_range`): the tables' time at the low end, :data:`BUSY` times it at the high
end (what the same work took on a busy machine).  A survey's time is its simulated forcing periods times the
measured cost of one (:data:`SURVEY_PERIOD`).

:func:`check_cost` is the one rule of every command before a costly job: above :data:`LIMIT_SECONDS` or
:data:`RAM_SHARE` of the machine's memory it is refused unless the user says ``--yes``; a job that cannot fit in
the machine's memory at all is refused always (before anything is allocated).
"""

from __future__ import annotations

from dataclasses import dataclass

import os

import numpy as np

from ..errors import InputError
from .case import Case

__all__ = ["Cost", "estimate_cost", "cost_note", "search_note", "check_cost", "survey_seconds", "duration",
           "duration_range", "BUSY", "MEASURED", "MEMORY", "NOTE_SECONDS", "LIMIT_SECONDS", "RAM_SHARE", "SIGNATURES",
           "SURVEY_PERIOD"]

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
SEARCH_NOTE_SECONDS = 10.0   #: ... and above this estimate of its signature search, says so before the search
LIMIT_SECONDS = 3600.0   #: above this estimate a command starts only with ``--yes``
RAM_SHARE = 0.5          #: ... or above this share of the machine's memory
DENSE_COPIES = 3         #: dense n x n arrays of the eigenproblem (K, M, the modes): the memory floor
#: (degrees of freedom, CPU seconds to simulate one forcing period of one motion), measured on 1 core (busy,
#: ``PLBAR_THREADS=1``, 1,000 periods from rest over the survey's default range): the paper's chain N = 5, FE P1
#: lumped N = 16 and 64 with an end mass 0.5 (the load studies agree: 5,152 x 1,000 FE N = 16 in 130-320 s on 2)
SURVEY_PERIOD = ((5, 1.7e-5), (16, 4.9e-5), (64, 3.3e-4))
SURVEY_EXPONENT = 1.4    #: beyond the largest size measured (the slope between the last two)
GRID = 200 * 200         #: the grid of the measurements
#: the high end of every estimate, as a multiple of the tables above: what the same work took on a busy machine (2
#: shared cores) against its estimate, measured in issue 44 (finding 7): plbar run estimated 86 s, took 358-565 s
#: (4.2-6.6x); survey --per-element 4 estimated 67 s, took 176 s (2.6x); the first run 68 s against 20-26 s
#: (2.6-3.4x).  The low end is the tables' own time (measured idle to busy: an idle machine is at most that fast).
BUSY = 6.6


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
    dofs = case.dofs
    modes = dofs if case.modes is None else min(case.modes, dofs)
    g = case.grid[0] * case.grid[1] / GRID
    sig = 0.0 if case.signatures == "paper" else _loglog(modes, SIGNATURES, SIGNATURES_EXPONENT)
    dense = DENSE_COPIES * 8.0 * dofs ** 2 / 1e9
    return Cost(_loglog(modes, MEASURED, TIME_EXPONENT) * g + sig,
                max(_loglog(modes, MEMORY, MEMORY_EXPONENT), dense), modes, dofs, tuple(case.grid), sig)


#: the continuum's seconds per motion per periods^2 at 32 steps per L/c (its fronts accumulate, so a motion's cost
#: grows with the square of its periods): 1,000 periods at T/L = 2.5 in 30-31 s, 2 busy cores
#: (tests/bench/results_continuum_speed.txt)
CONTINUUM_PERIOD2 = 3.1e-5


#: the damped continuum's seconds per motion per period (exact modes per contact state: linear in periods, and
#: nearly flat in the modes, whose decayed terms are left out): 1,000 periods in 82-216 s at T/L = 2.5 and 3.5,
#: 512 or 1,024 modes, 0.5-2 %, 2 cores idle to busy (tests/bench/refinement_vs_continuum.py, refinement_damping.py)
CONTINUUM_MODAL_PERIOD = 0.12


#: the forcing period (in transit times ``T c / L``) at which :data:`CONTINUUM_PERIOD2` was measured, and the power of
#: ``T c / L`` the continuum's cost grows with beyond it: more grid steps per period and more impacts (fronts) per
#: period, 53x from T c/L = 2.5 to 10 at 50 periods, 3.8-6.6x to 3.5 (measured in issue 44, finding 3)
CONTINUUM_TL, CONTINUUM_TL_POWER = 2.5, 3.0


def survey_seconds(case: Case, motions: int, periods: int, T=None) -> float:
    """The estimated CPU time of simulating ``motions`` motions of ``case`` over ``periods`` forcing periods each
    (``T``: the forcing periods, which the continuum's cost depends on; without them it is taken at
    :data:`CONTINUUM_TL`)."""
    if case.model == "continuum" and case.rayleigh is not None:
        return motions * CONTINUUM_MODAL_PERIOD * periods
    if case.model == "continuum":
        growth = 1.0
        if T is not None and np.size(T):
            x = np.asarray(T, float) / case.bar().transit / CONTINUUM_TL
            growth = float(np.mean(np.where(x > 1, x ** CONTINUUM_TL_POWER, x)))
        return motions * CONTINUUM_PERIOD2 * periods ** 2 * case.n_eff / 32 * growth
    return motions * periods * _loglog(case.dofs, SURVEY_PERIOD, SURVEY_EXPONENT)


def duration_range(s: float, busy: float = BUSY) -> str:
    """An estimate ``s`` as the range it holds over (``"2-13 minutes"``): ``s`` on an idle machine, ``busy`` times
    ``s`` on a busy one (:data:`BUSY`: measured); both ends in the unit of the high end."""
    hi = s * busy
    for unit, size in (("days", 86400.0), ("hours", 3600.0), ("minutes", 60.0)):
        if hi >= 2 * size:
            lo = s / size
            return f"{lo:.{1 if lo < 1 else 0}f}-{hi / size:.0f} {unit}"
    return "under 2 s" if hi < 2 else f"{max(s, 1):.0f}-{hi:.0f} s"


def duration(s: float) -> str:
    """``"45 s"``, ``"3 minutes"``, ``"4 hours"``, ``"2 days"``."""
    for unit, size in (("days", 86400.0), ("hours", 3600.0), ("minutes", 60.0)):
        if s >= 2 * size:
            return f"{s / size:.0f} {unit}"
    return f"{s:.0f} s"


#: what to use instead of a costly solve
CHEAPER = ("to follow one family to fine meshes use 'plbar refine', to locate paths fast use --modes M (never for "
           "xi_eq), or a coarser --grid")


def _solve_text(case: Case, c: Cost) -> str:
    kept = "the full model" if case.modes is None else f"{c.modes} modes per state"
    sig = (f", {duration(c.signatures)} of it the search for every other signature (--signatures paper skips "
           "it)") if c.signatures > 0.25 * c.seconds else ""
    return (f"this solve ({c.dofs} DOFs, {kept}, grid {c.grid[0]} x {c.grid[1]}) will take "
            f"{duration_range(c.seconds)} (idle to busy machine){sig} and {c.gigabytes:.1f} GB (the time grows like "
            "DOFs^2.1: docs/speed.md)")


def cost_note(case: Case, threshold: float = NOTE_SECONDS, yes: bool = False) -> str | None:
    """One line: what a solve of ``case`` will cost and what to do instead, if above ``threshold`` s (else None).

    First :func:`check_cost`: a solve above the limits is refused unless ``yes``.
    """
    c = estimate_cost(case)
    check_cost(c.seconds, c.gigabytes, _solve_text(case, c), CHEAPER, yes)
    if c.seconds <= threshold:
        return None
    return f"plbar: note: {_solve_text(case, c)}; {CHEAPER}"


def search_note(case: Case) -> str | None:
    """One line before a signature search of about :data:`SEARCH_NOTE_SECONDS` s or more that the cost note
    (:func:`cost_note`, above :data:`NOTE_SECONDS` in all) did not announce; else None."""
    c = estimate_cost(case)
    if c.signatures < SEARCH_NOTE_SECONDS or c.seconds > NOTE_SECONDS:
        return None
    return (f"plbar: note: the search for every other signature ({c.modes} modes per state) will take about "
            f"{duration(c.signatures)} (--signatures paper skips it)")


def _machine_gigabytes() -> float | None:
    """The machine's memory (GB), None where unknown."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 1e9
    except (AttributeError, ValueError, OSError):
        return None


def check_cost(seconds: float, gigabytes: float, job: str, cheaper: str, yes: bool) -> None:
    """Refuse a costly job before it starts (the one rule of every command; see the module docstring).

    Parameters
    ----------
    seconds, gigabytes : float
        The job's estimated time (on this machine's cores) and peak memory.
    job : str
        What the job is and what it will cost (``"this solve (...) will take about 4 days and 12.3 GB"``).
    cheaper : str
        What to do instead.
    yes : bool
        The user's ``--yes``: start a job above the limits anyway (never one larger than the memory).

    Raises
    ------
    InputError
        Above :data:`LIMIT_SECONDS` or :data:`RAM_SHARE` of the memory without ``yes``; above the memory always.
    """
    ram = _machine_gigabytes()
    if ram is not None and gigabytes > ram:
        raise InputError(f"{job}: more than this machine's {ram:.1f} GB of memory, so it is not started; {cheaper}")
    if yes:
        return
    if seconds > LIMIT_SECONDS or (ram is not None and gigabytes > RAM_SHARE * ram):
        limit = f"{duration(LIMIT_SECONDS)} or {RAM_SHARE * ram:.1f} GB" if ram else duration(LIMIT_SECONDS)
        raise InputError(f"{job}, above the {limit} plbar starts without asking; {cheaper}; --yes to start anyway")
