"""Study results are frozen dataclasses of one shape: ``files``, ``summary``, the tables as attributes, a short repr."""

import dataclasses

import numpy as np
import pytest

import plbar
from plbar.studies import RefineStudy, Survey, SurveyRefinement, TrackSettings, run_refine, run_survey_refine


def _frozen(obj):
    assert dataclasses.is_dataclass(obj)
    with pytest.raises(dataclasses.FrozenInstanceError):
        obj.files = {}
    assert isinstance(obj.files, dict) and isinstance(obj.summary, dict)


def test_refine_study(tmp_path):
    r = run_refine([plbar.Case()], [3, 4, 5], settings=TrackSettings(grid=(30, 30)), out=tmp_path / "r", plot=False)
    _frozen(r)
    assert isinstance(r, RefineStudy) and [row["n"] for row in r.rows] == [3, 4, 5]
    assert r.family("chain", "T0_II/2") == r.rows and "T0_I_L" in r.rates["chain"]["T0_II/2"]
    assert r.summary["ns"] == [3, 4, 5] and r.time == r.summary["seconds"] > 0
    assert set(r.files) == {"refine", "rates"} and all(p.is_file() for p in r.files.values())
    text = repr(r)
    assert text.startswith("RefineStudy(series=['chain'], families=['T0_II/2'], N=[3, 4, 5], rows=3")
    assert len(text) < 200


def test_survey_refinement(tmp_path):
    s = run_survey_refine(plbar.Case(), [3, 4], [9.0, 11.0], periods=20, record=5, out=tmp_path / "s", plot=False)
    _frozen(s)
    assert isinstance(s, SurveyRefinement) and sorted(s.surveys) == [3, 4]
    assert all(isinstance(v, Survey) for v in s.surveys.values())
    assert [r["N"] for r in s.rows] == [3, 3, 4, 4] and len(s.rates) == 2
    assert s.summary["sizes"] == [3, 4] and s.summary["periods"] == 20
    assert np.all(np.isfinite([r["loss_per_T"] for r in s.rows]))
    text = repr(s)
    assert text.startswith("SurveyRefinement(N=[3, 4], T/L=2, rows=4") and len(text) < 200


def test_every_name_the_front_door_had_is_still_there():
    import plbar.studies as st

    before = {"KINDS", "SerialExecutor", "get_executor", "FAMILIES", "OTHER", "assign_families", "default_positions",
              "load_sweep_study", "node_pairs", "sweep_tables", "write_sweep_tables", "xi_along_mesh", "refine_study",
              "run_refine", "Study", "StudyError", "load_results", "run_study", "task_key", "solve_task",
              "truncation_check", "RATIOS", "DampedRun", "ratio_table", "with_rayleigh"}
    assert before <= set(st.__all__) and all(hasattr(st, n) for n in st.__all__)
    for room in ("execution", "loads", "refine", "damping", "survey", "paper"):      # the rooms, not shadowed
        assert getattr(st, room).__name__ == f"plbar.studies.{room}"
