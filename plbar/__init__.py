"""plbar: periodic responses and equivalent viscous damping of bars with a unilateral contact.

Quick start::

    import plbar
    res = plbar.solve()                      # the paper's chain N = 5, unit force on DOF 1
    for b in res.branches:
        print(b.id, b.T.min(), b.T.max(), b.xi.max())
"""

from .bar import Bar, assemble, chain, graded_nodes, uniform_bar, uniform_nodes
from .case import Case
from .energy import damping, impact_loss
from .errors import CaseFileError, InputError, OutputExistsError, PlbarError
from .load import Load, node, point
from .orbit import Orbits, orbits
from .paths import Branch, Domain, Paths, default_domain, find_paths
from .response import Response, find_response
from .run import Result, solve, write_results
from .system import Problem, TwoStateSystem, problem, two_state

__version__ = "0.1.0"

__all__ = [
    "Bar", "assemble", "chain", "graded_nodes", "uniform_bar", "uniform_nodes", "Case", "damping",
    "impact_loss", "CaseFileError", "InputError", "OutputExistsError", "PlbarError", "Load", "node", "point",
    "Orbits", "orbits", "Branch", "Domain", "Paths", "default_domain", "find_paths", "Result", "solve",
    "write_results", "Response", "find_response", "Problem", "TwoStateSystem", "problem", "two_state", "__version__",
]
