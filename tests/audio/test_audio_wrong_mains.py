"""--mains 60 given for a 50 Hz hum (or the reverse): the warning says the input holds a hum of
the other family and how to remove it (pipeline._other_family_hint)."""
import logging

import pytest

from odnn_sep.audio import denoise
from odnn_sep.audio.synth import make_hum_mix

SR = 8000


def _said(caplog, y, **kw):
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="odnn_sep.audio"):
        r = denoise(y, SR, **kw)
    return r, " ".join(rec.getMessage() for rec in caplog.records)


@pytest.mark.parametrize("true_hz, given_hz", [(50.0, 60), (60.0, 50)])
def test_the_other_mains_family_is_named(caplog, true_hz, given_hz):
    y, _, _ = make_hum_mix(16.0, SR, snr_db=0.0, random_state=3, mains_hz=true_hz)
    r, said = _said(caplog, y, mains=given_hz)
    # before: "removed hum: fundamental 59.99 Hz, lines h5" (the 300 Hz line of the 50 Hz hum,
    # 0.0 dB of it removed), or "no mains hum found (tested 50 Hz)", and nothing more
    assert f"run again with --mains {true_hz:g}" in said
    assert all(abs(k * r.mains_hz / true_hz - round(k * r.mains_hz / true_hz)) < 0.01 for k in r.harmonics)


def test_music_without_hum_gets_no_such_hint(caplog):
    _, _, truth = make_hum_mix(16.0, SR, snr_db=0.0, random_state=3)
    _, said = _said(caplog, truth["host"], mains=60)
    assert "run again" not in said
