"""Sinusoidal mains frequency wander on the audio engine (hum_wander.py) and bounded intervals."""
import importlib.util
import pathlib

import numpy as np
import pytest

from odnn_sep.core.bounded_interval import bounded_interval
from odnn_sep.errors import InputError
from odnn_sep.mismatch import explain
from odnn_sep.mismatch.hum_wander import wander_cycles
from odnn_sep.mismatch.model import make_model

_GEN = pathlib.Path(__file__).resolve().parents[2] / "recipes" / "mismatch_hum_wav.py"
_spec = importlib.util.spec_from_file_location("mismatch_hum_wav", _GEN)
gen = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(gen)

SR, SECONDS = 4000, 16.0    # 64000 samples: on the engine, quick


def test_sinusoidal_wander_is_named_frequency_wander_not_amplitude_modulation():
    # +-0.04 Hz around 60 Hz with a 5 s period; the recording's other content as in the engine tests
    y, sr, _ = gen.hum_recording(seconds=SECONDS, sr=SR, drift_hz=0.04, drift_period_s=5.0, seed=1)
    res = explain("hum", np.arange(len(y)) / sr, y.astype(float))
    assert res.effects == ["frequency_wander"]
    p = res.final_fit.params
    assert abs(abs(p["df_w"]) - 0.04) < 0.004
    assert abs(p["f_w"] - 0.2) < 0.005
    lo, hi = res.final_intervals["f_w"]
    assert lo <= 0.2 <= hi or abs(p["f_w"] - 0.2) < 0.002
    assert abs(p["f0"] - 60.0) < 0.005


def test_steady_hum_with_a_clock_offset_names_no_wander():
    y, sr, _ = gen.hum_recording(seconds=SECONDS, sr=SR, mains_hz=60.055, drift_hz=0.0, seed=2)
    res = explain("hum", np.arange(len(y)) / sr, y.astype(float))
    assert res.effects == []
    assert abs(res.calibration.fit.params["f0"] - 60.055) < 0.002


def test_wander_is_the_integral_of_the_frequency_deviation():
    p = {"df_w": 0.03, "f_w": 0.1, "phase_w": 0.4}
    tau = np.linspace(0, 20, 20001)
    freq = np.gradient(wander_cycles(tau, p), tau)
    assert np.allclose(freq, 0.03 * np.cos(2 * np.pi * 0.1 * tau + 0.4), atol=1e-5)


def test_short_records_do_not_offer_the_wander():
    m = make_model("hum", {"f0": 50.0})
    assert "frequency_wander" not in m.applicable_effects()
    with pytest.raises(InputError, match="frequency_wander.*audio engine"):
        m.with_effect("frequency_wander")


@pytest.mark.parametrize("value, se, lo, hi", [(1e-4, 0.7e-4, 0.0, np.inf), (0.02, 0.015, 0.0, 1.0),
                                               (-3.0, 2.0, -np.inf, 0.0), (1e-9, 1e-3, 0.0, np.inf),
                                               (0.5, 10.0, 0.0, 1.0), (5.0, 1.0, 0.0, np.inf),
                                               (np.nextafter(1.0, 0.0), 0.5, -1.0, 1.0),
                                               (5e-324, 1.0, 0.0, np.inf)])
def test_bounded_intervals_never_leave_the_bounds_and_contain_the_estimate(value, se, lo, hi):
    a, b = bounded_interval(value, se, lo, hi)
    assert lo <= a <= value <= b <= hi


def test_positive_rate_interval_excludes_zero_when_the_estimate_is_clear_of_it():
    # the Wald interval 1e-4 +- 1.37e-4 would cross 0; a log interval stays positive
    a, b = bounded_interval(1e-4, 0.7e-4, 0.0)
    assert 0.0 < a < 1e-4 < b


def test_bounded_interval_coverage_for_a_lognormal_rate():
    # a positive parameter whose estimate scatters log-normally: the log interval covers about 95 %
    rng = np.random.default_rng(0)
    true, rel = 2e-4, 0.6      # relative spread where the Wald interval would cross 0
    est = true * np.exp(rel * rng.normal(size=4000))
    cover = np.mean([(lambda ab: ab[0] <= true <= ab[1])(bounded_interval(e, rel * e, 0.0)) for e in est])
    assert 0.93 <= cover <= 0.97


def test_asking_for_the_wander_on_a_short_record_is_a_clear_error():
    y, sr, _ = gen.hum_recording(seconds=1.0, sr=4000, drift_hz=0.0)
    with pytest.raises(InputError, match="needs the audio engine"):
        explain("hum", np.arange(len(y)) / sr, y.astype(float), effects=["frequency_wander"])
