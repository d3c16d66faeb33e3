"""The phase of a hum whose fundamental is weak (a rectifier's odd-dominant hum) while a sweep
passes it: the first round of the phase refinement must not rest on the fundamental alone."""
import numpy as np
import pytest

from odnn_sep.audio import denoise
from odnn_sep.audio import finetrack as ft


def _sweep_under_odd_hum(seed: int, sr: int = 8000, dur: float = 20.0):
    rng = np.random.default_rng(seed)
    t = np.arange(int(dur * sr)) / sr
    f0, f1 = 35.0, 1500.0                  # a logarithmic sweep: it crosses 60 Hz in the first seconds
    host = np.sqrt(2) * np.sin(2 * np.pi * f0 * dur / np.log(f1 / f0) * ((f1 / f0) ** (t / dur) - 1))
    f = 59.99 + 0.007 * (t - dur / 2)      # a slow ramp of the grid frequency
    ph = 2 * np.pi * np.cumsum(f) / sr
    amps = {1: 0.3, 3: 1.0, 5: 0.6, 7: 0.4, 9: 0.25, 11: 0.15}
    hum = sum(a * np.cos(k * ph + rng.uniform(0, 2 * np.pi)) for k, a in amps.items())
    hum *= np.std(host) / np.std(hum)
    return 0.1 * host, 0.1 * hum, sr


def test_sweep_through_a_weak_fundamental_keeps_the_phase():
    # the fundamental's phase alone followed the sweep for two seconds and bent every harmonic:
    # 12.6 dB before the carrying rule, 26.6 dB with it
    x, hum, sr = _sweep_under_odd_hum(0)
    r = denoise(x + hum, sr)
    assert r.harmonics[:4] == [1, 3, 5, 7]
    gain = 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - x) ** 2))
    assert gain > 20.0


@pytest.mark.parametrize("prec,expected", [
    ([0.01, 9.0, 9.0, 8.0], [True, True, False, False]),     # weak fundamental: the third joins
    ([5.0, 9.0, 9.0, 8.0], [True, False, False, False]),     # a fundamental that carries: as before
    ([0.0, 0.0, 0.001, 9.0], [True, True, True, True]),      # only the seventh carries
])
def test_carrying_extends_upwards_until_the_share_is_held(prec, expected):
    ks = np.array([1.0, 3.0, 5.0, 7.0])
    assert ft.carrying(ks <= 2, ks, np.array(prec)).tolist() == expected
