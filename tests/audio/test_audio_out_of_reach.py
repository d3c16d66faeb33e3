"""A hum whose lines the detection cannot test at the input's rate (a line needs a few Hz under the
Nyquist frequency) or under --max-hz: a one-line error naming the limit and, where the hum folds to
a line that can be tested, the --mains that removes it; never "no hum found (tested 60 Hz)"."""
import logging

import numpy as np
import pytest
import soundfile as sf

from odnn_sep.audio import denoise
from odnn_sep.cli import main
from odnn_sep.errors import InputError


def _hummed(sr, f0=60.02, seconds=30.0):
    t = np.arange(int(seconds * sr)) / sr
    host = 0.1 * np.random.default_rng(0).standard_normal(t.size)
    return host, 0.1 * np.cos(2 * np.pi * f0 * t + 1.0)


def test_mains_above_the_highest_line_tested_is_an_error_and_writes_nothing(tmp_path, capsys):
    host, hum = _hummed(128)
    sf.write(tmp_path / "in.wav", host + hum, 128, subtype="FLOAT")
    # before: exit 0, "no mains hum found (tested 60 Hz ...)", the input written unchanged
    rc = main(["denoise", str(tmp_path / "in.wav"), "-o", str(tmp_path / "out.wav"), "--mains", "60"])
    err = capsys.readouterr().err
    assert rc != 0 and "no line of 60 Hz hum can be tested at sr=128" in err
    assert not (tmp_path / "out.wav").exists()


def test_a_rate_too_low_for_mains_names_where_the_hum_folds_to():
    host, hum = _hummed(96)
    with pytest.raises(InputError, match=r"60 Hz hum folds to 36 Hz here \(--mains 36"):
        denoise(host + hum, 96)
    r = denoise(host + hum, 96, mains=36)                # what the message says works
    assert 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2)) > 15


def test_max_hz_under_the_fundamentals_room_is_an_error():
    host, hum = _hummed(8000, f0=50.0, seconds=5.0)
    # before: "no mains hum found (tested 50 Hz ...)": a 50 Hz line is tested only under 52 Hz and more
    with pytest.raises(InputError, match="under max_hz=49.6 Hz.*raise max_hz"):
        denoise(host + hum, 8000, mains=50, max_hz=49.6)


def test_no_hum_found_names_the_family_out_of_reach(caplog):
    host, _ = _hummed(128)
    with caplog.at_level(logging.WARNING, logger="odnn_sep.audio"):
        denoise(host, 128)
    said = " ".join(rec.getMessage() for rec in caplog.records)
    assert "tested 50 Hz; 60 Hz lies above the highest line tested at sr=128" in said


def test_named_harmonics_above_the_highest_line_are_named_once(caplog):
    host, hum = _hummed(500, f0=50.0, seconds=10.0)
    x = np.stack([host + hum * g for g in (1.0, 0.8, 0.6, 0.4)])        # channels first, EEG-like
    with caplog.at_level(logging.WARNING, logger="odnn_sep.audio"):
        denoise(x, sfreq=500.0, harmonics=[1, 2, 30])
    said = [rec.getMessage() for rec in caplog.records if "harmonic(s) 30 of 50 Hz" in rec.getMessage()]
    # before: h30 (1500 Hz, over the 250 Hz Nyquist frequency) left out without a word
    assert len(said) == 1 and "left out" in said[0]
