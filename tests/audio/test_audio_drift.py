"""A fast linear ramp of the fundamental (50 mHz/s, +-1.5 Hz over a minute) is found and tracked."""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import denoise
from odnn_sep.audio.metrics import snr_improvement_db


def _ramp_mix(rate_hz_s=0.05, dur_s=60.0, sr=4000, nominal=60.0, seed=3):
    rng = np.random.default_rng(seed)
    t = np.arange(int(dur_s * sr)) / sr
    # music-like host: a few held tones away from the hum lines, plus white noise
    host = 0.3 * rng.standard_normal(t.size)
    for f in (261.6, 329.6, 440.0, 523.3):
        host += 0.2 * np.sin(2 * np.pi * f * t + rng.uniform(0, 6)) * (np.sin(2 * np.pi * t / rng.uniform(3, 9)) > 0)
    cycles = nominal * t + 0.5 * rate_hz_s * (t - dur_s / 2) ** 2
    hum = sum(a * np.cos(2 * np.pi * k * cycles + rng.uniform(0, 6)) for k, a in ((1, 0.5), (2, 0.3), (3, 0.25),
                                                                                     (5, 0.1)))
    return host + hum, sr, host, hum


def test_fast_ramp_is_tracked():
    y, sr, host, hum = _ramp_mix()
    r = denoise(y, sr)
    assert r.harmonics[:3] == [1, 2, 3]
    # the track spans the ramp (58.5 .. 61.5 Hz) and the hum comes off
    assert np.ptp(r.track_hz) > 2.5
    assert snr_improvement_db(host, hum, r.y) > 25.0
