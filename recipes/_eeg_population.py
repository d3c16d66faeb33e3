"""Generated multichannel EEG with line noise, for recipes/bench_eeg.py (known clean signal).

Every nuisance is drawn per case from the seed:

- rate: 250, 512.5 or 1000 Hz; channels: 8, 16 or 32; mains 50 or 60 Hz;
- brain: as many sources as channels, 1/f^beta noise (beta 1-2) plus alpha (8-12 Hz) and beta
  (18-25 Hz) bursts and a little gamma, mixed by a random matrix, plus sensor noise; half the
  cases are low-passed at 40 Hz like many clinical recordings (the line then sits 40-60 dB above
  the floor of that band);
- hum: one grid fundamental drifting by a sinusoidal FM (0.01-0.08 Hz, periods 10-60 s) plus a
  slow random walk, seen through 1-3 sources (e.g. a cable and a device), each with harmonics
  1..K of its own random amplitudes (a weak fundamental in a quarter of the cases), an amplitude
  envelope (slow AM of depth 0-60 % with periods 2-30 s, or bursts: a log-normal envelope
  changing within 1-5 s over a factor of 3-10, as the real EEG file's line does), and a spatial
  pattern per harmonic: a smooth gain over the channels times a per-channel phase spread of
  0-0.6 rad (so the hum is not in phase everywhere);
- SNR: hum RMS over brain RMS on the channels' median, -25 to 0 dB.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal


@dataclass
class EegCase:
    name: str
    x: np.ndarray          # (n_channels, n_times) noisy
    clean: np.ndarray      # (n_channels, n_times) brain only
    sfreq: float
    mains: float
    harmonics: list        # harmonic numbers present in the hum
    drift_hz: float        # largest excursion of the fundamental from mains
    params: dict


def _pink(rng, n_src, n, beta):
    spec = np.fft.rfft(rng.standard_normal((n_src, n)), axis=1)
    f = np.arange(spec.shape[1], dtype=float)
    f[0] = 1.0
    return np.fft.irfft(spec / f ** (beta / 2), n=n, axis=1)


def _bursts(rng, n, sfreq, lo, hi, n_src):
    b, a = signal.butter(2, [lo, hi], btype="band", fs=sfreq)
    osc = signal.filtfilt(b, a, rng.standard_normal((n_src, n)), axis=1)
    env = signal.filtfilt(*signal.butter(2, 0.5, fs=sfreq), rng.standard_normal((n_src, n)), axis=1)
    return osc * np.maximum(env, 0) / (np.std(env) + 1e-12)


def _brain(rng, C, n, sfreq, lowpass):
    beta = rng.uniform(1.0, 2.0)
    src = _pink(rng, C, n, beta)
    src /= src.std(axis=1, keepdims=True)
    src += 1.5 * _bursts(rng, n, sfreq, 8, 12, C) + 0.5 * _bursts(rng, n, sfreq, 18, 25, C)
    if sfreq > 200:
        src += 0.05 * _bursts(rng, n, sfreq, 30, min(90, 0.45 * sfreq), C)
    mix = rng.standard_normal((C, C))
    brain = mix @ src / np.sqrt(C) + 0.1 * rng.standard_normal((C, n))
    if lowpass:
        brain = signal.sosfiltfilt(signal.butter(8, 40, fs=sfreq, output="sos"), brain, axis=1)
    return brain, beta


def _f0_track(rng, n, sfreq, mains):
    t = np.arange(n) / sfreq
    fm_amp, fm_period = rng.uniform(0.01, 0.08), rng.uniform(10, 60)
    walk = np.cumsum(rng.standard_normal(n)) / np.sqrt(sfreq) * 0.004
    walk -= walk.mean()
    f0 = mains + fm_amp * np.sin(2 * np.pi * t / fm_period + rng.uniform(0, 2 * np.pi)) + walk
    return f0, float(np.max(np.abs(f0 - mains)))


def _envelope(rng, t, sfreq):
    """Slow sinusoidal AM (half the sources) or bursty line noise as in the real EEG file: a
    log-normal envelope low-passed at 0.2-1 Hz, ranging over a factor of about 3-10."""
    if rng.random() < 0.5:
        depth, period = rng.uniform(0, 0.6), rng.uniform(2, 30)
        return 1 + depth * np.sin(2 * np.pi * t / period + rng.uniform(0, 2 * np.pi))
    g = rng.standard_normal(t.size)
    g = signal.sosfiltfilt(signal.butter(2, rng.uniform(0.2, 1.0), fs=sfreq, output="sos"), g)
    return np.exp(rng.uniform(0.4, 0.8) * g / g.std())


def _hum(rng, C, n, sfreq, mains):
    t = np.arange(n) / sfreq
    kmax = int(min(6, (0.45 * sfreq) // (mains * 1.01)))
    n_src = int(rng.integers(1, 4))
    total, present = np.zeros((C, n)), set()
    pos = np.linspace(0, 1, C)
    f0, drift = _f0_track(rng, n, sfreq, mains)      # one grid: every source follows the same fundamental
    phase = 2 * np.pi * np.cumsum(f0) / sfreq
    for _ in range(n_src):
        K = int(rng.integers(1, kmax + 1))
        amps = rng.uniform(0.2, 1.0, K) / np.arange(1, K + 1) ** rng.uniform(0, 1)
        if rng.random() < 0.25 and K > 1:
            amps[0] *= 0.1                       # weak fundamental, 2nd/3rd harmonic dominant
        env = _envelope(rng, t, sfreq)
        centre, width = rng.uniform(0, 1), rng.uniform(0.3, 1.5)
        for k in range(1, K + 1):
            gain = np.exp(-((pos - centre) / width) ** 2) * rng.uniform(0.7, 1.3, C)
            spread = rng.uniform(0, 0.6)
            ph = rng.uniform(0, 2 * np.pi) + spread * rng.standard_normal(C)
            total += amps[k - 1] * gain[:, None] * env * np.cos(k * phase[None, :] + ph[:, None])
            present.add(k)
    return total, sorted(present), drift, n_src


def make_eeg_case(seed: int, duration_s: float = 30.0) -> EegCase:
    """One generated recording; everything drawn from ``seed``."""
    rng = np.random.default_rng(seed)
    sfreq = float(rng.choice([250.0, 512.5, 1000.0]))
    C = int(rng.choice([8, 16, 32]))
    mains = float(rng.choice([50.0, 60.0]))
    lowpass = bool(rng.random() < 0.5)
    n = int(duration_s * sfreq)
    brain, beta = _brain(rng, C, n, sfreq, lowpass)
    hum, ks, drift, n_src = _hum(rng, C, n, sfreq, mains)
    snr_db = rng.uniform(-25, 0)
    scale = np.median(brain.std(axis=1)) / np.median(hum.std(axis=1)) * 10 ** (snr_db / 20)
    x = brain + scale * hum
    params = {"sfreq": sfreq, "channels": C, "mains": mains, "lowpass40": lowpass, "hum_sources": n_src,
              "harmonics": ks, "snr_db": round(snr_db, 1), "beta": round(beta, 2), "drift_hz": round(drift, 3)}
    return EegCase(f"seed{seed}", x, brain, sfreq, mains, ks, drift, params)
