"""Basis columns of far different sizes, and data in small units, keep honest coefficients and intervals."""
import warnings

import numpy as np
import pytest

from odnn_sep.core import Band, Basis, Convex, Orthogonal, Separator


def _fit(basis, dist, x, y):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Separator(basis, disturbance=dist).fit(x, y).result_


@pytest.mark.parametrize("dist", [Orthogonal(), Band(0, 0.1)])
def test_a_large_column_beside_a_small_one_keeps_both(dist):
    # x**10 on [0, 10] (norm 1e11): the pivoted QR dropped sin(3x) and reported it as 0 +- 0
    x = np.linspace(0, 10, 500)
    y = 2 * np.sin(3 * x) + 3e-10 * x**10 + 0.01 * np.random.default_rng(0).standard_normal(500)
    r = _fit(Basis([lambda x: np.sin(3 * x), lambda x: x**10], names=["s", "p"]), dist, x, y)
    lo, hi = r.interval[0]
    assert r.stderr[0] > 0 and lo < 2 < hi and hi - lo < 0.2


def test_convex_set_of_a_coefficient_in_small_units():
    # y in units where the coefficient is 2e-9: the set was [2.01953e-09, 2.01953e-09] (zero width, off)
    x = np.linspace(-1, 1, 400)
    y = 2 * np.sin(5 * x) + np.exp(x) + 0.02 * np.random.default_rng(0).standard_normal(400)
    basis = Basis([lambda x: np.sin(5 * x)], names=["s"])
    big = _fit(basis, Convex(), x, y).interval[0]
    small = _fit(basis, Convex(), x, 1e-9 * y).interval[0]
    assert small[0] < 2e-9 < small[1]
    assert np.allclose(small * 1e9, big, rtol=2e-3)
