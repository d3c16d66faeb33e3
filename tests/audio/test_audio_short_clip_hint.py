"""A clip under 1 s in which nothing locks says that the lock tests cannot decide at that length and
how to name the lines; with the lines named, its hum is removed."""
import logging

import numpy as np

from odnn_sep.audio import denoise


def _clip(seconds=0.4, sr=16000):
    t = np.arange(int(seconds * sr)) / sr
    hum = sum(a * np.sin(2 * np.pi * (k + 1) * 60.0 * t + k) for k, a in enumerate((0.1, 0.05, 0.03)))
    host = 0.3 * np.std(hum) * np.random.default_rng(0).standard_normal(t.size)
    return host, hum, sr


def test_a_short_clip_without_locked_lines_says_how_to_name_them(caplog):
    host, hum, sr = _clip()
    with caplog.at_level(logging.WARNING, logger="odnn_sep.audio.pipeline"):
        r = denoise(host + hum, sr)
    assert r.harmonics == []     # 0.4 s: the lock tests cannot decide (this test's premise)
    msg = " ".join(rec.getMessage() for rec in caplog.records)
    assert "no mains hum found" in msg and "0.40 s long" in msg and "--harmonics" in msg


def test_a_short_clip_with_its_lines_named_is_cleaned():
    host, hum, sr = _clip()
    r = denoise(host + hum, sr, mains=60, harmonics=[1, 2, 3])
    assert r.harmonics == [1, 2, 3]
    assert 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2)) > 20.0
