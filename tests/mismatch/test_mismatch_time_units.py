"""The same record with time in s, ms or us calibrates to the same physics, in the units of its time."""
import warnings

import numpy as np
import pytest

from odnn_sep.core.uncertainty import sandwich_standard_errors
from odnn_sep.mismatch.calibrate import calibrate
from odnn_sep.mismatch.model import make_model


def _calibrated(scale):
    rng = np.random.default_rng(0)
    t = np.linspace(0, 20, 400)
    y = np.exp(-0.1 * t) * np.cos(2 * t) + 0.01 * rng.normal(size=t.size)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return calibrate(make_model("oscillator"), t * scale, y).fit


@pytest.fixture(scope="module")
def seconds():
    return _calibrated(1.0)


# the power of the time unit in each parameter: k [1/s^2], c [1/s], x0 [m], v0 [m/s]
POWER = {"k": -2, "c": -1, "x0": 0, "v0": -1}


@pytest.mark.parametrize("scale", [1e3, 1e6])
def test_time_in_ms_or_us_calibrates_like_seconds(seconds, scale):
    f = _calibrated(scale)
    assert f.rms == pytest.approx(seconds.rms, rel=1e-6)
    for k, p in POWER.items():
        assert f.params[k] == pytest.approx(seconds.params[k] * scale ** p, rel=1e-4), k
        assert f.determined(k), k
        assert f.stderr[k] == pytest.approx(seconds.stderr[k] * scale ** p, rel=0.05), k


def test_standard_errors_do_not_depend_on_the_parameters_units():
    rng = np.random.default_rng(1)
    J = rng.normal(size=(200, 3))
    r = rng.normal(size=200)
    base = sandwich_standard_errors(J, r, 197, block=10).stderr
    units = np.array([1e-12, 1.0, 1e9])     # J'J's condition number goes to 1e42
    scaled = sandwich_standard_errors(J * units, r, 197, block=10).stderr
    np.testing.assert_allclose(scaled * units, base, rtol=1e-9)
