"""plbar: periodic responses and equivalent viscous damping of bars with a unilateral contact.

Quick start::

    import plbar
    res = plbar.solve()                      # the paper's chain N = 5, unit force on DOF 1
    for b in res.branches:
        print(b.id, b.T.min(), b.T.max(), b.xi.max())

The package is layered; each subpackage's ``__init__`` is its front door and
imports flow one way (``python -m plbar.util.layout`` prints the graph):

``errors`` -> ``util`` -> ``model`` -> ``continuum`` -> ``response`` -> ``paths`` -> ``motion`` -> ``periodic`` ->
``check`` -> ``io`` -> ``visuals`` -> ``app`` -> ``studies`` -> ``cli``.
"""

from .app import Case, Result, solve, write_results
from .check import simulate
from .errors import CaseFileError, InputError, OutputExistsError, PlbarError
from .model import (Bar, Load, Problem, Structure, TwoStateSystem, assemble, bar_structure, base_excitation, chain,
                    graded_nodes, node, point, problem, rayleigh_from_ratio, two_state, uniform_bar, uniform_nodes)
from .paths import Branch, Domain, Paths, default_domain, find_paths
from .response import Orbits, Response, damping, find_response, impact_loss, orbits
from .util.version import __version__

__all__ = [
    "Bar", "assemble", "chain", "graded_nodes", "uniform_bar", "uniform_nodes", "Case", "damping",
    "impact_loss", "CaseFileError", "InputError", "OutputExistsError", "PlbarError", "Load", "node", "point",
    "base_excitation",
    "Orbits", "orbits", "Branch", "Domain", "Paths", "default_domain", "find_paths", "Result", "solve",
    "write_results", "Response", "find_response", "Problem", "Structure", "bar_structure", "TwoStateSystem", "problem",
    "two_state", "simulate", "rayleigh_from_ratio", "__version__",
]
