"""When nothing locks at the spectrum's fundamental, the family is tried once more from the
fundamental its first harmonics place (lockcomb._low_harmonics_retry)."""
import numpy as np

from odnn_sep.audio import lockcomb
from odnn_sep.audio.detect import detect_hum, excerpt_spectrum
from odnn_sep.audio.io import ArraySource


def _source(with_hum: bool):
    sr = 4000
    t = np.arange(30 * sr) / sr
    rng = np.random.default_rng(0)
    y = 0.3 * rng.standard_normal(t.size)
    if with_hum:
        y += 0.3 * sum(np.cos(2 * np.pi * k * 60.0 * t + k) / k for k in range(1, 6))
    return ArraySource(y, sr)


def test_the_first_harmonics_place_a_fundamental_pulled_off_the_hum():
    src = _source(True)
    spec = excerpt_spectrum(src, keep_segments_hz=1000)
    det = detect_hum(spec, src.sr)
    det.mains_hz = 59.93                     # as held notes high up can pull the spectrum's estimate
    comb = lockcomb._low_harmonics_retry(src, spec, det, alpha=1e-3, max_hz=None, n_first=len(det.candidates))
    assert comb is not None and comb.harmonics[:3] == [1, 2, 3]
    assert abs(comb.f_ref - 60.0) < 0.01


def test_no_retry_without_low_harmonics():
    src = _source(True)
    spec = excerpt_spectrum(src, keep_segments_hz=1000)
    det = detect_hum(spec, src.sr)
    det.harmonics = [k for k in det.harmonics if k > lockcomb.LOWEST_K]
    assert lockcomb._low_harmonics_retry(src, spec, det, alpha=1e-3, max_hz=None, n_first=10) is None
