"""The finder on real recordings from ../shared/data (skipped when the data are absent)."""
from pathlib import Path

import pytest

from odnn_sep.mismatch import explain
from odnn_sep.mismatch.io import load_data

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"


def _need(rel):
    p = DATA / rel
    if not p.exists():
        pytest.skip(f"shared data {rel} absent")
    return p


def test_enf_mains_reference_misses_the_third_harmonic():
    t, y, _ = load_data(_need("enf_whu_mains_reference/001_ref.wav"), duration=4.0)
    res = explain("hum", t, y, params={"f0": 50.0})
    assert res.effect == "missing_harmonic" and res.verdict.fit.params["k_h"] == 3.0
    assert 49.9 < res.calibration.fit.params["f0"] < 50.1


@pytest.mark.slow
def test_phone_pendulum_at_60_degrees_needs_the_sine():
    t, y, _ = load_data(_need("phone_pendulum_phyphox/l2LongTheta60.csv"), column="1", start=5, duration=20)
    res = explain("pendulum", t, y, params={"L": 0.258})
    assert res.effect == "large_angle"
    assert 0.8 < res.verdict.fit.params["s_angle"] < 1.1
    # without the sine, calibration pulls w2 = g/L well below its small-angle value (37.97 at 5 deg)
    assert res.calibration.fit.params["w2"] < res.verdict.fit.params["w2"]
