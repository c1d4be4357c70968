"""Keyword options collected into their record (plbar.util.options): the names are the record's fields, an unknown
one says which function and which options."""

import pytest

import plbar
from plbar.studies import RunOptions
from plbar.studies.execution import SerialExecutor, run_options
from plbar.util.options import collect, keywords


def test_the_options_are_the_records_fields_and_travel_on_as_keywords():
    ex = SerialExecutor()
    opts = run_options({"executor": ex, "plot": False}, "run_survey")
    assert opts == RunOptions(executor=ex, plot=False) and opts.executor is ex
    assert keywords(opts) == {"executor": ex, "progress": False, "overwrite": False, "plot": False}
    assert keywords(opts)["executor"] is ex                     # the executor itself, not a copy
    with pytest.raises(TypeError, match=r"run_survey\(\) got an unexpected keyword argument 'plots' \(its options: "
                                        r"executor, progress, overwrite, plot\)"):
        collect(RunOptions, {"plots": False}, "run_survey")


def test_a_study_refuses_an_unknown_option_and_sweep_loads_an_executor_before_any_work(tmp_path):
    from plbar.continuum import ContinuumBar, simulate_modal
    from plbar.studies import run_survey, sweep_loads

    with pytest.raises(TypeError, match="run_survey"):
        run_survey(plbar.Case(), [8.0], 20, 2, tmp_path / "s", exectuor=None)
    with pytest.raises(TypeError, match="takes no executor"):
        sweep_loads(plbar.Case(), tmp_path / "l", executor=SerialExecutor())
    with pytest.raises(TypeError, match="simulate_modal"):
        simulate_modal(ContinuumBar(), 2.5, 1, steps=10)
    assert not (tmp_path / "s").exists() and not (tmp_path / "l").exists()
