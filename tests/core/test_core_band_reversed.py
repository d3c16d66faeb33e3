"""A band-limited class on a record given in decreasing order of x (a time axis counted down, a
depth profile from the bottom) is the same class: it was refused as not uniformly spaced."""
import numpy as np

from odnn_sep.core import Band, Basis, Separator


def test_band_on_a_reversed_record_gives_the_increasing_record_s_fit():
    x = np.linspace(0.0, 10.0, 501)
    y = 0.7 * np.exp(-0.3 * x) + 0.2 * np.sin(2 * np.pi * 2.0 * x)
    basis = Basis([lambda x: np.exp(-0.3 * x)], names=["a"])
    up = Separator(basis, disturbance=Band(1.5, 2.5)).fit(x, y)
    down = Separator(basis, disturbance=Band(1.5, 2.5)).fit(x[::-1], y[::-1])
    assert abs(float(up.theta_[0]) - 0.7) < 1e-3
    np.testing.assert_allclose(down.theta_, up.theta_, rtol=1e-9)
