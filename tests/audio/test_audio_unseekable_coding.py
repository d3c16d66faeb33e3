"""A file in a coding libsndfile cannot seek in (GSM 6.10 in WAV, telephone audio) is read whole.

Every pass reads the input again from a frame it names; such a file failed with "Seek attempted on
unseekable file type ... (the file may be truncated or corrupt)". It is now decoded once at the
opening (up to ``MAX_UNSEEKABLE_SAMPLES``), and the output, re-encoded in the same lossy coding,
says so.
"""
import numpy as np
import pytest
import soundfile as sf

from odnn_sep.audio import denoise_file, io
from odnn_sep.errors import FormatError


@pytest.fixture
def gsm_file(tmp_path):
    if "GSM610" not in sf.available_subtypes("WAV"):
        pytest.skip("this libsndfile has no GSM 6.10")
    sr = 8000
    t = np.arange(8 * sr) / sr
    x = 0.05 * np.random.default_rng(0).normal(size=t.size) + 0.2 * np.cos(2 * np.pi * 50 * t)
    path = tmp_path / "call.wav"
    sf.write(path, x, sr, subtype="GSM610")
    with sf.SoundFile(path) as f:
        if f.seekable():
            pytest.skip("this libsndfile seeks in GSM 6.10")
    return path


def test_gsm_input_is_cleaned(gsm_file, tmp_path):
    res = denoise_file(gsm_file, tmp_path / "out.wav")
    assert res.harmonics[:1] == [1] and abs(res.mains_hz - 50) < 0.05
    assert sf.info(tmp_path / "out.wav").subtype == "GSM610"
    assert "lossy coding" in res.info["lossy_output"]
    x, sr = sf.read(gsm_file)
    spec = lambda v: np.abs(np.fft.rfft(v))[400]   # noqa: E731 - the 50 Hz bin of 8 s
    assert spec(sf.read(tmp_path / "out.wav")[0]) < 0.2 * spec(x)


def test_too_long_to_read_whole_is_refused(gsm_file, tmp_path, monkeypatch):
    monkeypatch.setattr(io, "MAX_UNSEEKABLE_SAMPLES", 1000)
    with pytest.raises(FormatError, match="cannot be read in blocks"):
        denoise_file(gsm_file, tmp_path / "out.wav")
    assert not (tmp_path / "out.wav").exists()
