"""A lone hum line (a pure tone, no other harmonic) under a louder bass note 0.5-0.7 Hz away, on and
off every few seconds: the line's phase is bridged across the notes (``lonebridge.py``) instead of
turning with them."""
import numpy as np
import pytest

from odnn_sep.audio import denoise
from odnn_sep.audio.lonebridge import bridge, bridge_error, held_samples


def _bass_over_pure_hum(seed, off, period, sr=8000, dur=20.0, hum_f=50.03):
    rng = np.random.default_rng(seed)
    t = np.arange(int(dur * sr)) / sr
    hum = 0.1 * np.cos(2 * np.pi * hum_f * t + 1.0)
    gate = ((t % (2 * period)) < period).astype(float)
    host = 0.14 * gate * np.sin(2 * np.pi * (hum_f + off) * t) + 0.02 * rng.standard_normal(t.size)
    return host, hum, sr


@pytest.mark.parametrize("seed, off, period", [(0, 0.7, 2.5), (1, -0.5, 3.5)])
def test_a_louder_note_beside_a_lone_line_is_bridged(seed, off, period):
    # the version whose track turned with the note left these at 6.3 and 8.0 dB (36-40 dB now)
    host, hum, sr = _bass_over_pure_hum(seed, off, period)
    r = denoise(host + hum, sr)
    assert r.harmonics == [1]
    gain = 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2))
    assert gain > 30.0


def test_a_wandering_phase_is_not_bridged():
    # a phase that swings by 0.02 cycles every 5 s cannot be told under notes 3 s long: the check
    # of the bridges on the trusted stretches says so
    td = np.arange(400) / 10.0
    held = (td % 6) < 3
    assert bridge_error(0.02 * np.sin(2 * np.pi * td / 5), held, td, 12, 10.0) > 0.005
    assert bridge_error(0.01 * td + 0.001 * td ** 2, held, td, 12, 10.0) < 1e-9


def test_bridge_needs_trusted_phase_within_reach():
    td = np.arange(800) / 10.0
    held = np.zeros(800, bool)
    held[5:795] = True            # 0.5 s trusted at each end of 80 s: too little to bridge from
    assert bridge(np.zeros(800), held, td, 12, 10.0) is None


def test_held_samples_are_those_far_below_the_quiet_weights():
    w = np.ones(100)
    w[20:60] = 0.05               # a note: weights 20 times lower
    w[70:75] = 0.5                # a drum hit: twice lower, still trusted
    assert np.nonzero(held_samples(w))[0].tolist() == list(range(20, 60))
