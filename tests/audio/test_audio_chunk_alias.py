"""A steady hum at exactly 50.000 Hz tracked from a fundamental the spectrum placed 0.09 Hz off.

The 10 ms chunk sums are read at 100 Hz, twice 50 Hz: a strong line leaks into the chunk sums of
every harmonic of the same parity and, once the track has turned it, sits there as a steady
(locked) line. Demodulated at the spectrum's 49.91 Hz, the leak of a strong fundamental passed the
lock test at the odd harmonics 9-75 of a hum that has only harmonics 1-5 (and the denoiser then
removed 34 lines of the content). A line added by a lock test must now stand above the leak the
comb's own lines put there (chunkalias.py).
"""
import numpy as np
import pytest

from odnn_sep.audio.detect import detect_hum, excerpt_spectrum
from odnn_sep.audio.io import ArraySource
from odnn_sep.audio.lockcomb import settle


def _hum(seed: int, sr: int = 8000, seconds: float = 30.0):
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * sr)) / sr
    hum = sum(np.cos(2 * np.pi * k * 50.0 * t + rng.uniform(0, 2 * np.pi)) / k for k in range(1, 6))
    return hum + 0.01 * rng.standard_normal(t.size), sr


@pytest.mark.parametrize("seed", [1, 3])
@pytest.mark.parametrize("f_spectrum", [49.91, 50.09])
def test_no_alias_lines_from_an_offset_reference(seed, f_spectrum):
    y, sr = _hum(seed)
    src = ArraySource(y, sr)
    spec = excerpt_spectrum(src, keep_segments_hz=sr / 2)
    det = detect_hum(spec, sr, mains=50.0, f0=f_spectrum)
    assert det.harmonics[:5] == [1, 2, 3, 4, 5]
    comb = settle(src, spec, det, [k for k in range(6, 41) if k not in det.harmonics], alpha=1e-3, n_tests=40)
    assert comb.harmonics == [1, 2, 3, 4, 5]

