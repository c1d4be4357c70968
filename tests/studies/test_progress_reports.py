"""A study's progress moves while its tasks run (issue 30, item 4): reports from inside the workers.

Before, the progress counted finished tasks: the default survey (two tasks of a minute each on a busy machine)
showed nothing for a minute.  Now a task reports its units as it works and the runner reads them every
:data:`POLL` s.
"""

import time

import numpy as np
import pytest

import plbar.studies.execution.study as study_mod
from plbar.studies import get_executor
from plbar.studies.execution import Study, report, run_study
from plbar.studies.execution.reports import POLL, read_report, reporting
from plbar.studies.survey import survey_study
from plbar.studies.survey.tasks import task_units


class Recorder:
    """A progress bar that keeps what it is told, and when."""

    def __init__(self, total, *_, initial=0, **__):
        self.total, self.n, self.seen = total, initial, []

    def update(self, n=1):
        self.n += n
        self.seen.append((time.monotonic(), self.n))

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def slow_task(task):
    """Ten units, one every 0.3 s."""
    for _ in range(10):
        time.sleep(0.3)
        report(1)
    return {"x": task["x"]}


@pytest.fixture
def recorder(monkeypatch):
    bars = []

    def make(total, enabled, desc, unit="it", delay=1.0, initial=0):
        bars.append(Recorder(total, initial=initial))
        return bars[-1]

    monkeypatch.setattr(study_mod, "progress_bar", make)
    return bars


def test_progress_moves_inside_a_running_task(tmp_path, recorder):
    st = Study("slow", slow_task, ({"x": 1}, {"x": 2}), {}, lambda t: 10, "unit")
    t0 = time.monotonic()
    with get_executor("local", None, 2) as ex:
        out = run_study(tmp_path / "s", st, ex, progress=True)
    t1 = time.monotonic()
    bar = recorder[0]
    assert out == [{"x": 1}, {"x": 2}] and bar.total == 20 and bar.n == 20
    partial = [n for t, n in bar.seen if n < 20]
    assert len(partial) >= 3                               # moved several times before the tasks ended (3 s)
    assert min(t for t, n in bar.seen if n > 0) - t0 < 3.0 - 0.5 * POLL
    assert t1 - t0 < 10
    assert not list((tmp_path / "s" / "tasks").glob("*.progress"))    # reports removed with their tasks


def test_a_finished_study_counts_its_tasks_once(tmp_path, recorder):
    st = Study("slow", slow_task, ({"x": 1},), {}, lambda t: 10, "unit")
    run_study(tmp_path / "s", st, progress=True)          # serial: the task ends before anything is read
    run_study(tmp_path / "s", st, progress=True)          # resumed: nothing to do, all counted as done
    assert [b.n for b in recorder] == [10, 10] and recorder[1].seen == []


def test_report_writes_what_was_done(tmp_path):
    path = tmp_path / "k.progress"
    with reporting(path):
        report(5)                       # the first report is written at once, later ones at most every POLL
        assert read_report(path) == 5
        report(3)
    assert not path.exists() and read_report(path) == 0
    report(7)                           # outside a task: goes nowhere


def test_a_survey_task_reports_its_units(tmp_path):
    """Every unit of a survey task (trajectories x periods, from rest and in a sweep) is reported."""
    import plbar

    st = survey_study(plbar.Case(), [8.0, 9.0, 10.0], periods=40, record=10, modes=("rest", "up"), chunks=1)
    seen = []
    for task in st.tasks:
        with reporting(tmp_path / "r.progress"):
            import plbar.studies.execution.reports as R

            st.func(task)
            seen.append(R._now["done"])
    assert seen == [task_units(t) for t in st.tasks] == [120, 120]
    assert np.all(np.asarray(seen) > 0)


def test_refine_moves_within_a_mesh(monkeypatch):
    """``refine`` counted meshes only (18 s without a move at N = 16): now the carried points of each mesh."""
    import plbar
    import plbar.studies.refine.study as refine_mod

    said = []

    class Bar(Recorder):
        def set_description(self, desc, *_):
            said.append((desc, self.n))

    monkeypatch.setattr(refine_mod, "progress_bar", lambda total, *a, **k: Bar(total))
    task = refine_mod.refine_study([plbar.Case()], [3, 4, 5]).tasks[0]
    refine_mod.track_family(task, progress=True)
    inside = [(d, n) for d, n in said if ": point " in d]
    assert {d.split(",")[1].split(":")[0].strip() for d, _ in inside} == {"N = 4", "N = 5"}
    assert all(n < 3 for _, n in inside)               # while the mesh is being carried, before it counts
    j, k = map(int, inside[-1][0].rsplit(" ", 1)[1].split("/"))
    assert j == k > 1
