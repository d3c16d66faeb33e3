import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from odnn_sep.mismatch.locate import locate, locate_frequency, locate_time, noise_sigma


def test_white_noise_rarely_flags_anything():
    flagged = 0
    for seed in range(40):
        r = np.random.default_rng(seed).normal(size=800)
        t = np.arange(800) / 100.0
        flagged += bool(locate(t, r))
    assert flagged <= 4   # about 5 % per test family (BH / Bonferroni at 0.05)


def test_burst_located_in_time_and_tone_in_frequency():
    rng = np.random.default_rng(1)
    t = np.arange(2000) / 100.0
    r = rng.normal(size=2000)
    r[1000:1200] += 2.0 * np.sin(2 * np.pi * 7.0 * t[1000:1200])
    wins = locate_time(t, r)
    assert len(wins) == 1 and 9.5 <= wins[0]["start"] <= 10.5 and 11.5 <= wins[0]["end"] <= 12.5
    bands = locate_frequency(t, r)
    assert bands and abs(bands[0]["peak_hz"] - 7.0) < 0.3


@settings(max_examples=25, deadline=None)
@given(st.floats(0.1, 10.0), st.floats(-5, 5))
def test_noise_sigma_is_scale_equivariant_and_ignores_slow_trends(scale, slope):
    r = np.random.default_rng(0).normal(size=1000)
    s0 = noise_sigma(r)
    t = np.linspace(0, 1, 1000)
    assert abs(noise_sigma(scale * r) - scale * s0) < 1e-9 * scale
    assert abs(noise_sigma(r + slope * t) - s0) / s0 < 0.05
