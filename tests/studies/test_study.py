"""Studies: load sweep against the core API, dask == local, kill-and-resume."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import plbar
from plbar.studies import get_executor
from plbar.studies import assign_families
from plbar.studies import run_study, task_key
from plbar.studies import load_sweep_study, sweep_tables, write_sweep_tables

GRID = (80, 80)
POSITIONS = (0.5, 1.5, 2.5, 3.0, 3.5)


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    st = load_sweep_study(5, positions=POSITIONS, grid=GRID)
    with get_executor("local", workers=2) as ex:
        res = run_study(folder, st, ex, progress=False)
    tables = sweep_tables(st.tasks, res)
    write_sweep_tables(folder, tables)
    return folder, st, tables


def test_sweep_max_matches_core_api(sweep):
    """(a) The sweep's max xi_eq on the family near T0_II/2, recomputed with plbar.solve at that s."""
    _, _, tables = sweep
    best = tables.summary["best"]["T0_II/2"]["single"]
    s = best["s1"]
    res = plbar.solve(plbar.Case(signatures="paper", load_points=((s, 1.0),), grid=GRID))
    T0I, T0II = res.prob.system.T0
    labels = assign_families([(b.T.min(), b.T.max()) for b in res.branches], [len(b) for b in res.branches],
                             T0I, T0II)
    fam = [b for b, f in zip(res.branches, labels) if f == "T0_II/2"]
    assert fam, "no branch near T0_II/2"
    xi = max(float(b.xi.max()) for b in fam)
    assert xi == pytest.approx(best["xi_max"], rel=1e-12)
    # the family is the paper's path 2 and the max beats every other position
    T = np.concatenate([b.T for b in fam])
    assert 11.2 < T.min() < 11.5 and 12.4 < T.max() < 12.7
    assert abs(T.min() - T0II / 2) / (T0II / 2) < 0.1
    mx = tables.maxima
    others = [mx["xi_max"][i] for i, f in enumerate(mx["family"]) if f == "T0_II/2"]
    assert best["xi_max"] == max(others)
    # the path geometry does not depend on the load position (paper Sec. 4.2)
    assert max(mx["geom_dev"]) < 1e-9


def test_sweep_tables_are_tidy(sweep):
    folder, st, tables = sweep
    rows = (folder / "sweep.csv").read_text().splitlines()
    assert rows[0].split(",")[:7] == ["case", "load", "s1", "a1", "s2", "a2", "family"]
    assert len(rows) - 1 == len(tables.rows["T"])
    assert {"T0_I", "T0_II/2"} <= set(tables.rows["family"])
    assert sorted(p.name for p in (folder / "tasks").iterdir()) == sorted(f"{task_key(t)}.json" for t in st.tasks)
    assert not [p for p in folder.rglob("*") if p.name.startswith(".")]


def _read_tables(folder: Path) -> dict:
    return {n: (folder / n).read_bytes() for n in ("sweep.csv", "sweep_max.csv", "sweep_summary.json")}


@pytest.mark.slow
def test_dask_equals_local(tmp_path):
    """(b) A dask LocalCluster with 2 workers gives bit-identical tables."""
    pytest.importorskip("dask.distributed")
    st = load_sweep_study(4, positions=(1.0, 2.5), pairs=(((1.0, 0.5), (3.0, 0.5)),), grid=(60, 60))
    out = {}
    for kind in ("local", "dask"):
        folder = tmp_path / kind
        with get_executor(kind, workers=2) as ex:
            res = run_study(folder, st, ex, progress=False)
        write_sweep_tables(folder, sweep_tables(st.tasks, res))
        out[kind] = _read_tables(folder)
    assert out["local"] == out["dask"]


SCRIPT = """
import sys
from plbar.studies import get_executor
from plbar.studies import run_study
from plbar.studies import load_sweep_study, sweep_tables, write_sweep_tables
st = load_sweep_study(5, positions=[0.1 * k for k in range(1, 50)], grid=(40, 40))
with get_executor("serial") as ex:
    res = run_study(sys.argv[1], st, ex, progress=False)
write_sweep_tables(sys.argv[1], sweep_tables(st.tasks, res))
"""


def _run(folder):
    return subprocess.run([sys.executable, "-c", SCRIPT, str(folder)], capture_output=True, text=True, timeout=300)


def _final(folder: Path) -> list[Path]:
    """Files under final names (temporary files start with a dot)."""
    return [p for p in folder.glob("*.json") if not p.name.startswith(".")]


@pytest.mark.slow
def test_kill_and_resume(tmp_path):
    """(c) kill -9 mid-study: no partial file under a final name; the rerun completes identically."""
    killed = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT, str(killed)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    tasks = killed / "tasks"
    t0 = time.time()
    while time.time() - t0 < 120:
        if tasks.is_dir() and len(_final(tasks)) >= 2:
            break
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    done = _final(tasks)
    assert 2 <= len(done) < 49, "the kill should land mid-study"
    for p in done:                      # every file under a final name is complete JSON
        d = json.loads(p.read_text())
        assert d["key"] == p.stem and "branches" in d["result"]
    assert not (killed / "sweep.csv").exists()
    r = _run(killed)
    assert r.returncode == 0, r.stderr
    fresh = tmp_path / "fresh"
    r = _run(fresh)
    assert r.returncode == 0, r.stderr
    assert _read_tables(killed) == _read_tables(fresh)
    # a third run computes nothing: every task file is reused unchanged
    before = {p.name: p.stat().st_mtime_ns for p in _final(tasks)}
    assert len(before) == 49
    assert _run(killed).returncode == 0
    assert before == {p.name: p.stat().st_mtime_ns for p in _final(tasks)}


_ORDER: list = []


def _record_order(task: dict) -> dict:
    _ORDER.append(task["i"])
    return {"i": task["i"]}


def test_costliest_tasks_are_submitted_first_and_tables_keep_the_task_order(tmp_path):
    """Study.cost: the longest-processing-time rule (submission by decreasing cost, ties in task order); the
    results come back in task order whatever ran first."""
    from plbar.studies import Study

    costs = [1.0, 5.0, 2.0, 5.0, 0.5]
    st = Study("order", _record_order, tuple({"i": i, "c": c} for i, c in enumerate(costs)), {},
               cost=lambda t: t["c"])
    _ORDER.clear()
    res = run_study(tmp_path / "s", st, progress=False)
    assert _ORDER == [1, 3, 2, 0, 4]
    assert [r["i"] for r in res] == [0, 1, 2, 3, 4]


def test_survey_tasks_are_sized_and_ordered_by_the_time_they_simulate():
    """Four forcing periods a task (the default survey: 161 -> 41 tasks), each task's cost its simulated time."""
    from plbar.studies.survey.study import survey_study
    from plbar.studies.survey.tasks import task_cost

    st = survey_study(plbar.Case(), np.linspace(6.0, 14.0, 161), 1000, 100)
    assert len(st.tasks) == 41 and sum(len(t["T"]) for t in st.tasks) == 161
    assert st.cost is task_cost
    assert task_cost(st.tasks[-1]) == pytest.approx(1000 * sum(st.tasks[-1]["T"]), rel=1e-15)
