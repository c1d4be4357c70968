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

from .bruteforce import (MAX_HEADER, SWEEP_HEADER, SweepTables, default_positions, load_sweep_study, node_pairs,
                         sweep_tables, write_sweep_tables, xi_along_mesh)
from .damped import THETA_GRID, DampedLoadForms, damped_forms
from .extremes import RCOND, ElementMax, PointLoads, Worst, element_max, worst
from .families import FAMILIES, OTHER, anchors, assign_families
from .forms import HZERO_TOL, LoadForms, load_forms
from .sweep import (PAIRS_HEADER, POSITIONS_HEADER, SWEEP_OWNED, WARN_BYTES, WORST_HEADER, LoadStudy,
                    check_positions, family_labels, mesh_positions, pair_table, position_table, sweep_loads,
                    tidy_positions, vertex_loads, worst_table)

__all__ = ["sweep_loads", "LoadStudy", "load_forms", "LoadForms", "DampedLoadForms", "damped_forms", "THETA_GRID",
           "Worst", "ElementMax", "PointLoads", "element_max", "worst", "RCOND", "HZERO_TOL", "FAMILIES", "OTHER",
           "anchors", "assign_families", "mesh_positions", "vertex_loads", "family_labels", "pair_table",
           "position_table", "tidy_positions", "worst_table", "check_positions", "POSITIONS_HEADER", "WORST_HEADER",
           "PAIRS_HEADER", "SWEEP_OWNED", "WARN_BYTES", "load_sweep_study", "default_positions", "node_pairs",
           "SweepTables", "sweep_tables", "write_sweep_tables", "xi_along_mesh", "SWEEP_HEADER", "MAX_HEADER"]
