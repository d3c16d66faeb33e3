"""A periodic class on sample points with repeats (several readings at one x).

The sampling step was the median of all spacings, 0 when most points repeat: a ZeroDivisionError
traceback from ``separate --disturbance periodic:P``. The step is now the median of the positive
spacings.
"""
import numpy as np

from odnn_sep.core import Periodic


def test_periodic_on_repeated_points_keeps_periodic_functions():
    x = np.repeat(np.linspace(0.0, 10.0, 200), 2)
    P = Periodic(period=1.0).projector(x)
    g = np.sin(2 * np.pi * x) + 0.3 * np.cos(4 * np.pi * x)
    assert np.abs(P.apply(g) - g).max() < 1e-9       # in the class: kept whole
    trend = x - x.mean()
    assert np.linalg.norm(P.apply(trend)) < 0.5 * np.linalg.norm(trend)   # a trend is mostly not periodic
