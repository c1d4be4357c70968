"""The independent check: an event-driven simulator of the two-state bar (imports :mod:`plbar.model` only).

It shares nothing with the periodic solver but the model data, so agreement
between the two is evidence, not a tautology (FORMULATION §7).
"""

from .segments import IMPACT, OPEN, duhamel, modal_flow
from .simulate import History, Simulation, SimulationError, period_map, simulate

__all__ = ["IMPACT", "OPEN", "duhamel", "modal_flow", "History", "Simulation", "SimulationError", "period_map",
           "simulate"]
