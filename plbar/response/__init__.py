"""Periodic responses at given ``(T^I, T^II, phi)``: flows, the one-period map, orbits, energy, checks.

* :mod:`.flow` -- closed-form modal flows (Appendix 1) and ``Psi`` (Eq. (20), Appendix 2), damped with ``zeta=``;
* :mod:`.damped` -- the damped (Rayleigh) modal flows, kernels and ``Psi`` in closed form;
* :mod:`.onemap` -- the one-period map, the residual coefficients and the ONE scan function ``G``;
* :mod:`.orbit` -- :class:`Orbits`: time histories, reaction, gap, impact of periodic responses;
* :mod:`.energy` -- ``Delta_PL`` and ``xi_eq`` (Eqs. (14), (21), (22));
* :mod:`.power` -- the work of the load over a segment, in closed form;
* :mod:`.records` -- :class:`Modes` and :class:`Forcing`, what ``Psi`` and the work of a segment take;
* :mod:`.admissible` -- no premature switch (Eqs. (4)-(5));
* :mod:`.find` -- :func:`find_response`, one response from a guess.
"""

from .admissible import Admissibility, check, check_both
from .energy import Damping, damping, impact_loss, kinetic_energy_loss, psi_sums, work_quadrature
from .find import NoResponseError, Response, find_response
from .flow import flow_matrix, forced_coeffs, free_flow, kernels, psi, segment
from .onemap import Coefficients, PeriodMap, coefficients, period_map, phase, scan_function, states
from .onemap import G as scan_G
from .orbit import Orbits, orbits, periodic_state
from .power import segment_work, work_closed_form
from .records import Forcing, Modes

__all__ = ["Admissibility", "check", "check_both", "Damping", "damping", "impact_loss", "kinetic_energy_loss",
           "psi_sums", "flow_matrix", "work_quadrature", "NoResponseError", "Response", "find_response",
           "forced_coeffs", "free_flow", "kernels", "Forcing", "Modes", "psi", "segment", "segment_work",
           "work_closed_form", "Coefficients", "PeriodMap", "coefficients", "period_map", "phase", "scan_function",
           "states", "scan_G", "Orbits", "orbits", "periodic_state"]
