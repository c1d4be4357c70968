"""The bar record's derived numbers against closed forms."""

import numpy as np
import pytest

from plbar.model import Bar, chain, uniform_bar


def test_transit_time_is_the_sum_of_the_elements_crossings():
    """``Bar.transit``: L / c for a uniform bar (the 3 m column: c = sqrt(2.7e9 / 216)), N for the chain, and the sum
    of h_e / c_e over elements of different sections (each crossing timed independently here)."""
    col = uniform_bar(4, length=3.0, EA=2.7e9, rhoA=216.0)
    assert col.transit == pytest.approx(3.0 / np.sqrt(2.7e9 / 216.0), rel=1e-14)
    assert chain(5).transit == pytest.approx(5.0, rel=1e-14)
    EA, rhoA = np.array([1.0, 4.0, 9.0]), np.array([1.0, 1.0, 4.0])
    bar = Bar(np.array([0.0, 0.5, 1.0, 2.0]), "P1", "lumped", EA, rhoA)
    assert bar.transit == pytest.approx(0.5 / 1.0 + 0.5 / 2.0 + 1.0 / 1.5, rel=1e-14)
