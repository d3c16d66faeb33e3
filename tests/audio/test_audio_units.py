"""The same hum in other units (arrays scaled by 1e20 or 1e-30): the same lines removed, the
output in the input's units, no NumPy warnings (api.unit_exponent)."""
import warnings

import numpy as np
import pytest

from odnn_sep.audio import denoise
from odnn_sep.audio.synth import make_hum_demo


@pytest.mark.parametrize("scale", [2.0 ** 70, 2.0 ** -100])
def test_far_from_unit_samples_give_the_same_removal(scale):
    y, sr, _ = make_hum_demo(duration_s=4.0, sr=8000)
    ref = denoise(y, sr)
    with warnings.catch_warnings():
        warnings.simplefilter("error")     # before: 500 overflow and 0/0 warnings at 2^70
        r = denoise(y * scale, sr)
    # before: "no mains hum found" at both scales, the output equal to the input
    assert r.harmonics == ref.harmonics
    assert np.allclose(r.y / scale, ref.y, rtol=0, atol=1e-9)
    assert np.allclose(r.line_amplitude("h1") / scale, ref.line_amplitude("h1"), rtol=1e-9)


def test_float32_samples_come_back_float32():
    y, sr, _ = make_hum_demo(duration_s=4.0, sr=8000)
    r = denoise(y.astype(np.float32), sr)
    # before: float64 (the channels-first EEG/MEG call of the same function kept float32)
    assert r.y.dtype == np.float32 and r.hum.dtype == np.float32
    assert np.allclose(r.y, denoise(y.astype(np.float32).astype(np.float64), sr).y, atol=1e-6)
    x = np.stack([y, 0.5 * y]).astype(np.float32)
    assert denoise(x, sfreq=8000.0).dtype == np.float32
