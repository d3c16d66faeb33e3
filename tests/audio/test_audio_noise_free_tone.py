"""A synthetic hum with nothing beside it (no noise at all): removed, with no numeric warnings.

The lock test's and the near-line power's single-precision divisions met exact zeros there and
printed divide-by-zero and overflow warnings to the user (the removal itself was right).
"""
import warnings

import numpy as np
import pytest

from odnn_sep.audio import denoise


@pytest.mark.parametrize("channels", [1, 2])
def test_pure_tone_removed_without_warnings(channels):
    sr = 8000
    t = np.arange(12 * sr) / sr
    x = 0.3 * np.sin(2 * np.pi * 50 * t) + 0.05 * np.sin(2 * np.pi * 150 * t + 1.0)
    if channels == 2:
        x = np.stack([x, x], axis=1)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        r = denoise(x, sr)
    assert np.sqrt(np.mean(r.y ** 2)) < 1e-4 * np.sqrt(np.mean(x ** 2))
