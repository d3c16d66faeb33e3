"""Whole-input harmonic amplitudes by generalised least squares (odnn_sep.audio.amplitude)."""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import amplitude, denoise, track
from odnn_sep.audio.blockplan import BlockPlan
from odnn_sep.audio.io import ArraySource

SR = 2000


def _bursty_noise(n, rng, *, period_s=6.0, quiet=0.05):
    """White noise whose level switches between loud and quiet every ``period_s`` / 2 seconds
    (speech-like: syllables and pauses)."""
    t = np.arange(n) / SR
    gate = np.where(np.sin(2 * np.pi * t / period_s + rng.uniform(0, 6)) > 0, 1.0, quiet)
    return gate * rng.standard_normal(n)


def _steady(y, ks, f0=50.0, hop_s=4.0):
    src = ArraySource(y, SR)
    D = track.demodulate(src, f0, ks)
    nb = (src.frames - 1) // int(hop_s * SR) + 2
    z = np.zeros(nb)
    trk = track.Track(t=np.arange(nb) * hop_s, f0=np.full(nb, f0), rate=z, curv=z,
                      confident=np.ones(nb, bool), strength=z)
    return amplitude.steady_amplitudes(D, f0, ks, trk, BlockPlan(sr=SR, n_frames=src.frames, hop=int(hop_s * SR)))


def test_weights_follow_the_content_level_and_beat_equal_weights():
    # a weak steady line under noise that comes and goes: weighting by the local content power
    # uses the pauses; the equal-weight least-squares amplitude does not
    rng = np.random.default_rng(1)
    n = 96 * SR
    t = np.arange(n) / SR
    errs_gls, errs_ls = [], []
    for _ in range(6):
        noise = 0.6 * _bursty_noise(n, rng)
        y = 0.05 * np.cos(2 * np.pi * 100.0 * t + 0.3) + noise
        errs_gls.append(_steady(y, [2])[0, 0] / 0.05 - 1)
        cs = np.stack([np.cos(2 * np.pi * 100.0 * t), np.sin(2 * np.pi * 100.0 * t)], axis=1)
        errs_ls.append(np.hypot(*np.linalg.lstsq(cs, y, rcond=None)[0]) / 0.05 - 1)
    rms_gls, rms_ls = np.sqrt(np.mean(np.square(errs_gls))), np.sqrt(np.mean(np.square(errs_ls)))
    assert rms_gls < 0.5 * rms_ls, (rms_gls, rms_ls)
    assert rms_gls < 0.01, rms_gls


def test_changing_line_is_not_reported_as_steady():
    rng = np.random.default_rng(2)
    n = 96 * SR
    t = np.arange(n) / SR
    ramp = 1.0 - 0.5 * t / t[-1]
    y = ramp * np.cos(2 * np.pi * 50.0 * t) + 0.3 * np.cos(2 * np.pi * 100.0 * t + 1.0) + 0.2 * rng.standard_normal(n)
    a = _steady(y, [1, 2])
    assert np.isnan(a[0, 0])
    assert abs(a[0, 1] / 0.3 - 1) < 0.01, a


def test_near_partial_does_not_bias_the_line():
    # a louder partial 3 Hz from the line, slowly swelling, with bursty content around it
    rng = np.random.default_rng(3)
    n = 96 * SR
    t = np.arange(n) / SR
    env = 0.5 + 0.5 * np.sin(2 * np.pi * 0.05 * t) ** 2
    y = (0.1 * np.cos(2 * np.pi * 100.0 * t + 2.0) + 0.3 * env * np.cos(2 * np.pi * 103.0 * t)
         + 0.3 * _bursty_noise(n, rng))
    a = _steady(y, [2])
    assert abs(a[0, 0] / 0.1 - 1) < 0.01, a


def test_denoise_reports_the_whole_input_amplitudes():
    rng = np.random.default_rng(5)
    n = 96 * SR
    t = np.arange(n) / SR
    amps = (0.2, 0.1, 0.05)
    hum = sum(a * np.cos(2 * np.pi * k * 50.0 * t + k) for k, a in enumerate(amps, start=1))
    r = denoise(hum + 0.4 * _bursty_noise(n, rng), SR)
    assert r.harmonics[:3] == [1, 2, 3]
    for k, a in enumerate(amps, start=1):
        assert np.isfinite(r.amplitude_overall[0, k - 1])
        assert abs(r.line_amplitude(f"h{k}")[0] / a - 1) < 0.01, (k, r.line_amplitude(f"h{k}"))


def test_batches_of_blocks_give_the_same_amplitudes(monkeypatch):
    # long inputs are processed a few blocks at a time (bounded memory): same numbers
    rng = np.random.default_rng(7)
    n = 96 * SR
    t = np.arange(n) / SR
    y = 0.2 * np.cos(2 * np.pi * 50.0 * t) + 0.05 * np.cos(2 * np.pi * 100.0 * t + 1) + 0.3 * _bursty_noise(n, rng)
    one = _steady(y, [1, 2])
    monkeypatch.setattr(amplitude, "BATCH_CHUNKS", 1000)      # 1-2 blocks of 800 chunks per batch
    np.testing.assert_allclose(_steady(y, [1, 2]), one, rtol=1e-12)
