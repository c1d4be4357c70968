"""Drawing only (no solving inside): plots of a solved case, the paper's figures, off-screen renderings.

matplotlib and pyvista are imported inside the drawing functions.
"""

from .convergence import convergence_plot
from .damping import xi_rayleigh_plot
from .paper import GREEN, RED, nearest_point
from .plots import frequency_response, paths_plane, xi_load_map
from .refinement import refine_family_plot
from .render import RenderFiles, render
from .survey import survey_damping_plot, survey_loads_plot, survey_plot, survey_restitution_plot

__all__ = ["GREEN", "RED", "nearest_point", "frequency_response", "paths_plane", "xi_load_map",
           "RenderFiles", "render", "convergence_plot", "refine_family_plot", "survey_plot", "survey_loads_plot",
           "survey_restitution_plot", "survey_damping_plot", "xi_rayleigh_plot"]
