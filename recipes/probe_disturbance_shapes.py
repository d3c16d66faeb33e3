"""Disturbances whose shape no generator of the project draws: what ``mismatch`` and ``denoise`` say.

The populations draw a mismatch record's periodic pickup as one sinusoid, and a hum's level and
baseline as steady or smoothly changing. Users bring other shapes. Each row is one record and what
the tool answered; run it with another version on ``PYTHONPATH`` to compare.

- mismatch, null records (nothing missing from the model) under a square-wave, sawtooth, amplitude-
  modulated or two-line pickup, a chirp, a step of the sensor's level, a drift plus a line, a burst;
  on an oscillator, a cooling curve (HVAC cycles) and a pendulum (a line with its harmonic); then
  four of these shapes over records that do miss an effect (cubic stiffness, radiation, large angle);
- denoise: 50 Hz hum over a pink-noise and note host with a DC offset, a splice (phase jump), a step
  of the mains frequency, a clipped 60 Hz sine, amplitude modulation at 0.05-2 Hz (the gain is the
  hum's power over the power of what the output has wrong);
- the real EEG file of ``../shared/data/meegkit_eeg_line_noise`` with DC-coupled amplifier offsets,
  a slow drift, or one channel at a rail for 5 s (before cleaning: 50 Hz line 5.1 dB over its flanks, median channel; 12.3 worst).

    python recipes/probe_disturbance_shapes.py              # both tables (about 5 minutes)
    python recipes/probe_disturbance_shapes.py --audio-only
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))


def mismatch_rows():
    from probe_user_inputs import _mismatch
    from scipy.signal import chirp, sawtooth, square

    from odnn_sep.mismatch import make_model

    rng = np.random.default_rng(42)
    rows = []
    t = np.linspace(0, 20, 400)
    osc = make_model("oscillator", {"k": 4.0, "c": 0.1, "x0": 1.0}).predict(t) + 0.01 * rng.normal(size=t.size)
    for label, d in (("square wave 3.7 Hz, 0.05", 0.05 * square(2 * np.pi * 3.7 * t + 1)),
                     ("sawtooth 2.3 Hz, 0.04", 0.04 * sawtooth(2 * np.pi * 2.3 * t + 1)),
                     ("3.7 Hz line, amplitude modulated at 0.1 Hz",
                      0.05 * (1 + 0.5 * np.sin(2 * np.pi * 0.1 * t)) * np.cos(2 * np.pi * 3.7 * t)),
                     ("two lines, 2.9 and 4.4 Hz", 0.04 * np.cos(2 * np.pi * 2.9 * t) + 0.03 * np.cos(2 * np.pi * 4.4 * t + 2)),
                     ("chirp 2-5 Hz", 0.04 * chirp(t, 2, 20, 5)),
                     ("step of the level at 12 s, 0.05", 0.05 * (t > 12)),
                     ("drift plus a 3.1 Hz line", 0.003 * t + 0.04 * np.cos(2 * np.pi * 3.1 * t)),
                     ("3.7 Hz burst, 8-9 s", 0.1 * ((t > 8) & (t < 9)) * np.cos(2 * np.pi * 3.7 * t))):
        rows.append(("oscillator (0.32 Hz), nothing missing", label, _mismatch("oscillator", t, osc + d)))
    tc = np.linspace(0, 1800, 360)
    cool = make_model("cooling", {"h": 0.002}).predict(tc) + 0.05 * rng.normal(size=tc.size)
    for label, d in (("HVAC square wave, 120 s, 0.2 K", 0.2 * square(2 * np.pi * tc / 120)),
                     ("HVAC sawtooth, 300 s, 0.2 K", 0.2 * sawtooth(2 * np.pi * tc / 300)),
                     ("sensor step 0.3 K at 900 s", 0.3 * (tc > 900))):
        rows.append(("cooling, nothing missing", label, _mismatch("cooling", tc, cool + d)))
    tp = np.linspace(0, 20, 1000)
    pend = make_model("pendulum", {"w2": 9.0, "c": 0.05, "theta0": 0.2}).predict(tp) + 0.002 * rng.normal(size=tp.size)
    for label, d in (("6 Hz line with its 12 Hz harmonic",
                      0.01 * np.cos(2 * np.pi * 6 * tp) + 0.005 * np.cos(2 * np.pi * 12 * tp + 1)),
                     ("square wave 7.1 Hz, 0.01 rad", 0.01 * square(2 * np.pi * 7.1 * tp))):
        rows.append(("pendulum, nothing missing", label, _mismatch("pendulum", tp, pend + d)))
    # the same shapes over a record that does miss an effect: it should be named, the shape absorbed
    duff = make_model("oscillator", {"k": 4.0, "c": 0.1, "x0": 1.0}).with_effect(
        "cubic_stiffness", {"beta": 0.5}).predict(t) + 0.01 * rng.normal(size=t.size)
    rows.append(("oscillator, cubic stiffness missing", "square wave 3.7 Hz, 0.05",
                 _mismatch("oscillator", t, duff + 0.05 * square(2 * np.pi * 3.7 * t + 1))))
    rad = make_model("cooling", {"h": 0.002}).with_effect("radiation", {"r_rad": 0.002}).predict(tc) + \
        0.05 * rng.normal(size=tc.size)
    rows.append(("cooling, radiation missing", "HVAC square wave, 120 s, 0.2 K",
                 _mismatch("cooling", tc, rad + 0.2 * square(2 * np.pi * tc / 120))))
    rows.append(("cooling, radiation missing", "sensor step 0.3 K at 900 s", _mismatch("cooling", tc, rad + 0.3 * (tc > 900))))
    big = make_model("pendulum", {"w2": 9.0, "c": 0.05, "theta0": 0.8}).with_effect(
        "large_angle", {"s_angle": 1.0}).predict(tp) + 0.002 * rng.normal(size=tp.size)
    rows.append(("pendulum, large angle missing", "6 Hz line with its 12 Hz harmonic",
                 _mismatch("pendulum", tp, big + 0.01 * np.cos(2 * np.pi * 6 * tp) + 0.005 * np.cos(2 * np.pi * 12 * tp + 1))))
    return rows


def _host(n, sr, rng):
    """Pink-ish noise (AR(1), 0.95) and 12 decaying notes of the 12-tone scale: RMS about 0.1."""
    from scipy.signal import lfilter

    p = lfilter([1], [1, -0.95], rng.normal(size=n))
    x = 0.05 * p / p.std()
    t = np.arange(n) / sr
    for _ in range(12):
        f = 440 * 2 ** (rng.integers(-12, 12) / 12)
        t0 = rng.uniform(0, n / sr - 1)
        x += 0.08 * np.exp(-np.clip(t - t0, 0, None) / 0.4) * (t >= t0) * np.sin(2 * np.pi * f * t)
    return x


def _hum(phase, amps=(0.05, 0.03, 0.02, 0.01)):
    return sum(a * np.cos(k * phase + 0.3 * k) for k, a in enumerate(amps, 1))


def audio_rows():
    from odnn_sep.audio import denoise

    sr, T = 16000, 20
    t = np.arange(T * sr) / sr
    host = _host(t.size, sr, np.random.default_rng(7))
    w50 = 2 * np.pi * 50 * t
    cases = [("steady 50 Hz (reference)", host, _hum(w50)),
             ("DC offset 0.3 (3x the host's RMS)", host + 0.3, _hum(w50)),
             ("DC offset -0.5", host - 0.5, _hum(w50)),
             ("splice: phase jump of half a cycle at 9.3 s", host, _hum(w50 + np.pi * (t > 9.3))),
             ("mains frequency steps 49.95 -> 50.15 Hz at 10 s", host,
              _hum(2 * np.pi * np.cumsum(np.where(t > 10, 50.15, 49.95)) / sr)),
             ("60 Hz sine clipped at 2/3 of its peak", host, np.clip(0.3 * np.cos(2 * np.pi * 60 * t), -0.2, 0.2))]
    for fm, depth in ((0.05, 0.5), (0.25, 0.5), (0.5, 0.3), (1.0, 0.3), (2.0, 0.2)):
        cases.append((f"amplitude modulated at {fm:g} Hz, depth {depth:g}", host,
                      (1 + depth * np.sin(2 * np.pi * fm * t)) * _hum(w50)))
    rows = []
    for label, clean, hum in cases:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = denoise(clean + hum, sr)
        gain = 10 * np.log10(np.sum(hum ** 2) / np.sum((r.y - clean) ** 2))
        lines = ",".join(str(k) for k in r.harmonics) or "none"
        rows.append(("pink noise and notes, 16 kHz, 20 s", label,
                     f"gain {gain:.1f} dB, f0 {r.mains_hz:.4f} Hz, harmonics {lines}"))
    return rows


def eeg_rows():
    """The real EEG file (8 channels, 250 Hz, 50 Hz line) as recorded, with DC-coupled amplifier
    offsets (uniform in +-2000, a few hundred times the EEG's spread), with a slow drift (300,
    0.02 Hz) as well, and with one channel at a rail for 5 s: the line's level over its flanks after
    cleaning (offsets and drift taken out again), median and worst channel."""
    from bench_eeg import EEG_FILE, line_levels

    from odnn_sep.audio import denoise

    if not EEG_FILE.exists():
        return []
    x = np.load(EEG_FILE)
    rng = np.random.default_rng(0)
    off = rng.uniform(-2000, 2000, size=(x.shape[0], 1))
    drift = 300 * np.sin(2 * np.pi * 0.02 * np.arange(x.shape[1]) / 250 + rng.uniform(0, 6, (x.shape[0], 1)))
    rail = np.zeros_like(x)
    rail[5, 5000:6250] = 300.0 - x[5, 5000:6250]      # channel 5 pinned at a rail for 5 s
    rows = []
    # (label, what is added, what is taken out of the output again: the rail's stretch holds no EEG)
    for label, added, back in (("as recorded", 0.0, 0.0), ("channel offsets", off, off),
                               ("channel offsets and a slow drift", off + drift, off + drift),
                               ("one channel at a rail (300) for 5 s", rail, 0.0)):
        for spatial in (False, True):
            r = denoise((x + added).T, 250, spatial=spatial)
            lv = line_levels((r if isinstance(r, np.ndarray) else r.y).T - back, 250.0)
            rows.append(("real EEG (meegkit), " + ("spatial" if spatial else "per channel"), label,
                         f"50 Hz line over its flanks after: median {np.median(lv):.1f} dB, worst {np.max(lv):.1f} dB"))
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--audio-only", action="store_true")
    args = ap.parse_args(argv)
    import logging
    logging.disable(logging.WARNING)
    t0 = time.time()
    rows = ([] if args.audio_only else mismatch_rows()) + audio_rows() + eeg_rows()
    from probe_user_inputs import print_rows
    print_rows(rows, ("record", "disturbance", "what the tool says"), t0)
    return 0


if __name__ == "__main__":
    sys.exit(main())
