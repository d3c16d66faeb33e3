"""A drum loop placed to the sample has a line at every multiple of 1/P (P its period), so at every
multiple of 50 Hz: a "further comb" at exactly 50.000 Hz, steady and locked, beside the real hum. Its
lines hold the loop's neighbouring lines as sidebands of their baseband, a hum comb's lines do not
(``combs._off_host_grid``)."""
import sys
from pathlib import Path

import numpy as np
import pytest

from odnn_sep.audio import denoise

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "recipes"))
from _audio_hosts import drum_loop  # noqa: E402  (the hosts generator's loop, with a given step)


def _loop_and_hum(seed, sr=16000, seconds=20.0):
    n = int(seconds * sr)
    x = 0.3 * drum_loop(n, sr, np.random.default_rng(seed), 0.5)      # a 4 s pattern: lines every 0.25 Hz
    t = np.arange(n) / sr
    phase = 2 * np.pi * np.cumsum(50.0 + 0.004 * (t - seconds / 2)) / sr   # a ramp of 4 mHz/s through 50 Hz
    hum = sum(np.cos(k * phase + k) / k for k in range(1, 25))
    return x, 0.3 * hum / np.std(hum), sr


@pytest.mark.parametrize("seed", [4, 5])
def test_a_loops_lines_are_not_a_further_comb(seed):
    # the version before removed 8-10 of the loop's lines (harmonics 25-40 of 50.000 Hz) as a second
    # hum comb, and the hum came out 29.5 and 28.7 dB down instead of 37-38 dB
    x, hum, sr = _loop_and_hum(seed)
    r = denoise(x + hum, sr)
    assert r.extra_combs == []
    assert r.harmonics == list(range(1, 25))
    assert 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - x) ** 2)) > 35.0
