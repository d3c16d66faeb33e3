"""A convex or monotone class with x in epoch seconds (1.7e9 and up, as loggers write time).

The least-squares solve inside the cone fit cut the constant column off next to x (its singular
value fell under lstsq's relative cut-off): theta came out 2.94 instead of 3.00 and the identified set
had zero width, ``[2.93838, 2.93838]``. The fit must not depend on where the clock started.
"""
import warnings

import numpy as np
import pytest

from odnn_sep.core import Basis, Convex, Separator

T0 = np.linspace(0, 3 * 86400, 300)
Y = (3 * np.sin(2 * np.pi * T0 / 86400) + 1e-5 * T0
     + 0.1 * np.random.default_rng(0).normal(size=T0.size))
DAY = 2 * np.pi / 86400


@pytest.mark.parametrize("dist", [Convex()])
def test_offset_of_the_clock_does_not_change_the_set(dist):
    sets = []
    for start in (0.0, 1.7e9):
        basis = Basis([lambda t, s=start: np.sin(DAY * (t - s)), lambda t, s=start: np.cos(DAY * (t - s))],
                      names=["s", "c"])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sets.append(Separator(basis, disturbance=dist).fit(T0 + start, Y).result_.interval)
    np.testing.assert_allclose(sets[1], sets[0], rtol=1e-6, atol=1e-6)
    lo, hi = sets[1][0]
    assert lo < 3 < hi and hi - lo > 1e-3
