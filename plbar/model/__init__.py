"""The model: a two-state structure, its builders, and its two-state modal system.

:class:`Structure` (mass, stiffness, the contact row, the load, damping, restitution: any matrices) is what
every solver takes; :func:`bar_structure` builds it for the finite-element bar (``Bar`` -> :func:`assemble`,
scikit-fem, contact DOF last) and the paper's chain (:func:`chain`); :func:`problem` turns it into the modes
of the stuck state I and the free state II and the switch maps (:func:`two_state`, Eqs. (2)-(10)) with the
modal load (Eq. (3)), in the contact coordinates of :func:`contact_coordinates`.  :func:`linear_model` and
:func:`steady_response` are its equivalent linear models (one stiffness, viscous damping: where ``xi_eq`` is put).
"""

from .bar import (ELEMENTS, MASSES, Assembled, Bar, assemble, chain, graded_nodes, uniform_bar,
                  uniform_nodes)
from .damping import check_rayleigh, rayleigh_from_ratio, rayleigh_ratio
from .load import Load, base_excitation, node, point
from .builders import BarOrigin, bar_structure
from .beam import SUPPORTS, Beam, BeamAssembled, BeamOrigin, assemble_beam, beam_structure, uniform_beam
from .statics import Statics, check_gap, statics
from .structure import Coordinates, Structure, check_restitution, contact_coordinates
from .system import Problem, TwoStateSystem, problem, two_state, with_load_vector
from .linear import STIFFNESSES, LinearModel, SteadyResponse, linear_model, steady_response

__all__ = ["SUPPORTS", "Beam", "BeamAssembled", "BeamOrigin", "assemble_beam", "beam_structure", "uniform_beam",
           "ELEMENTS", "MASSES", "Assembled", "Bar", "assemble", "chain", "graded_nodes", "uniform_bar",
           "uniform_nodes", "check_rayleigh", "rayleigh_from_ratio", "rayleigh_ratio", "Load", "node", "point",
           "base_excitation",
           "Problem", "TwoStateSystem", "problem", "two_state", "with_load_vector", "check_restitution",
           "BarOrigin", "bar_structure", "Coordinates", "Structure", "contact_coordinates", "STIFFNESSES",
           "LinearModel", "SteadyResponse", "linear_model", "steady_response", "Statics", "check_gap", "statics"]
