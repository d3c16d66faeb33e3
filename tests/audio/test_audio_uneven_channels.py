"""Channels of very uneven levels: one electrode that saturated does not hide the others' hum.

The line tests pooled the channels by their plain sum, led by the channel with the most power. On
the real EEG file (8 channels, 50 Hz line), one channel pinned at a rail for 5 s of 60 raised its
floor so far that no hum was found in any channel (the output equalled the input, the line 12 dB
over its flanks on the worst channel). Channels whose broadband levels are ten times apart are now
each taken over their own level (``Spectrum.channel_weights``).
"""
from pathlib import Path

import numpy as np
import pytest
from scipy.signal import welch

from odnn_sep.audio import denoise
from odnn_sep.audio.spectrum import Spectrum

EEG = Path(__file__).resolve().parents[3] / "shared" / "data" / "meegkit_eeg_line_noise" / "eeg_raw.npy"


def _line_levels(y):
    f, p = welch(y, fs=250, nperseg=2000, axis=-1)
    d = np.abs(f - 50.0)
    return 10 * np.log10(p[:, d <= 0.5].mean(1) / np.median(p[:, (d >= 2) & (d <= 5)], axis=1))


def test_saturated_electrode_does_not_hide_the_line():
    if not EEG.exists():
        pytest.skip(f"{EEG} is absent")
    x = np.load(EEG)
    x[5, 5000:6250] = 300.0                  # channel 5 at the rail for 5 s
    r = denoise(x.T, 250)
    assert 1 in r.harmonics
    assert _line_levels(r.y.T).max() < 3.0


def test_channels_of_one_level_pool_by_their_sum():
    psd = np.ones((40, 2))
    psd[:, 1] = 3.0
    assert Spectrum(np.arange(40) * 0.5, psd, 4, 10.0).channel_weights is None
    psd[:, 1] = 300.0
    w = Spectrum(np.arange(40) * 0.5, psd, 4, 10.0).channel_weights
    assert w is not None and np.allclose(w * psd[0], 1.0)


def test_flat_electrode_without_numeric_warnings():
    # a disconnected electrode recorded as zeros: 0/0 in the lock test and infinite weights in the
    # amplitude estimate printed five NumPy warnings; the channel stays zero and the others are cleaned
    import warnings

    if not EEG.exists():
        pytest.skip(f"{EEG} is absent")
    x = np.load(EEG)
    x[3] = 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        r = denoise(x.T, 250)
    assert not r.y[:, 3].any()
    levels = _line_levels(np.delete(r.y.T, 3, axis=0))
    assert levels.max() < 3.0
