"""A steady content line half a resolution cell from a hum line (a drum loop's line at exactly
60.000 Hz under a 60.045 Hz hum) is fitted with the hum and kept, not taken for hum."""
import numpy as np

from odnn_sep.audio import denoise

SR = 8000


def _case(seconds=10.5, rng=0, host_share=0.2):
    t = np.arange(int(seconds * SR)) / SR
    r = np.random.default_rng(rng)
    f0 = 60.045
    hum = sum(0.1 / k * np.cos(2 * np.pi * k * f0 * t + r.uniform(0, 2 * np.pi)) for k in (1, 2, 3, 4))
    # the content: lines at exactly 60 and 120 Hz (a loop's, to the sample) over noise
    lines = sum(host_share * 0.1 / k * np.cos(2 * np.pi * k * 60.0 * t + r.uniform(0, 2 * np.pi)) for k in (1, 2))
    return lines + 0.003 * r.standard_normal(t.size), hum, lines


def _gain(host, hum, y):
    return 10 * np.log10(np.sum(hum ** 2) / np.sum((y - host) ** 2))


def test_line_under_hum_is_kept():
    for rng in (0, 1):
        host, hum, _ = _case(rng=rng)
        r = denoise(host + hum, SR)
        assert r.harmonics[:4] == [1, 2, 3, 4]
        # the lines taken into the hum's fit instead: 15.5 and 15.7 dB
        assert _gain(host, hum, r.y) > 25.0


def test_no_line_no_change():
    # without content lines nothing is found and the output is the plain fit's
    host, hum, _ = _case(host_share=0.0)
    r = denoise(host + hum, SR)
    assert _gain(host, hum, r.y) > 30.0


def test_lines_found_and_put_back():
    from odnn_sep.audio import hostlines
    from odnn_sep.audio.io import ArraySource
    from odnn_sep.audio.track import demodulate

    host, hum, lines = _case(rng=2)
    D = demodulate(ArraySource(host + hum, SR), 60.0, [1, 2])
    psi = 0.045 * (np.arange(len(D)) * 80 + 39.5) / SR
    found = hostlines.find(D, SR, 60.0, [1, 2], psi, 0.5)
    assert sorted(round(h.freq_hz, 2) for h in found) == [60.0, 120.0]
    # the input read without them: what is left of the content lines is under 5 % of them
    w = hostlines.WithoutLines(ArraySource(host + hum, SR), found)
    left = w.read(0, len(host))[:, 0] - hum - (host - lines)
    assert np.std(left) < 0.05 * np.std(lines)
