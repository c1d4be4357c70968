"""The paper's figures (Figs. 2-9) for our numbers: ``plbar figures``.

* :mod:`.figures` -- solve the paper's cases and draw them (:mod:`plbar.visuals.paper`).
"""

from .figures import (FIGURES, fig2_paths, fig3_time_histories, fig4_energies, fig5_loss_damping, fig6_damping_paths,
                      fig7_load_responses, fig8_xi_per_load, fig9_xi_position, make_all)

__all__ = ["FIGURES", "fig2_paths", "fig3_time_histories", "fig4_energies", "fig5_loss_damping", "fig6_damping_paths",
           "fig7_load_responses", "fig8_xi_per_load", "fig9_xi_position", "make_all"]
