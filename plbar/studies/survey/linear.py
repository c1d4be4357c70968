"""The survey's equivalent linear models: what a linear model with the motion's ``xi_eq`` predicts beside it.

For every forcing period of a survey, the structure's equivalent linear models (:func:`plbar.model.linear_model`:
the free, stuck and bilinear stiffness) with the viscous ratio ``xi_eq`` of the motion simulated there, and
their steady responses in closed form (:func:`plbar.model.steady_response`): the contact's amplitude (the free
and bilinear models; the stuck model holds the contact) and the energy the ratio takes per period (against the
motion's impact loss ``loss_per_T``).  The columns are blank for the continuum and a truncated model (no
matrices of every mode), where the motion has no ``xi_eq``, and for a model that has no steady response (undamped,
``xi_eq = 0``, at one of its natural periods).
"""

from __future__ import annotations

import numpy as np

from ...errors import InputError
from ...model import Problem, linear_model, steady_response

__all__ = ["LINEAR_COLUMNS", "linear_models", "linear_fields"]

#: the survey's columns of the linear models' predictions
LINEAR_COLUMNS = ("linear_free_amp_c", "linear_bilinear_amp_c", "linear_free_loss", "linear_bilinear_loss",
                  "linear_stuck_loss")


def linear_models(prob: Problem) -> dict:
    """The three equivalent linear models of ``prob`` by stiffness (none for a truncated problem)."""
    if prob.system.truncated:
        return {}
    return {k: linear_model(prob, k) for k in ("free", "bilinear", "stuck")}


def linear_fields(models: dict, T: float, xi: float) -> dict:
    """The row's linear columns at forcing period ``T`` with the ratio ``xi`` (no fields without models or a
    finite ``xi >= 0``)."""
    if not models or not (np.isfinite(xi) and xi >= 0):
        return {}
    out = {}
    for k, model in models.items():
        try:
            st = steady_response(model, T, xi)
        except InputError:                  # undamped at a natural period of the model: no steady response
            continue
        if k != "stuck":
            out[f"linear_{k}_amp_c"] = st.amplitude_contact
        out[f"linear_{k}_loss"] = st.dissipated_xi
    return out
