"""The model: the bar and its finite-element assembly, loads, and the two-state modal system.

``Bar`` -> :func:`assemble` (scikit-fem; K, M over the free DOFs, contact DOF
last) -> :func:`two_state` (modes of the stuck state I and the free state II and
the switch maps, Eqs. (2)-(10)) -> :func:`problem` (with the load vector of a
:class:`Load`, Eq. (3)).
"""

from .bar import (ELEMENTS, MASSES, Assembled, Bar, assemble, chain, graded_nodes, uniform_bar,
                  uniform_nodes)
from .damping import check_rayleigh, rayleigh_from_ratio, rayleigh_ratio
from .load import Load, node, point
from .system import Problem, TwoStateSystem, check_restitution, problem, two_state, with_load_vector

__all__ = ["ELEMENTS", "MASSES", "Assembled", "Bar", "assemble", "chain", "graded_nodes", "uniform_bar",
           "uniform_nodes", "check_rayleigh", "rayleigh_from_ratio", "rayleigh_ratio", "Load", "node", "point",
           "Problem", "TwoStateSystem", "problem", "two_state", "with_load_vector", "check_restitution"]
