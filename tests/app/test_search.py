"""The search for other signatures begun beside the paper's class (plbar.app.signatures.Search)."""

import threading
import time

import numpy as np
import pytest

import plbar
from plbar.app.signatures import SEED_PERIODS, Search, _seeding, _seeds, search_window


def _seeding_threads():
    return [t for t in threading.enumerate() if t.name.startswith("plbar-seeding")]


def test_the_seeds_begun_beside_the_paper_solve_are_those_simulated_after_it():
    """The seeding simulation run in the search's thread (during the paper's solve) gives the seeds of the same
    simulation run afterwards in the calling thread: the same forcing periods, the same polished orbits."""
    case = plbar.Case()
    prob, dom = case.problem(), case.domain(plbar.Case().problem())
    plbar.motion.prepare(prob, accounts=False)               # compiled: the search simulates in its thread
    with Search(prob, dom, "default") as search:
        assert search._future is not None
        plbar.find_paths(prob, dom, case.grid)                  # the paper's class meanwhile
        beside = search._simulation()
    after = _seeding(prob, search_window(prob, dom), "default")
    np.testing.assert_array_equal(beside.T, after.T)
    np.testing.assert_array_equal(beside.events["time"], after.events["time"])
    a, b = _seeds(prob, beside), _seeds(prob, after)
    assert len(a) == len(b) > 0
    assert [str(o.sig) for o in a] == [str(o.sig) for o in b]
    np.testing.assert_allclose([o.loss_per_T for o in a], [o.loss_per_T for o in b], rtol=1e-12)
    assert search.done == SEED_PERIODS["default"][1]             # every period counted for the progress bar


def test_a_cancelled_search_stops_its_simulation_at_once():
    """Leaving the search early (an error in the paper's solve, Ctrl-C) stops the simulation at its next block of
    periods and leaves no thread behind: far sooner than the simulation would take."""
    case = plbar.Case()
    prob, dom = case.problem(), case.domain(plbar.Case().problem())
    plbar.motion.prepare(prob, accounts=False)
    t = time.perf_counter()
    _seeding(prob, search_window(prob, dom), "all")             # the whole simulation, for scale
    full = time.perf_counter() - t
    with pytest.raises(KeyError):
        with Search(prob, dom, "all"):
            time.sleep(0.05)
            raise KeyError("the paper's solve failed")
    stopped = time.perf_counter() - t - full
    assert not _seeding_threads()
    assert stopped < 0.75 * full, (stopped, full)
