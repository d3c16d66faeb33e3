"""A third generator of hum cases, with hosts the other two do not have: a plucked string, a drum loop
to the sample, a swept sine, a synthesised voice with regular vibrato, pink noise and a bass note
held just off the fundamental. Used by ``bench_audio_hosts.py``.

Each case draws its sample rate (8-48 kHz), mains (50/60 Hz), length (8-30 s), input SNR (-5..+5 dB),
drift (steady, a sinusoidal wander of 5-60 s, a ramp) and hum shape (``buzz``: 1/k up to 24
harmonics; ``rect``: odd harmonics, the third loudest; ``pure``: the fundamental alone; ``second``:
the second harmonic loudest).
"""
from __future__ import annotations

import numpy as np
from scipy import signal

RATES = (8000, 16000, 22050, 32000, 44100, 48000)
SHAPES = ("buzz", "rect", "pure", "second")
A440 = 440.0 * 2 ** (np.arange(-33, 10) / 12)      # equal temperament, C2 .. F#5


def plucked(n, sr, rng):
    """Karplus-Strong plucked notes from the A440 scale, overlapping."""
    y = np.zeros(n)
    t = 0
    while t < n:
        f = float(rng.choice(A440[(A440 > 80) & (A440 < 700)]))
        L = max(2, int(round(sr / f)))
        dur = min(n - t, int(sr * rng.uniform(0.3, 1.5)))
        a = np.zeros(L + 2)
        a[0], a[L], a[L + 1] = 1.0, -0.498, -0.498          # y[i] = 0.996 (y[i-L] + y[i-L-1]) / 2 + burst
        burst = np.zeros(dur)
        burst[:L] = rng.uniform(-1, 1, min(L, dur))
        y[t:t + dur] += signal.lfilter([1.0], a, burst)
        t += int(sr * rng.uniform(0.2, 0.8))
    return y / np.std(y)


def drum_loop(n, sr, rng, step_s=None):
    """A kick and a noise snare on a step of 0.125-0.5 s (``step_s``, drawn when not given), placed to
    the sample in a pattern of 8 steps: a line spectrum on a grid of 0.25-1 Hz (the pattern's
    period), which holds every multiple of 50 and 60 Hz."""
    step = int(sr * (rng.choice([0.125, 0.25, 0.5]) if step_s is None else step_s))
    L = min(step, int(0.2 * sr))
    env = np.exp(-np.arange(L) / (0.03 * sr))
    kick = env * np.sin(2 * np.pi * rng.uniform(45, 90) * np.arange(L) / sr * (1 + env))
    snare = env * rng.standard_normal(L) * 0.7
    pattern = rng.random(8) < 0.5
    y = np.zeros(n)
    for i, s0 in enumerate(range(0, n - L, step)):
        y[s0:s0 + L] += kick if pattern[i % 8] else snare
    return y / np.std(y)


def sweep(n, sr, rng):
    """A logarithmic sine sweep from 30-45 Hz to 2 kHz: it crosses every harmonic once."""
    T = n / sr
    f0, f1 = rng.uniform(30, 45), min(2000.0, 0.45 * sr)
    t = np.arange(n) / sr
    return np.sqrt(2) * np.sin(2 * np.pi * f0 * T / np.log(f1 / f0) * ((f1 / f0) ** (t / T) - 1))


def vibrato_voice(n, sr, rng):
    """A synthesised voice (7 partials, no noise) on held scale notes, vibrato 4.5-6.5 Hz, +-1 %."""
    t = np.arange(n) / sr
    f = np.empty(n)
    i = 0
    while i < n:
        j = min(n, i + int(sr * rng.uniform(1.0, 4.0)))
        f[i:j] = rng.choice(A440[(A440 > 150) & (A440 < 500)])
        i = j
    f = f * (1 + 0.01 * np.sin(2 * np.pi * rng.uniform(4.5, 6.5) * t))
    ph = 2 * np.pi * np.cumsum(f) / sr
    y = sum(np.sin(k * ph) / k for k in range(1, 8))
    return y / np.std(y)


def pink(n, sr, rng):
    X = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n, 1 / sr)
    f[0] = f[1]
    y = np.fft.irfft(X / np.sqrt(f), n)
    return y / np.std(y)


def bass_near(n, sr, rng, mains):
    """A bass note 0.3-1.5 Hz from the fundamental, on and off every 2-6 s, over quiet noise."""
    t = np.arange(n) / sr
    period = rng.uniform(2, 6)
    gate = ((t % (2 * period)) < period).astype(float)
    f = mains + rng.choice([-1, 1]) * rng.uniform(0.3, 1.5)
    return gate * np.sin(2 * np.pi * f * t) * 1.4 + 0.3 * rng.standard_normal(n)


HOSTS = ("plucked", "drum_loop", "sweep", "vibrato_voice", "pink", "bass_near")


def host(name, n, sr, rng, mains):
    if name == "bass_near":
        return bass_near(n, sr, rng, mains)
    return globals()[name](n, sr, rng)


def harmonic_amplitudes(shape, sr, mains):
    if shape == "buzz":
        return {k: 1.0 / k for k in range(1, min(25, int(0.45 * sr / mains)))}
    if shape == "rect":
        return {1: 0.3, 3: 1.0, 5: 0.6, 7: 0.4, 9: 0.25, 11: 0.15}
    if shape == "pure":
        return {1: 1.0}
    return {1: 0.1, 2: 1.0, 3: 0.4, 4: 0.3}


def fundamental(n, sr, rng, mains):
    """The drifting fundamental (Hz per sample) and a description of its drift."""
    t = np.arange(n) / sr
    f = mains + rng.uniform(-0.05, 0.05)
    kind = rng.choice(["steady", "wander", "ramp"])
    if kind == "wander":
        period, depth = rng.uniform(5, 60), rng.uniform(0.01, 0.05)
        return f + depth * np.sin(2 * np.pi * t / period), f"wander +-{1000 * depth:.0f} mHz / {period:.0f} s"
    if kind == "ramp":
        rate = rng.choice([-1, 1]) * rng.uniform(0.002, 0.02)
        return f + rate * (t - t[-1] / 2), f"ramp {1000 * rate:+.0f} mHz/s"
    return np.full(n, f), "steady"


def make_case(seed: int, i: int):
    """Case ``i`` of seed ``seed``: host ``i % 6``, hum shape ``i // 6 % 4``; returns the clean host,
    the hum, the sample rate and a description with the true lines."""
    rng = np.random.default_rng((seed, i))
    name, shape = HOSTS[i % len(HOSTS)], SHAPES[(i // len(HOSTS)) % len(SHAPES)]
    sr = int(rng.choice(RATES))
    mains = float(rng.choice([50.0, 60.0]))
    n = int(rng.uniform(8, 30) * sr)
    x = host(name, n, sr, rng, mains)
    f, drift = fundamental(n, sr, rng, mains)
    ph = 2 * np.pi * np.cumsum(f) / sr
    amps = harmonic_amplitudes(shape, sr, mains)
    hum = sum(a * np.cos(k * ph + rng.uniform(0, 2 * np.pi)) for k, a in amps.items())
    snr = rng.uniform(-5, 5)
    hum = hum * np.std(x) / np.std(hum) * 10 ** (-snr / 20)
    desc = dict(host=name, shape=shape, sr=sr, mains=mains, seconds=n / sr, snr_db=snr, drift=drift,
                lines=[k * float(np.mean(f)) for k in amps])
    return 0.1 * x, 0.1 * hum, sr, desc
