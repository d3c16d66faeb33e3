"""Content power right beside a line (nearpower.py) and what it is for: a weak hum harmonic under
a loud note partial 0.8 Hz away (F4 = 349.2 Hz beside 350 Hz), read in the rests between notes."""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import denoise
from odnn_sep.audio.amplitude import local_power
from odnn_sep.audio.nearpower import near_power

SR = 4000


def _notes(n, f, rng, amp):
    """A repeated pitch ``f``: notes of 0.5-3 s (decaying) with rests of 0.5-2 s."""
    y = np.zeros(n)
    t0 = int(0.5 * SR)
    while t0 < n:
        i1 = min(n, t0 + int(rng.uniform(0.5, 3.0) * SR))
        tt = np.arange(i1 - t0) / SR
        env = np.minimum(1.0, tt / 0.01) * np.exp(-tt / 3.0) * np.clip((tt[-1] - tt) / 0.05, 0, 1)
        y[t0:i1] += amp * env * np.sin(2 * np.pi * f * tt + rng.uniform(0, 2 * np.pi))
        t0 = i1 + int(rng.uniform(0.5, 2.0) * SR)
    return y


def test_near_power_sees_a_partial_the_offset_band_misses():
    rng = np.random.default_rng(0)
    J = 3000
    t = np.arange(J) / 100.0
    u = 2.0 + rng.standard_normal(J) + 1j * rng.standard_normal(J)
    note = (t > 10) & (t < 14)
    u[note] += 20.0 * np.exp(2j * np.pi * 0.8 * t[note])        # 0.8 Hz from the line
    p_near = near_power(u, 100.0)
    p_off = local_power(u, 100.0)[0]
    inside = slice(1100, 1300)
    assert p_near[inside].min() > 30 * np.median(p_near)
    # the 1.5-6 Hz band takes the partial for part of the line: it sees much less of it
    assert np.median(p_off[inside]) < 0.3 * np.median(p_near[inside]) * np.median(p_off) / np.median(p_near)
    # away from the note: the noise power (2 per chunk), within a factor of 2
    assert 1.0 < np.median(p_near[:900]) < 4.0


def _case(seed, with_h7):
    rng = np.random.default_rng(seed)
    n = 32 * SR
    t = np.arange(n) / SR
    amps = {1: 0.05, 2: 0.3, 3: 0.15, 4: 0.08}
    if with_h7:
        amps[7] = 0.3 * 10 ** (-26 / 20)                         # -26 dB under the strongest
    hum = sum(a * np.cos(2 * np.pi * k * 50.0 * t + k) for k, a in amps.items())
    host = 0.003 * rng.standard_normal(n) + _notes(n, 349.23, rng, 0.5)
    return host, hum


def _band_energy(x, f0, half=0.3):
    f = np.fft.rfftfreq(len(x), 1 / SR)
    return float((np.abs(np.fft.rfft(x)) ** 2)[np.abs(f - f0) < half].sum())


def test_weak_harmonic_beside_loud_note_partial_removed_partial_kept():
    host, hum = _case(1, with_h7=True)
    r = denoise(host + hum, SR)
    assert r.harmonics == [1, 2, 3, 4, 7]
    gain = 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2))
    assert gain > 40.0                                           # 27 dB with harmonic 7 left in
    assert _band_energy(r.y - host, 350.0) < 0.01 * _band_energy(hum, 350.0)
    assert 0.98 < _band_energy(r.y - hum, 349.23) / _band_energy(host, 349.23) < 1.02


def test_note_partial_beside_absent_harmonic_is_left():
    host, hum = _case(1, with_h7=False)
    r = denoise(host + hum, SR)
    assert r.harmonics == [1, 2, 3, 4] and not r.tones and not r.extra_combs
    assert 0.98 < _band_energy(r.y - hum, 349.23) / _band_energy(host, 349.23) < 1.02
