"""At EEG and ECG rates the lines are looked for up to 5 Hz under Nyquist (detect.top_hz): the
120 Hz harmonic of 60 Hz mains in a 256 Hz recording lies 8 Hz under it."""
import numpy as np

from odnn_sep.audio import denoise
from odnn_sep.audio.detect import candidate_harmonics, top_hz


def test_the_top_is_unchanged_at_audio_rates_and_nearer_nyquist_at_eeg_rates():
    assert top_hz(8000) == 3800.0 and top_hz(44100) == 0.95 * 22050
    assert top_hz(256) == 123.0 and top_hz(1000) == 495.0 and top_hz(100) == 47.5
    assert candidate_harmonics(60.0, 256, "auto", None) == [1, 2]
    assert candidate_harmonics(60.0, 256, "auto", 100.0) == [1]


def test_a_second_harmonic_near_nyquist_at_256_hz_is_removed():
    sr = 256
    rng = np.random.default_rng(0)
    t = np.arange(60 * sr) / sr
    ph = 2 * np.pi * np.cumsum(60.0 + 0.02 * np.sin(2 * np.pi * t / 20)) / sr
    hum = np.cos(ph + 1) + 0.5 * np.cos(2 * ph + 2)
    host = np.convolve(rng.standard_normal(t.size), np.ones(5) / 5, "same")
    host *= np.std(hum) / np.std(host)
    r = denoise(host + hum, sr)
    assert r.harmonics == [1, 2]
    # 7 dB when only the 60 Hz line was tested
    assert 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2)) > 30.0
