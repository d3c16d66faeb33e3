"""Weak hum harmonics under bursty content, a note partial beside a harmonic, and the amplitude
paths of steady lines (lock.weighted_lock_p_values, lockcomb._new_lines, steadypath.py)."""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import denoise
from odnn_sep.audio import steadypath as _steadypath

SR = 4000


def _bursty_host(n, rng):
    """White noise in 0.5-2 s bursts about half of the time, near silence between them."""
    y = 1e-4 * rng.standard_normal(n)
    t0 = 0
    while t0 < n:
        dur = int(rng.uniform(0.5, 2.0) * SR)
        if rng.random() < 0.5:
            y[t0: t0 + dur] += rng.standard_normal(min(dur, n - t0))
        t0 += dur
    return y


def _gated_partial(n, f, rng):
    """A partial at ``f`` Hz in notes of 0.3-2 s with rests between them (a repeated pitch)."""
    y = np.zeros(n)
    t0 = int(0.2 * SR)
    while t0 < n:
        dur = int(rng.uniform(0.3, 2.0) * SR)
        i1 = min(n, t0 + dur)
        tt = np.arange(i1 - t0) / SR
        env = np.minimum(1.0, tt / 0.01) * np.minimum(1.0, (tt[-1] - tt) / 0.05 + 1e-9)
        y[t0:i1] += 0.3 * env * np.sin(2 * np.pi * f * tt + rng.uniform(0, 2 * np.pi))
        t0 = i1 + int(rng.uniform(0.2, 1.0) * SR)
    return y


def _gain_db(host, hum, out):
    return 10 * np.log10(np.sum(hum ** 2) / np.sum((out - host) ** 2))


def test_weak_harmonic_under_bursts_removed_and_partial_left():
    rng = np.random.default_rng(3)
    n = 30 * SR
    t = np.arange(n) / SR
    ph = 50.02 * t + 0.01 * np.sin(2 * np.pi * t / 17)
    # harmonic 2 is 40 dB under the fundamental: invisible beside the bursts at equal weight
    hum = (0.3 * np.cos(2 * np.pi * ph) + 0.15 * np.cos(2 * np.pi * 3 * ph + 1)
           + 0.003 * np.cos(2 * np.pi * 2 * ph + 2))
    partial = _gated_partial(n, 201.0, rng)            # 1 Hz from harmonic 4, which the hum lacks
    host = 0.3 * _bursty_host(n, rng) + partial
    r = denoise(host + hum, SR)
    assert 2 in r.harmonics and 1 in r.harmonics and 3 in r.harmonics
    assert 4 not in r.harmonics and not r.tones and not r.extra_combs
    # the partial is left: the output keeps its energy within +-0.6 Hz of 201 Hz
    spec = lambda x: np.abs(np.fft.rfft(x)) ** 2                          # noqa: E731
    f = np.fft.rfftfreq(n, 1 / SR)
    band = np.abs(f - 201.0) < 0.6
    kept = spec(r.y - hum)[band].sum() / spec(host)[band].sum()
    assert 0.9 < kept < 1.1
    # harmonic 2's own band: what is left of it is well under the line
    b2 = np.abs(f - 100.04) < 0.3
    assert spec(r.y - host)[b2].sum() < 0.1 * spec(hum)[b2].sum()


def test_amplitude_path_of_weak_harmonic_beside_note_partial(monkeypatch):
    """A weak harmonic (-20 dB) 1.5 Hz from a loud, gated note partial: its amplitude path
    (steadypath.py, weighted means over the whole input) removes it far better than block fits,
    which take the partial's leakage; the partial stays."""
    rng = np.random.default_rng(7)
    n = 40 * SR
    t = np.arange(n) / SR
    hum = sum(a * np.cos(2 * np.pi * k * 50.01 * t + k) for k, a in ((1, 0.2), (2, 0.1), (3, 0.02)))
    host = 0.01 * rng.standard_normal(n) + _gated_partial(n, 151.53, rng)
    r = denoise(host + hum, SR)
    assert r.harmonics == [1, 2, 3]
    with_paths = _gain_db(host, hum, r.y)
    f = np.fft.rfftfreq(n, 1 / SR)
    spec = lambda x: np.abs(np.fft.rfft(x)) ** 2                          # noqa: E731
    band = np.abs(f - 151.53) < 0.4
    assert 0.9 < spec(r.y - hum)[band].sum() / spec(host)[band].sum() < 1.1
    monkeypatch.setattr(_steadypath, "comb_block_amplitudes", lambda *a, **k: None)
    without = _gain_db(host, hum, denoise(host + hum, SR).y)
    assert with_paths > 30.0
    assert with_paths > without + 6.0
