import os

import numpy as np
import pytest

os.environ.setdefault("MPLBACKEND", "agg")
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


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
