"""Copies of one channel are one piece of evidence: the pooled lock tests count the channels as
independent only as far as their contents differ (``lock.effective_channels``)."""
import sys
from pathlib import Path

import numpy as np
import pytest

from odnn_sep.audio import denoise
from odnn_sep.audio.lock import effective_channels, lock_p_values

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "recipes"))
from _audio_hosts import bass_near  # noqa: E402  (a bass note 0.3-1.5 Hz off 50 Hz, gated, over noise)


def _music(sr=16000, seconds=20.0):
    return 0.1 * bass_near(int(seconds * sr), sr, np.random.default_rng(0), 50.0)


@pytest.mark.parametrize("copies", [4, 8])
def test_copies_of_a_hum_free_channel_hold_no_hum(copies):
    # the version before found harmonic 1 (the bass note) on 2, 4 and 8 copies, none on the channel alone
    x, sr = _music(), 16000
    assert denoise(x, sr).harmonics == []
    y = np.tile(x[:, None], (1, copies))
    r = denoise(y, sr)
    assert r.harmonics == [] and not r.extra_combs
    assert np.array_equal(r.y, y)


@pytest.mark.parametrize("copies", [4, 8])
def test_a_hum_on_every_copy_is_still_found(copies):
    x, sr = _music(), 16000
    t = np.arange(len(x)) / sr
    hum = 0.1 * (np.cos(2 * np.pi * 50.02 * t) + 0.5 * np.cos(2 * np.pi * 100.04 * t + 1)
                  + 0.3 * np.cos(2 * np.pi * 150.06 * t + 2))
    mono = denoise(x + hum, sr)
    r = denoise(np.tile((x + hum)[:, None], (1, copies)), sr)
    assert r.harmonics == mono.harmonics == [1, 2, 3]
    gain = 10 * np.log10(copies * np.sum(hum ** 2) / np.sum((r.y - x[:, None]) ** 2))
    gain_mono = 10 * np.log10(np.sum(hum ** 2) / np.sum((mono.y - x) ** 2))
    assert gain > 30.0 and gain > gain_mono - 1.0        # 35.4 and 35.5 dB


def test_copies_count_once_in_the_lock_test():
    rng = np.random.default_rng(1)
    one = (rng.standard_normal((2000, 1, 1)) + 1j * rng.standard_normal((2000, 1, 1))) + 0.12
    p_one = lock_p_values(one, 8000)[0][0]
    p_copies = lock_p_values(np.repeat(one, 6, axis=1), 8000)[0][0]
    assert p_copies == pytest.approx(p_one, rel=1e-6)
    other = rng.standard_normal((2000, 5, 1)) + 1j * rng.standard_normal((2000, 5, 1))
    assert 4.5 < effective_channels(np.concatenate([one, other + 0.12], axis=1))[0] <= 6.0
