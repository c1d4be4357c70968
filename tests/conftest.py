import os

import numpy as np
import pytest

os.environ.setdefault("MPLBACKEND", "agg")
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


#: a run of at least this many tests compiles (or loads) the kernels before its first test (:func:`_kernels`)
WARM_FROM = 100

#: the simulator's specialisations the suite uses (accounts or replay, damped or not, split model or not: the FE
#: bar of 16 modes), compiled in a process of their own
_MOTION = """
from dataclasses import replace
import plbar
from plbar.motion import prepare
ratio = plbar.rayleigh_from_ratio(0.02, 8.0, 12.0)
for case in (plbar.Case(), plbar.Case(model="fe", n=16)):
    for rayleigh in (None, ratio):
        for accounts in (True, False):
            prepare(replace(case, rayleigh=rayleigh).problem(), accounts=accounts)
"""


def pytest_collection_finish(session):
    session.config.plbar_warm = len(session.items) >= WARM_FROM and not session.config.option.collectonly


@pytest.fixture(scope="session", autouse=True)
def _kernels(request):
    """The kernels compiled (after an install) or loaded once, before the first test of a full run: the
    simulator's in another process beside the continuum's in this one (two cores, two kernel packages: no cache
    entry written by both), then the chain's (its seeds are replayed by the simulator: after it), so that a first
    compile lands on no test's time (issue 44).  A run of a few
    tests skips it: they compile what they use, if anything."""
    if not getattr(request.config, "plbar_warm", False):
        return
    import subprocess
    import sys

    import plbar
    from plbar.continuum import simulate

    motion = subprocess.Popen([sys.executable, "-c", _MOTION], stdin=subprocess.DEVNULL)
    try:
        simulate(plbar.Case(model="continuum").continuum(), 2.5, periods=2, record=1)
    finally:
        motion.wait()
    plbar.solve(plbar.Case(signatures="paper", grid=(60, 60)))     # the chain (its replays: the simulator, loaded)


@pytest.fixture(autouse=True)
def _strict_floats():
    """A silent nan or overflow anywhere is a failing test (STYLE: py-pde)."""
    old = np.seterr(all="raise", under="ignore")
    yield
    np.seterr(**old)


@pytest.fixture(scope="session")
def default_result():
    """The paper's case, the paper's class only (what most tests are about)."""
    import plbar

    return plbar.solve(plbar.Case(signatures="paper"))


@pytest.fixture(scope="session")
def default_run():
    """The default case as ``plbar run`` solves it: the paper's class and every other signature."""
    import plbar

    return plbar.solve()


@pytest.fixture(scope="session")
def fe_p2_result():
    import plbar

    return plbar.solve(plbar.Case(signatures="paper", model="fe", n=8, element="P2", mass="consistent",
                                  load_points=((0.37, 1.0),)))


@pytest.fixture(scope="session")
def fe_p2_coarse():
    """The case of ``fe_p2_result`` on a 60 x 60 grid (a few seconds: for the tests not marked slow)."""
    import warnings

    import plbar

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", plbar.errors.CoarseGridWarning)
        return plbar.solve(plbar.Case(signatures="paper", model="fe", n=8, element="P2", mass="consistent",
                                      load_points=((0.37, 1.0),),
                                      grid=(60, 60)))


@pytest.fixture(scope="session")
def small():
    """The default case on a coarse grid (export and render tests)."""
    import plbar

    return plbar.solve(plbar.Case(signatures="paper", grid=(60, 60)))


@pytest.fixture(scope="session")
def p2_small():
    """A small P2 consistent-mass FE case (export and render tests)."""
    import plbar

    return plbar.solve(plbar.Case(signatures="paper", model="fe", n=4, element="P2", mass="consistent",
                                  load_points=((0.37, 1.0),),
                                  grid=(50, 50)))


#: the FE bar of the damped tests (issue 21)
DAMPED_FE = dict(model="fe", n=8, element="P1", mass="lumped", end_mass=0.5)


@pytest.fixture(scope="session")
def damped_result():
    """The default case with 2 % Rayleigh damping at T = 8 and 12."""
    import plbar

    return plbar.solve(plbar.Case(signatures="paper", rayleigh=plbar.rayleigh_from_ratio(0.02, 8.0, 12.0)))


@pytest.fixture(scope="session")
def damped_fe_result():
    """FE P1 lumped N = 8 with an end mass 0.5, 2 % Rayleigh damping at T = 2 and 4."""
    import plbar

    return plbar.solve(plbar.Case(signatures="paper", **DAMPED_FE, rayleigh=plbar.rayleigh_from_ratio(0.02, 2.0, 4.0)))
