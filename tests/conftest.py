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
    import plbar

    return plbar.solve()


@pytest.fixture(scope="session")
def fe_p2_result():
    import plbar

    return plbar.solve(plbar.Case(model="fe", n=8, element="P2", mass="consistent", load_points=((0.37, 1.0),)))


@pytest.fixture(scope="session")
def fe_p2_coarse():
    """The case of ``fe_p2_result`` on a 60 x 60 grid (a few seconds: for the tests not marked slow)."""
    import warnings

    import plbar

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", plbar.errors.CoarseGridWarning)
        return plbar.solve(plbar.Case(model="fe", n=8, element="P2", mass="consistent", load_points=((0.37, 1.0),),
                                      grid=(60, 60)))


@pytest.fixture(scope="session")
def small():
    """The default case on a coarse grid (export and render tests)."""
    import plbar

    return plbar.solve(plbar.Case(grid=(60, 60)))


@pytest.fixture(scope="session")
def p2_small():
    """A small P2 consistent-mass FE case (export and render tests)."""
    import plbar

    return plbar.solve(plbar.Case(model="fe", n=4, element="P2", mass="consistent", load_points=((0.37, 1.0),),
                                  grid=(50, 50)))
