"""Hum clipped by the recorder: the result says the input is clipped (the flat tops cannot be
removed), and a take that only touches full scale says nothing (inputclip.py)."""
import json
import logging

import numpy as np
import soundfile as sf

from odnn_sep.audio import denoise
from odnn_sep.audio.synth import make_hum_mix
from odnn_sep.cli import main

SR = 8000


def _loud_hum(gain):
    _, _, truth = make_hum_mix(10.0, SR, snr_db=0.0, random_state=3)
    return 0.1 * truth["host"] + gain * truth["hum"]


def test_clipped_hum_is_reported(tmp_path, caplog):
    y = np.clip(_loud_hum(5.0), -1, 1)                 # an eighth of the samples at full scale
    sf.write(tmp_path / "in.wav", y, SR, subtype="PCM_16")
    with caplog.at_level(logging.WARNING, logger="odnn_sep.audio"):
        assert main(["denoise", str(tmp_path / "in.wav"), "-o", str(tmp_path / "out.wav"),
                     "--report", str(tmp_path / "r.json")]) == 0
    # before: "removed hum" and nothing else, its error 13.6 dB over the music (-30.3 dB unclipped)
    assert any("the input is clipped" in rec.getMessage() for rec in caplog.records)
    assert 0.1 < json.loads((tmp_path / "r.json").read_text())["input_clipped"] < 0.4


def test_a_take_that_touches_full_scale_is_not_called_clipped(tmp_path):
    y = _loud_hum(2.0)
    y = y / np.abs(y).max()                            # its peak at full scale, once
    assert "input_clipped" not in denoise(y, SR).info
    sf.write(tmp_path / "in.wav", y * (1 - 2 ** -15), SR, subtype="PCM_16")
    assert main(["denoise", str(tmp_path / "in.wav"), "-o", str(tmp_path / "out.wav"),
                 "--report", str(tmp_path / "r.json"), "--quiet"]) == 0
    assert "input_clipped" not in json.loads((tmp_path / "r.json").read_text())


def test_a_float_file_beyond_full_scale_is_not_called_clipped(tmp_path):
    y = 4 * _loud_hum(2.0) / np.abs(_loud_hum(2.0)).max()     # a float file may hold values over 1
    sf.write(tmp_path / "in.wav", y, SR, subtype="FLOAT")
    assert main(["denoise", str(tmp_path / "in.wav"), "-o", str(tmp_path / "out.wav"),
                 "--report", str(tmp_path / "r.json"), "--quiet"]) == 0
    assert "input_clipped" not in json.loads((tmp_path / "r.json").read_text())
