"""Weak lines in the locked comb's own pattern (combpattern.py): a dimmer-like hum of odd
harmonics falling as 1/k under a host with pauses."""
import numpy as np

from odnn_sep.audio import combpattern, denoise


def _odd_hum(sr=8000, dur=20.0, seed=3):
    t = np.arange(int(sr * dur)) / sr
    rng = np.random.default_rng(seed)
    ph = 2 * np.pi * 50.02 * t + 0.3
    hum = sum(np.cos(k * ph + 0.1 * k) / k for k in range(1, 72, 2))     # up to 0.45 sr
    gate = (np.sin(2 * np.pi * 2.3 * t) > -0.3).astype(float)          # bursts and pauses
    host = 0.1 * rng.standard_normal(t.size) * gate
    return host, 0.1 * hum, sr


def _run(host, hum, sr):
    r = denoise(host + hum, sr)
    return r.harmonics, 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2))


def test_pattern_lines_are_added_and_only_in_the_pattern(monkeypatch):
    host, hum, sr = _odd_hum()
    ks, gain = _run(host, hum, sr)
    monkeypatch.setattr(combpattern, "pattern_lines", lambda *a, **k: [])
    ks0, gain0 = _run(host, hum, sr)
    added = sorted(set(ks) - set(ks0))
    assert set(ks0) <= set(ks)
    assert len(added) >= 4 and all(k % 2 == 1 for k in ks)           # no even line: not in the hum
    assert gain > gain0 + 2.0


def test_no_pattern_from_few_lines():
    assert combpattern.pattern([2, 4, 6]) is None
    assert combpattern.pattern_lines([2, 4, 6], {8: (1e-9, 0.9, 1.0)}, {}, alpha=1e-3, floor_rel=3e-3) == []
