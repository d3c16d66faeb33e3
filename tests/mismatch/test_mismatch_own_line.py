"""A pickup at a harmonic of an oscillator's own frequency is described, never named, and the verdict
does not blame the calibration."""
import warnings

import numpy as np
import pytest

from odnn_sep.mismatch import explain, make_model
from odnn_sep.mismatch.report import result_dict


@pytest.mark.parametrize("harmonic", [2, 3])
def test_a_pickup_at_a_harmonic_is_described_not_named(harmonic):
    t = np.linspace(0, 20, 600)
    m = make_model("oscillator", {"k": 4.0, "c": 0.1, "x0": 1.0})
    y = m.predict(t) + 0.05 * np.sin(harmonic * 2.0 * t + 0.4) + 0.01 * np.random.default_rng(3).normal(size=t.size)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        v = result_dict(explain("oscillator", t, y))["verdict"]
    assert v["effects"] == []                       # never periodic_forcing with confidence
    line = v["unnamed_periodic"]
    assert line["harmonic"] == harmonic
    assert abs(line["frequency_hz"] - harmonic * 2.0 / (2 * np.pi)) < 0.01
    assert f"{harmonic}x the system's own frequency" in v["description"]
    assert "--disturbance periodic:" in v["description"]
    # the calibration converged: the verdict used to send the user to the starting values
    assert "starting values" not in v["description"]
