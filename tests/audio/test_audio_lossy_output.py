"""A lossy output (OGG/Vorbis) is written at the coder's highest quality and says what it costs.

At the library's default quality the re-encoding's error (0.010 RMS on this kind of input) was four
times the hum a good removal leaves, with no word about it.
"""
import numpy as np
import pytest
import soundfile as sf

from odnn_sep.audio import denoise, denoise_file
from odnn_sep.audio.io import lossy_write_options


def test_ogg_written_at_highest_quality_with_a_warning(tmp_path):
    if not lossy_write_options("VORBIS"):
        pytest.skip("this soundfile cannot set the Vorbis quality (compression_level)")
    sr = 44100
    t = np.arange(6 * sr) / sr
    x = 0.05 * np.random.default_rng(0).normal(size=t.size) + 0.05 * np.sin(2 * np.pi * 60.02 * t)
    src = tmp_path / "in.ogg"
    sf.write(src, x, sr, subtype="VORBIS")
    res = denoise_file(src, tmp_path / "out.ogg")
    assert "lossy" in res.info["lossy_output"]
    decoded, _ = sf.read(src)
    written, _ = sf.read(tmp_path / "out.ogg")
    exact = denoise(decoded, sr).y
    assert np.sqrt(np.mean((written - exact) ** 2)) < 0.004
    assert "lossy_output" not in denoise_file(src, tmp_path / "out.wav").info
