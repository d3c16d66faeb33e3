"""Hum over part of the input only (humspans.py): found and removed where it sounds, the rest
written as read; a held note near the harmonics is not taken for it."""
import json

import numpy as np
import soundfile as sf

from odnn_sep.audio import denoise
from odnn_sep.cli import main

SR = 8000


def _pink(n, rng):
    S = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n, 1 / SR)
    S[1:] /= np.sqrt(f[1:])
    S[0] = 0
    y = np.fft.irfft(S, n)
    return y / np.std(y)


def _gated(on=(10.0, 16.0), dur=24.0, seed=0):
    """Hum loudest at its second harmonic (harmonics 1-4 of 50.02 Hz) switched on for 6 s of 24 s
    (10 ms ramps), over pink noise at about the hum's level."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(dur * SR)) / SR
    gate = np.clip((t - on[0]) / 0.01, 0, 1) * np.clip((on[1] - t) / 0.01, 0, 1)
    amps = {1: 0.1, 2: 1.0, 3: 0.4, 4: 0.3}
    hum = gate * sum(a * np.cos(2 * np.pi * 50.02 * k * t + k) for k, a in amps.items())
    host = _pink(t.size, rng) * np.std(hum[gate > 0.5])
    return 0.1 * host, 0.1 * hum


def test_hum_switched_on_for_part_of_the_take_is_removed_there_only():
    host, hum = _gated()
    r = denoise(host + hum, SR)
    spans = r.info["hum_spans"]
    assert len(spans) == 1 and r.harmonics == [1, 2, 3, 4]
    start, end = spans[0]["start_s"], spans[0]["end_s"]
    assert 9.95 <= start <= 10.05 and 15.95 <= end <= 16.05      # placed at the switches
    gain = 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2))
    assert gain > 24.0          # nothing was removed before (the whole input's tests: 0 dB)
    # outside the span the output is the input, sample for sample
    a, b = int(round(start * SR)), int(round(end * SR))
    assert np.array_equal(r.y[:a], (host + hum)[:a]) and np.array_equal(r.y[b:], (host + hum)[b:])


def test_a_held_note_near_the_harmonics_is_not_taken_for_a_span_of_hum():
    rng = np.random.default_rng(1)
    n = int(24 * SR)
    y = 0.05 * _pink(n, rng)
    t = np.arange(int(6 * SR)) / SR
    f4 = 440.0 * 2 ** (-4 / 12)                       # F4 = 349.2 Hz, 0.8 Hz from 7 x 50 Hz
    env = np.minimum(1, np.minimum(t, t[-1] - t) / 0.05)
    note = env * sum(np.cos(2 * np.pi * j * f4 * t + j) / j for j in range(1, 7))
    y[8 * SR: 8 * SR + t.size] += 0.3 * note
    r = denoise(y, SR)
    assert r.line_names == [] and r.info["hum_spans"] == []
    assert np.array_equal(r.y, y)


def test_the_command_line_says_where_the_hum_was(tmp_path, capsys):
    host, hum = _gated()
    src, out, rep = tmp_path / "in.wav", tmp_path / "out.wav", tmp_path / "r.json"
    sf.write(src, host + hum, SR, subtype="FLOAT")
    assert main(["denoise", str(src), "-o", str(out), "--report", str(rep)]) == 0
    said = capsys.readouterr().out
    assert "the hum sounds over" in said and "only: removed there, the rest written as read" in said
    spans = json.loads(rep.read_text())["hum_spans"]
    assert len(spans) == 1 and spans[0]["harmonics"]


def test_a_lone_hum_line_switched_on_for_part_of_the_take_is_fitted_where_it_sounds():
    # one line (no harmonics): the shared level that follows a switch needs two lines, so the
    # line was fitted with one level per block across its switches (6-8 dB)
    rng = np.random.default_rng(2)
    t = np.arange(int(26 * SR)) / SR
    gate = np.clip((t - 7.0) / 0.01, 0, 1) * np.clip((21.5 - t) / 0.01, 0, 1)
    hum = 0.1 * gate * np.cos(2 * np.pi * 60.01 * t + 0.3)
    host = np.std(hum[gate > 0.5]) * rng.standard_normal(t.size)          # white, at the line's level
    r = denoise(host + hum, SR)
    assert r.harmonics == [1] and len(r.info["hum_spans"]) == 1
    start, end = r.info["hum_spans"][0]["start_s"], r.info["hum_spans"][0]["end_s"]
    assert 6.95 <= start <= 7.05 and 21.45 <= end <= 21.55
    assert 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2)) > 20.0


def test_hum_running_to_the_end_of_the_take_is_removed_to_the_end():
    # the last 4 s segment of the detection spectrum stops short of the input's end: a span that
    # reaches it runs to the end (13 dB before: the last half second kept its hum)
    host, hum = _gated(on=(15.0, 30.0), dur=25.0, seed=3)
    r = denoise(host + hum, SR)
    assert r.info["hum_spans"] and r.info["hum_spans"][-1]["end_s"] == 25.0
    assert 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - host) ** 2)) > 25.0
