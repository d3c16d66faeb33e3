"""Block-length choice, amplitude pooling across blocks and the second look for comb gaps."""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import blocklen, denoise, detect, track
from odnn_sep.audio.io import ArraySource


def _hum(t, f0=50.0, amps=(1.0, 0.5, 0.3), am=None):
    env = 1.0 if am is None else am
    return sum(a * env * np.cos(2 * np.pi * k * f0 * t + k) for k, a in enumerate(amps, start=1))


def _choice(y, sr):
    src = ArraySource(y, sr)
    spec = detect.excerpt_spectrum(src, keep_segments_hz=400.0)
    det = detect.detect_hum(spec, sr)
    ks = det.harmonics
    w = np.stack([1.0 / det.floors[("h", k)] for k in ks], axis=1)
    D = track.demodulate(src, det.mains_hz, ks)
    T, trk = blocklen.choose_block(D, sr, src.frames, det.mains_hz, ks, w)
    return T, trk


def test_block_length_follows_the_hum():
    rng = np.random.default_rng(3)
    sr = 2000
    t = np.arange(64 * sr) / sr
    noise = 0.3 * rng.standard_normal(len(t))
    # steady hum in noise: the long block cuts the narrower notch
    T_steady, trk = _choice(_hum(t) + noise, sr)
    assert T_steady == 16.0 and len(trk.f0) == (len(t) - 1) // (8 * sr) + 2
    # strong hum whose amplitude swings within a block: the short block follows it
    am = 1.0 + 0.8 * np.sin(2 * np.pi * t / 9.0)
    T_fast, trk = _choice(30 * _hum(t, am=am) + noise, sr)
    assert T_fast == 8.0 and len(trk.f0) == (len(t) - 1) // (4 * sr) + 2


def test_steady_tone_amplitude_is_pooled_and_changing_tone_is_followed():
    rng = np.random.default_rng(4)
    sr = 4000
    t = np.arange(80 * sr) / sr
    noise = 0.5 * rng.standard_normal(len(t))
    hum = _hum(t)
    steady = 0.02 * np.cos(2 * np.pi * 733.3 * t + 0.4)
    r = denoise(hum + steady + noise, sr, tones=[733.3], block_s=8.0)
    name = r.line_names[len(r.harmonics)]
    # a weak tone (about 10 dB over the floor in one block), refined to a fraction of a mHz so
    # its phase holds from block to block: the pooled whole-input amplitude is far closer than
    # one block's scatter allows
    assert abs(r.tones[0] - 733.3) < 0.002
    assert np.isfinite(r.amplitude_overall[0, len(r.harmonics)])
    rng2 = np.random.default_rng(40)
    noise2 = 0.5 * rng2.standard_normal(len(t))
    one_block = [denoise(hum[:8 * sr] + steady[:8 * sr] + noise2[i * 8 * sr: (i + 1) * 8 * sr], sr,
                         tones=[733.3], block_s=8.0, harmonics=3).amplitudes[:, 0, -1].max() for i in range(6)]
    scatter = np.std(np.array(one_block) / 0.02 - 1)
    assert abs(r.line_amplitude(name)[0] / 0.02 - 1) < 0.5 * scatter, (r.line_amplitude(name), scatter)
    # a tone that jumps in level half-way through is not smoothed over: it is removed on both sides
    step = np.where(t < 40, 0.02, 0.2) * np.cos(2 * np.pi * 733.3 * t + 0.4)
    r2 = denoise(hum + step + noise, sr, tones=[733.3], block_s=8.0)
    assert np.isnan(r2.amplitude_overall[0, len(r2.harmonics)])
    sel = (t > 48) & (t < 72)
    resid = r2.y[sel] - noise[sel]
    cs = np.stack([np.cos(2 * np.pi * 733.3 * t[sel]), np.sin(2 * np.pi * 733.3 * t[sel])], axis=1)
    left = np.hypot(*np.linalg.lstsq(cs, resid, rcond=None)[0])
    assert left < 0.02 * 0.2, left


def test_lock_test_records_gap_harmonics_and_keeps_absent_ones_out():
    rng = np.random.default_rng(6)
    sr = 4000
    t = np.arange(40 * sr) / sr
    # harmonics 1, 2, 3 and 5 present, 4 absent
    y = _hum(t, amps=(1.0, 0.5, 0.3, 0.0, 0.3)) + 0.3 * rng.standard_normal(len(t))
    r = denoise(y, sr)
    assert {1, 2, 3, 5} <= set(r.harmonics) and 4 not in r.harmonics
    looks = {c["harmonic"]: c for c in r.candidates if c.get("look") == "phase lock"}
    assert looks[5]["significant"] and looks[5]["lock_index"] > 0.9
    assert not looks[4]["significant"] and looks[4]["lock_index"] < 0.7


def _one_channel_hum(hum_amp, seed=5, sr=8000, dur=10.0):
    """Stereo noise and a 440 Hz tone on both channels; a weak 50 Hz hum on channel 1 only."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(dur * sr)) / sr
    content = 0.05 * rng.standard_normal((t.size, 2)) + 0.1 * np.sin(2 * np.pi * 440 * t)[:, None]
    hum = np.zeros_like(content)
    hum[:, 1] = hum_amp * np.sin(2 * np.pi * 50 * t)
    return content, hum, sr, t


def test_weak_hum_on_one_channel_of_a_stereo_input_is_removed_as_on_that_channel_alone():
    from odnn_sep.audio import denoise

    content, hum, sr, t = _one_channel_hum(0.003)
    r = denoise(content + hum, sr)
    line = lambda a: 2 * abs(np.mean(a * np.exp(-2j * np.pi * 50 * t)))  # noqa: E731
    # the channels pooled halve its level and blur its track: it was left whole
    assert r.harmonics == [1], r.harmonics
    assert line(r.y[:, 1] - content[:, 1]) < 0.1 * line(hum[:, 1])
    # the channel without hum keeps its content (its fitted hum is the noise at the line: -47 dB)
    assert np.sqrt(np.mean((r.y[:, 0] - content[:, 0]) ** 2)) < 1e-2 * np.std(content[:, 0])


def test_stereo_content_without_hum_finds_no_channel_comb():
    from odnn_sep.audio import denoise

    content, _, sr, _ = _one_channel_hum(0.0)
    assert denoise(content, sr).harmonics == []
