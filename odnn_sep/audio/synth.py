"""Synthetic audio with known mains hum: a music-like host plus drifting 50/60 Hz hum and harmonics.

Everything is generated from one seeded ``numpy.random.Generator``, so the same arguments always
give the same samples (the bundled ``samples/hum_demo.wav`` relies on that).
"""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from odnn_sep.errors import InputError


def _drift(t: np.ndarray, rng: np.random.Generator, drift_hz: float):
    """Smooth frequency wander (sum of slow sinusoids) and its exact time integral.

    Returns ``(df, int_df)`` so the hum phase is computed analytically instead of with a cumulative
    sum, which would accumulate rounding error over an hour of samples.
    """
    periods = rng.uniform(15.0, 90.0, size=3)
    amps = rng.uniform(0.5, 1.0, size=3)
    phases = rng.uniform(0, 2 * np.pi, size=3)
    # normalise so the wander spans +-drift_hz over a typical stretch of signal
    amps *= drift_hz / amps.sum()
    df = np.zeros_like(t)
    integ = np.zeros_like(t)
    for a, p, ph in zip(amps, periods, phases, strict=False):
        w = 2 * np.pi / p
        df += a * np.sin(w * t + ph)
        integ += a * (np.cos(ph) - np.cos(w * t + ph)) / w
    return df, integ


def _host(n: int, sr: int, rng: np.random.Generator, mains_hz: float, near_partials: bool):
    """Music/speech-like host: plucked harmonic notes with vibrato, formant noise bursts, and notes
    whose partials come within a few Hz of hum harmonics (the hard case for a notch filter)."""
    t = np.arange(n) / sr
    y = np.zeros(n)
    dur = n / sr
    base = [110.0, 130.8, 146.8, 164.8, 196.0, 220.0, 246.9, 261.6, 293.7, 329.6]
    note_len = 0.45
    onsets = np.arange(0.0, max(dur - 0.05, 0.0), note_len * 0.8)
    for on in onsets:
        f = rng.choice(base) * rng.choice([0.5, 1.0, 2.0])
        i0 = int(on * sr)
        i1 = min(n, i0 + int(note_len * 2.2 * sr))
        tt = t[i0:i1] - on
        env = (1 - np.exp(-tt / 0.01)) * np.exp(-tt / rng.uniform(0.15, 0.5))
        # 0.4 % vibrato at 5.5 Hz, integrated analytically into the phase
        ph = 2 * np.pi * f * tt + f * 0.004 / 5.5 * (1 - np.cos(2 * np.pi * 5.5 * tt))
        note = np.zeros_like(tt)
        for h in range(1, 7):
            if h * f < sr / 2 * 0.9:
                note += (0.6 / h) * np.sin(h * ph + rng.uniform(0, 2 * np.pi))
        y[i0:i1] += rng.uniform(0.3, 1.0) * env * note
    # speech-like formant noise bursts (syllables)
    from scipy import signal

    noise = rng.standard_normal(n)
    for lo, hi in ((300.0, 900.0), (1000.0, 2500.0)):
        if hi < sr / 2 * 0.95:
            sos = signal.butter(2, [lo, hi], btype="bandpass", fs=sr, output="sos")
            band = signal.sosfilt(sos, noise)
            syl = 0.5 * (1 + np.sign(np.sin(2 * np.pi * 3.1 * t + rng.uniform(0, 6)))) * \
                (0.5 + 0.5 * np.sin(2 * np.pi * 0.37 * t) ** 2)
            y += 0.25 * band * syl
    if near_partials:
        # sustained tonal partials 2-4 Hz from the 2nd, 3rd and 5th hum harmonics
        for k, off in ((2, 3.0), (3, -2.5), (5, 4.0)):
            f = k * mains_hz + off
            if f < sr / 2 * 0.9:
                env = 0.5 + 0.5 * np.sin(2 * np.pi * 0.05 * t + rng.uniform(0, 6)) ** 2
                y += 0.15 * env * np.sin(2 * np.pi * f * t + rng.uniform(0, 2 * np.pi))
    return y


def make_hum_mix(duration_s: float = 30.0, sr: int = 16000, *, mains_hz: float = 50.0,
                 amplitudes: Sequence[float] | None = (1.0, 0.6, 0.45, 0.3, 0.2, 0.12, 0.08, 0.05),
                 drift_hz: float = 0.05, snr_db: float = 0.0, noise_db: float = -30.0,
                 near_partials: bool = True, channels: int = 1, random_state: int | None = 0):
    """Host + drifting hum with known truth (one keyword per property of the mix: why long).

    Parameters
    ----------
    duration_s, sr : length (s) and sample rate (Hz).
    mains_hz : nominal hum fundamental (Hz); the true fundamental is ``mains_hz + drift(t)``.
    amplitudes : relative peak amplitudes of harmonics 1, 2, ...; scaled so that
        host power / hum power = ``snr_db``.
    drift_hz : peak wander of the fundamental (Hz).
    snr_db : input SNR, host (music + noise) over hum, in dB.
    noise_db : broadband white noise power relative to the music power, in dB.
    near_partials : add host partials within 2-4 Hz of harmonics 2, 3 and 5.
    channels : number of channels; each has its own hum gain and phase and its own host.
    random_state : int seed.

    Returns
    -------
    y : (n,) or (n, channels) float array
    sr : int
    truth : dict with ``host``, ``hum`` (arrays like ``y``), ``t_track``/``f0_track`` (fundamental
        every 10 ms), ``harmonics`` (list of k), ``amplitudes`` (channels, K) peak amplitudes,
        ``snr_db``.

    Examples
    --------
    >>> y, sr, truth = make_hum_mix(2.0, 8000, random_state=1)
    >>> y.shape, sr, truth["harmonics"][:3]
    ((16000,), 8000, [1, 2, 3])
    """
    if duration_s <= 0:
        raise InputError(f"duration_s must be > 0; got {duration_s}")
    if sr <= 0:
        raise InputError(f"sr must be a positive integer; got {sr}")
    rng = np.random.default_rng(random_state)
    n = int(round(duration_s * sr))
    t = np.arange(n) / sr
    df, int_df = _drift(t, rng, drift_hz)
    phase = 2 * np.pi * (mains_hz * t + int_df)
    amps = np.asarray(amplitudes, dtype=float)
    ks = [k for k in range(1, len(amps) + 1) if k * (mains_hz + drift_hz) < sr / 2 * 0.95]
    amps = amps[: len(ks)]
    hosts, hums, amp_rows = _channels(n, sr, rng, mains_hz, near_partials, noise_db, phase, ks, amps, channels)
    # one scale for all channels, set on channel 0, so relative gains stay as drawn
    scale = np.sqrt(np.mean(hosts[0] ** 2) / np.mean(hums[0] ** 2) / 10 ** (snr_db / 10))
    hums = [h * scale for h in hums]
    amp_rows = np.array(amp_rows) * scale
    host = np.stack(hosts, axis=1)
    hum = np.stack(hums, axis=1)
    y = host + hum
    peak = np.abs(y).max()
    if peak > 0.9:  # leave headroom so a 16-bit file does not clip
        g = 0.9 / peak
        y, host, hum, amp_rows = y * g, host * g, hum * g, amp_rows * g
    if channels == 1:
        y, host, hum = y[:, 0], host[:, 0], hum[:, 0]
    step = max(1, sr // 100)
    truth = {"host": host, "hum": hum, "t_track": t[::step], "f0_track": mains_hz + df[::step],
             "harmonics": ks, "amplitudes": amp_rows, "snr_db": float(snr_db), "mains_hz": float(mains_hz)}
    return y, sr, truth


def _channels(n, sr, rng, mains_hz, near_partials, noise_db, phase, ks, amps, channels):
    """Per channel: a host with its noise, and the hum with its own gain and phases (lists of
    arrays, and the amplitude rows). Internal to :func:`make_hum_mix`, whose drawing order it
    keeps (same outputs for a seed), hence its parameter list (why long)."""
    hosts, hums, amp_rows = [], [], []
    for c in range(channels):
        host = _host(n, sr, rng, mains_hz, near_partials)
        host += 10 ** (noise_db / 20) * host.std() * rng.standard_normal(n)
        gain = 1.0 if c == 0 else rng.uniform(0.4, 1.2)
        hum = np.zeros(n)
        a_c = amps * gain
        for k, a in zip(ks, a_c, strict=False):
            hum += a * np.cos(k * phase + rng.uniform(0, 2 * np.pi))
        hosts.append(host)
        hums.append(hum)
        amp_rows.append(a_c)
    return hosts, hums, amp_rows


def make_hum_demo(duration_s: float = 8.0, sr: int = 16000, random_state: int | None = 0):
    """The bundled demo: 8 s of music-like audio at 16 kHz with 50 Hz hum drifting by about 0.05 Hz.

    Deterministic for a given ``random_state``; used to write ``samples/hum_demo.wav``.

    Parameters
    ----------
    duration_s : float
        Length (s).
    sr : int
        Sample rate (Hz).
    random_state : int
        Seed.

    Returns
    -------
    y : (n,) float array in [-0.9, 0.9]
    sr : int
    truth : dict (see :func:`make_hum_mix`)

    Examples
    --------
    >>> y, sr, truth = make_hum_demo(duration_s=1.0, sr=8000)
    >>> y.shape, sr, round(truth["mains_hz"])
    ((8000,), 8000, 50)
    """
    return make_hum_mix(duration_s, sr, mains_hz=50.0, drift_hz=0.05, snr_db=6.0, noise_db=-35.0,
                        random_state=random_state)
