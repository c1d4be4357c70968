"""Load studies: every load from one path solve, the worst load, and the brute-force reference.

* :mod:`.sweep` -- :func:`sweep_loads` (``plbar sweep-loads``): one solve, then unit forces anywhere,
  the paper's node pairs and the worst load distribution at every path point (:class:`LoadStudy`);
* :mod:`.forms` -- the quadratic forms ``Delta_PL(q) = (b . q)^2`` and ``q^T G q`` at every path point
  (``docs/load_structure.md``); :mod:`.damped` the same with Rayleigh damping;
* :mod:`.extremes` -- the worst load ``b^T G^+ b / 2`` and the exact best point force per element;
* :mod:`.families` -- which branch is "path 1" / "path 2" in any case;
* :mod:`.bruteforce` -- the old per-load sweep (one full solve per load) as a resumable study: the
  reference the tests prove the exact load theorems against, and the study the dask tests run.
"""

from .bruteforce import (SweepTables, default_positions, load_sweep_study, node_pairs, sweep_tables, write_sweep_tables,
                         xi_along_mesh)
from .damped import DampedLoadForms
from .extremes import RCOND, ElementMax, Worst, element_max, worst
from .families import FAMILIES, OTHER, anchors, assign_families
from .forms import HZERO_TOL, LoadForms, load_forms
from .sweep import WARN_BYTES, WORST_HEADER, LoadStudy, check_positions, pair_table, sweep_loads

__all__ = ["sweep_loads", "LoadStudy", "load_forms", "LoadForms", "DampedLoadForms", "Worst", "ElementMax",
           "element_max", "worst", "RCOND", "HZERO_TOL", "FAMILIES", "OTHER", "anchors", "assign_families",
           "pair_table", "check_positions", "WORST_HEADER", "WARN_BYTES", "load_sweep_study", "default_positions",
           "node_pairs", "SweepTables", "sweep_tables", "write_sweep_tables", "xi_along_mesh"]
