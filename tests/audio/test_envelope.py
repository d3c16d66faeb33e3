"""A hum level shared by the harmonics that changes within a block is followed (envelope.py); steady
hum and content near the lines leave the output as the block fit gives it."""
import numpy as np

from odnn_sep.audio import denoise


def _hum(t, f0=50.0):
    return sum(np.cos(2 * np.pi * k * f0 * t + k) / k for k in range(1, 6))


def _gain_db(host, hum, out):
    return 10 * np.log10(np.sum(hum ** 2) / np.sum((out - host) ** 2))


def test_a_modulated_hum_level_is_followed():
    sr = 4000
    t = np.arange(30 * sr) / sr
    rng = np.random.default_rng(3)
    host = 0.3 * rng.standard_normal(t.size)
    hum = 0.3 * _hum(t) * (1 + 0.4 * np.sin(2 * np.pi * 0.5 * t))   # a load changing twice a second
    r = denoise(host + hum, sr)
    assert r.info["level_followed_s"] is not None
    # one amplitude per block leaves about 11 dB here
    assert _gain_db(host, hum, r.y) > 18


def test_a_hum_switched_on_midway_is_followed():
    sr = 4000
    t = np.arange(30 * sr) / sr
    rng = np.random.default_rng(4)
    host = 0.3 * rng.standard_normal(t.size)
    hum = 0.3 * _hum(t) * np.where(t > 12.0, 1.0, 0.2)
    r = denoise(host + hum, sr)
    assert r.info["level_followed_s"] is not None
    assert _gain_db(host, hum, r.y) > 20


def test_steady_hum_is_left_to_the_block_fit():
    sr = 4000
    t = np.arange(30 * sr) / sr
    rng = np.random.default_rng(5)
    host = 0.3 * rng.standard_normal(t.size)
    r = denoise(host + 0.3 * _hum(t), sr)
    assert r.info["level_followed_s"] is None
