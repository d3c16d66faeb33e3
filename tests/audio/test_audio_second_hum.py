"""A take with a 50 Hz and a 60 Hz hum: one run removes the stronger one and says the other is
left, with the run that removes it (lockcomb._second_hum); one hum alone gives no such warning."""
import numpy as np

from odnn_sep.audio import denoise
from odnn_sep.audio.synth import make_hum_mix

SR = 8000


def _two_hums(weaker=0.3):
    _, _, a = make_hum_mix(16.0, SR, snr_db=0.0, random_state=3, mains_hz=50.0)
    _, _, b = make_hum_mix(16.0, SR, snr_db=0.0, random_state=103, mains_hz=60.0)
    return a["host"], a["hum"], weaker * b["hum"]


def _gain_db(hum, out, host):
    return 10 * np.log10(np.sum(hum ** 2) / np.sum((out - host) ** 2))


def test_a_weaker_60_hz_hum_beside_a_50_hz_hum_is_named_and_a_second_run_removes_it(caplog):
    host, hum50, hum60 = _two_hums()
    r = denoise(host + hum50 + hum60, SR)
    assert r.nominal_hz == 50.0
    # before: exit 0, the 60 Hz hum left without a word (11.6 dB of gain on both hums; 28.6 dB after the second run)
    second = r.info["second_hum"]
    assert abs(second["fundamental_hz"] - 60.0) < 0.1 and {1, 2, 3} <= set(second["harmonics"])
    assert any("--mains 60" in rec.getMessage() for rec in caplog.records)
    again = denoise(r.y, SR, mains=60)
    assert _gain_db(hum50 + hum60, again.y, host) > _gain_db(hum50 + hum60, r.y, host) + 15


def test_one_hum_alone_names_no_second_one():
    host, hum50, _ = _two_hums()
    assert "second_hum" not in denoise(host + hum50, SR).info
