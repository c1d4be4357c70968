"""The survey's linear columns: the equivalent linear models with each motion's xi_eq, beside the motion."""

from __future__ import annotations

import numpy as np
import pytest

import plbar
from plbar.model import linear_model, steady_response
from plbar.studies.survey.linear import LINEAR_COLUMNS
from plbar.studies.survey.points import COLUMNS, survey_chunk


def test_each_row_has_the_linear_models_with_its_own_xi_eq():
    case = plbar.Case()
    rows, _ = survey_chunk(case, [9.0, 12.0], 300, 30)
    prob = case.problem()
    assert set(LINEAR_COLUMNS) <= set(COLUMNS)
    for r in rows:
        for k in ("free", "bilinear", "stuck"):
            st = steady_response(linear_model(prob, k), r["T"], r["xi_eq"])
            assert r[f"linear_{k}_loss"] == pytest.approx(st.dissipated_xi, rel=1e-14)
            if k != "stuck":
                assert r[f"linear_{k}_amp_c"] == pytest.approx(st.amplitude_contact, rel=1e-14)
        # the linear model's loss with xi_eq is 2 xi_eq sum_j w_j Psi_j of ITS motion (Eq. (22) read backwards)
        st = steady_response(linear_model(prob, "free"), r["T"], r["xi_eq"])
        psi = np.pi * (2 * np.pi / r["T"]) * np.abs(st.eta) ** 2
        assert st.dissipated_xi == pytest.approx(2 * r["xi_eq"] * np.sum(linear_model(prob, "free").w * psi),
                                                 rel=1e-13)


def test_no_linear_columns_without_every_mode():
    rows, _ = survey_chunk(plbar.Case(modes=3), [12.0], 200, 20)
    assert not set(LINEAR_COLUMNS) & set(rows[0])


def test_a_model_with_no_steady_response_leaves_its_columns_blank():
    """Undamped with xi_eq = 0 (an elastic contact's motion loses nothing) at a natural period of one model: that
    model's columns are blank, the others' are there (the survey went on: examples/restitution.py hit one)."""
    from plbar.studies.survey.linear import linear_fields, linear_models

    models = linear_models(plbar.Case().problem())
    T = 2 * np.pi / models["bilinear"].w[0]
    out = linear_fields(models, T, 0.0)
    assert "linear_bilinear_amp_c" not in out and "linear_bilinear_loss" not in out
    assert "linear_free_amp_c" in out and "linear_stuck_loss" in out
