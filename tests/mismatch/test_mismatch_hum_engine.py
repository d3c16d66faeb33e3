"""The hum preset on long records: the audio engine's basebands (hum_engine.py, hum_baseband.py)."""
import importlib.util
import pathlib

import numpy as np
import pytest

from odnn_sep.mismatch import explain
from odnn_sep.mismatch.hum_baseband import band_noise, demodulate_bands, stack, track_mains
from odnn_sep.mismatch.hum_engine import HumBands

_GEN = pathlib.Path(__file__).resolve().parents[2] / "recipes" / "mismatch_hum_wav.py"
_spec = importlib.util.spec_from_file_location("mismatch_hum_wav", _GEN)
gen = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(gen)

SR, SECONDS = 4000, 12.0    # 48000 samples: long enough for the engine, fast enough for a test


def _record(**kw):
    y, sr, truth = gen.hum_recording(seconds=SECONDS, sr=SR, **kw)
    return np.arange(len(y)) / sr, y.astype(float), truth


def test_weak_fundamental_drift_named_and_f0_not_pulled():
    t, y, truth = _record(drift_hz=0.08)
    res = explain("hum", t, y)
    assert res.effects == ["frequency_drift"]
    assert "audio engine" in res.notes[0]
    p = res.final_fit.params
    assert abs(p["f0"] - 60.0) < 0.005                      # weak 60 Hz under strong 120/180 Hz
    assert abs(p["f1"] - 0.08 / SECONDS) < 0.05 * 0.08 / SECONDS
    assert abs(np.hypot(p["a2"], p["b2"]) - 0.1) < 0.005


def test_given_harmonics_name_the_missing_one():
    t, y, _ = _record(drift_hz=0.0)
    res = explain("hum", t, y, params={"harmonics": 1})
    assert res.effects[0] == "missing_harmonic"
    p = res.final_fit.params
    assert p["k_h"] == 2 and abs(np.hypot(p["a_h"], p["b_h"]) - 0.1) < 0.005


def test_steady_hum_nothing_missing():
    t, y, _ = _record(drift_hz=0.0, seed=3)
    res = explain("hum", t, y)
    assert res.effects == [] and "audio engine" in res.notes[0]


def test_channel_coupling_on_the_bands_and_its_null():
    y2, _, _ = gen.hum_recording(seconds=SECONDS, sr=SR, drift_hz=0.0, coupling=0.05, seed=4)
    t = np.arange(len(y2)) / SR
    res = explain("hum", t, y2[:, 0].astype(float), aux={"B": y2[:, 1].astype(float)})
    assert res.effects == ["channel_coupling"]
    assert abs(res.final_fit.params["kappa_B"] - 0.05) < 0.01
    y0, _, _ = gen.hum_recording(seconds=SECONDS, sr=SR, drift_hz=0.0, coupling=0.0, seed=4)
    res0 = explain("hum", t, y0[:, 0].astype(float), aux={"B": y0[:, 1].astype(float)})
    assert res0.effects == []


def test_short_record_stays_on_the_samples():
    t = np.arange(800) / 400.0
    y = np.cos(2 * np.pi * 50 * t) + 0.05 * np.random.default_rng(0).normal(size=800)
    res = explain("hum", t, y, params={"f0": 50.0, "harmonics": 1})
    assert not any("audio engine" in n for n in res.notes)


def test_band_model_matches_demodulated_hum_exactly():
    """The baseband hum model is the demodulated hum itself (no approximation beyond the filter)."""
    t, y, _ = _record(drift_hz=0.05, noise=0.0, host=0.0)
    mains = track_mains(y + 1e-4 * np.random.default_rng(1).normal(size=len(y)), SR)
    bands = demodulate_bands(y, 0.0, SR, [1, 2, 3, 4], mains, rate_hz=10.0)
    sigma = np.ones(4)
    pre = HumBands(bands, sigma, mains, t0=0.0)
    # the truth, written as the hum preset's parameters (phases of the generator with seed 0)
    rng = np.random.default_rng(0)
    phases = [rng.uniform(0, 2 * np.pi) for _ in range(3)]
    p = {"f0": 60.0, "harmonics": 3, "f1": 0.05 / SECONDS}
    for k, (a, ph) in enumerate(zip((0.01, 0.1, 0.08), phases, strict=True), start=1):
        # a cos(k phi + ph) with phi = 2 pi int f: phi(0) = 0, so the model's phase origin is t = 0 ...
        p[f"a{k}"], p[f"b{k}"] = a * np.cos(ph), -a * np.sin(ph)
    p["f0"] += p["f1"] * (pre.t_mid - SECONDS / 2)   # the generator's drift is centred on the record
    pred = pre.build(("frequency_drift",))(pre.times(), p)
    data = stack(bands.z, sigma)
    # ... and the model's drift term is zero at the first kept step, so allow one common phase per harmonic
    z_pred = (pred[0::2] + 1j * pred[1::2]).reshape(-1, 4)
    z_data = (data[0::2] + 1j * data[1::2]).reshape(-1, 4)
    for i in range(3):
        rot = np.vdot(z_pred[:, i], z_data[:, i]) / np.vdot(z_pred[:, i], z_pred[:, i])
        assert abs(abs(rot) - 1) < 2e-3
        assert np.max(np.abs(z_data[:, i] - rot * z_pred[:, i])) < 2e-3 * abs(z_pred[0, i])
    assert np.max(np.abs(z_data[:, 3])) < 1e-4


def test_band_noise_reads_each_band():
    rng = np.random.default_rng(2)
    z = np.vstack([0.1 * (rng.normal(size=3000) + 1j * rng.normal(size=3000)),
                   1.0 * (rng.normal(size=3000) + 1j * rng.normal(size=3000))])
    assert np.allclose(band_noise(z), [0.1, 1.0], rtol=0.08)


@pytest.mark.parametrize("bad", [np.r_[np.arange(30000), 30000.5 + np.arange(20000)] / 4000.0])
def test_irregular_time_stays_on_the_samples(bad):
    y = np.cos(2 * np.pi * 50 * bad)
    from odnn_sep.mismatch.hum_engine import _engine_case
    assert _engine_case("hum", bad, y, {}) is None
