"""Hum with strong harmonics far up (a phase-cut dimmer's current) is followed past the 40th."""
import numpy as np

from odnn_sep.audio import denoise


def _dimmer(sr=8000, dur=20.0, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(int(dur * sr)) / sr
    ph = 2 * np.pi * 50.02 * t
    hum = np.where(np.mod(ph, np.pi) > 1.7, np.sin(ph), 0.0)          # cut for part of each half cycle
    S = np.fft.rfft(hum)
    S[np.fft.rfftfreq(t.size, 1 / sr) > 0.45 * sr] = 0                 # band-limited, as recorded
    hum = 0.5 * np.fft.irfft(S, t.size)
    return 0.05 * rng.standard_normal(t.size), hum, sr


def _removed(host, hum, sr):
    r = denoise(host + hum, sr)
    ks = [int(n[1:]) for n in r.line_names if n.startswith("h")]
    return max(ks), 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2))


def test_dimmer_hum_is_removed_past_the_40th_harmonic(monkeypatch):
    from odnn_sep.audio import lockcomb

    host, hum, sr = _dimmer()
    top, gain = _removed(host, hum, sr)
    monkeypatch.setattr(lockcomb, "HIGH_REACH", 0)          # never extended: the first 40 only
    top40, gain40 = _removed(host, hum, sr)
    # the harmonics up to 75 (0.95 x Nyquist) carry a few dB of such hum past the 40th
    assert top40 <= 40 < 60 < top and gain > gain40 + 2.5, (top, gain, top40, gain40)


def test_a_decaying_comb_is_not_extended():
    rng = np.random.default_rng(1)
    sr = 8000
    t = np.arange(10 * sr) / sr
    hum = sum(np.cos(2 * np.pi * 60.01 * k * t + k) / k ** 2 for k in range(1, 9))
    r = denoise(0.05 * rng.standard_normal(t.size) + 0.3 * hum, sr)
    assert max(int(n[1:]) for n in r.line_names if n.startswith("h")) <= 40
