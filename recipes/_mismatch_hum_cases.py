"""Population of long hum recordings for ``bench_mismatch_hum.py`` (the hum preset on the audio engine).

Kinds (the truth each case carries):

- ``drift``: the mains frequency ramps linearly (0.7-3 mHz/s) -> ``frequency_drift``;
- ``wander``: sinusoidal mains wander (FM, +-10-40 mHz, period 4 s to half the record) -> ``frequency_wander``;
- ``wander_slow``: the same with a period of half the record to the whole record (1-2 cycles);
- ``wander_weak``: the same with a depth of only +-2-8 mHz (where naming the wander gets hard);
- ``grid``: the real grid-frequency trajectory of ``../shared/data/enf_whu_mains_reference`` (a random
  excerpt) -> a moving mains frequency: ``frequency_wander`` or ``frequency_drift`` are both right;
- ``am``: amplitude modulation of the hum (m = 0.05-0.3, 0.1-1.2 Hz) -> ``amplitude_modulation``;
- ``coupling``: a second channel (its own host and hum) leaks into the first with gain 0.05-0.2 ->
  ``channel_coupling``;
- ``null``: steady hum, nothing missing; ``null_coupling``: two channels, gain 0 (nothing missing).

Nuisances drawn for every case: 50/60 Hz mains; a sound-card clock offset (half the cases, +-0.02-0.1 %,
so 60 Hz reads 59.94-60.06 Hz); hum spectrum (fundamental dominant, 2nd dominant with a weak
fundamental, 3rd dominant, or 2nd/3rd/4th only with no fundamental at all); host (tonal music tuned
to A440 with notes near the hum harmonics, speech-like, coloured noise); hum-to-host level -5..+5 dB;
8 or 16 kHz; 24-36 s.
"""
from __future__ import annotations

import zlib

import numpy as np
from _audio_cases import enf_files, enf_phase, hum_amplitudes, noise_host, speech_host, tonal_host

EFFECT_KINDS = ("drift", "wander", "wander_slow", "wander_weak", "grid", "am", "coupling")
NULL_KINDS = ("null", "null_coupling")
KINDS = EFFECT_KINDS + NULL_KINDS
TRUTH = {"drift": {"frequency_drift"}, "wander": {"frequency_wander"}, "wander_weak": {"frequency_wander"},
         "wander_slow": {"frequency_wander"},
         "grid": {"frequency_wander", "frequency_drift"}, "am": {"amplitude_modulation"},
         "coupling": {"channel_coupling"}, "null": set(), "null_coupling": set()}
SHAPES = ("decay", "second", "third", "no_fundamental")
HOSTS = ("tonal", "speech", "noise")
DEV_SEED0, EVAL_SEED0 = 0, 100


def _kind_id(kind):
    """A stable number per kind (adding a kind leaves the other kinds' cases as they were)."""
    return zlib.crc32(kind.encode())


def case_spec(kind, seed, quick=False):
    """The drawn nuisances of one case (a dict)."""
    rng = np.random.default_rng([seed, _kind_id(kind)])
    spec = {"kind": kind, "seed": seed, "nominal": float(rng.choice([50.0, 60.0])),
            "clock": float(rng.uniform(2e-4, 1e-3) * rng.choice([-1, 1])) if rng.random() < 0.5 else 0.0,
            "shape": str(rng.choice(SHAPES)), "host": str(rng.choice(HOSTS)),
            "snr_db": float(rng.uniform(-5, 5)), "sr": int(rng.choice([8000, 16000])),
            "dur": float(rng.uniform(24, 36)), "kmax": int(rng.integers(4, 8))}
    if quick:
        spec.update(sr=8000, dur=24.0)
    return spec


def _amplitudes(shape, rng, kmax):
    if shape == "no_fundamental":
        a = np.zeros(kmax)
        a[1:4] = np.array([1.0, 0.7, 0.5])[: max(0, kmax - 1)] * rng.uniform(0.7, 1.3, size=3)[: max(0, kmax - 1)]
        return a / a.max()
    return hum_amplitudes({"decay": "decay", "second": "second", "third": "third"}[shape], rng, kmax)


def _deviation(kind, t, rng, f_base):
    """Phase deviation of the fundamental (cycles) and the effect's parameters in words."""
    dur = float(t[-1])
    if kind == "drift":
        rate = rng.uniform(0.7e-3, 3e-3) * rng.choice([-1, 1])
        return 0.5 * rate * (t - dur / 2) ** 2, {"f1": rate}
    if kind in ("wander", "wander_weak", "wander_slow"):
        period = rng.uniform(4.0, dur / 2) if kind != "wander_slow" else rng.uniform(dur / 2, dur)
        depth = rng.uniform(0.01, 0.04) if kind == "wander" else rng.uniform(0.002, 0.008)
        ph0 = rng.uniform(0, 2 * np.pi)
        return depth * period / (2 * np.pi) * np.sin(2 * np.pi * t / period + ph0), \
            {"df_w": depth, "f_w": 1 / period}
    if kind == "grid" and enf_files():
        ph = enf_phase(str(rng.choice(enf_files())))
        start = int(rng.integers(0, max(1, len(ph) - int(dur * 100) - 2)))
        seg = ph[start: start + int(dur * 100) + 2] - ph[start]
        fdev = np.diff(seg) * 100 * f_base / 50
        return (f_base / 50.0) * np.interp(t * 100, np.arange(len(seg)), seg), \
            {"range_mHz": 1000 * float(np.ptp(fdev))}
    return np.zeros_like(t), {}


def _host(name, n, sr, rng, nominal):
    return {"tonal": lambda: tonal_host(n, sr, rng, nominal), "speech": lambda: speech_host(n, sr, rng),
            "noise": lambda: noise_host(n, sr, rng)}[name]()


def _hum(t, f_base, dev, amps, rng):
    ph = 2 * np.pi * (f_base * t + dev)
    hum = np.zeros(len(t))
    for k, a in enumerate(amps, start=1):
        if a > 0:
            hum += a * np.cos(k * ph + rng.uniform(0, 2 * np.pi))
    return hum


def make_case(spec):
    """(y, aux, sr, truth): y (n,), aux {"ch2": (n,)} or None, truth with f0_mean and effect values."""
    rng = np.random.default_rng([spec["seed"], 77, _kind_id(spec["kind"])])
    sr, kind = spec["sr"], spec["kind"]
    n = int(spec["dur"] * sr)
    t = np.arange(n) / sr
    f_base = spec["nominal"] * (1 + spec["clock"])
    dev, eff = _deviation(kind, t, rng, f_base)
    kmax = min(spec["kmax"], int(0.45 * sr / (f_base + 2)))
    hum = _hum(t, f_base, dev, _amplitudes(spec["shape"], rng, kmax), rng)
    if kind == "am":
        m, f_am = rng.uniform(0.05, 0.3), rng.uniform(0.1, 1.2)
        hum = hum * (1 + m * np.cos(2 * np.pi * f_am * t + rng.uniform(0, 2 * np.pi)))
        eff = {"m_am": m, "f_am": f_am}
    host = _host(spec["host"], n, sr, rng, spec["nominal"])
    host = host / host.std()
    hum *= 10 ** (spec["snr_db"] / 20) / hum.std()
    y = host + hum + 0.05 * rng.standard_normal(n)
    aux = None
    if kind in ("coupling", "null_coupling"):
        other = _host(str(rng.choice(HOSTS)), n, sr, rng, spec["nominal"])
        other = other / other.std() + 0.5 * _hum(t, f_base, dev, _amplitudes("decay", rng, kmax), rng)
        other += 0.05 * rng.standard_normal(n)
        kappa = rng.uniform(0.05, 0.2) if kind == "coupling" else 0.0
        y = y + kappa * other
        aux = {"ch2": other}
        eff = {"kappa": kappa}
    fdev = np.gradient(dev, 1 / sr)
    truth = {"effects": TRUTH[kind], "f0_mean": float(f_base + fdev.mean()), "params": eff}
    # the true effect's parameters, rounded for the table
    truth["params"] = {k: float(f"{v:.4g}") for k, v in eff.items()}
    scale = 0.8 / max(np.abs(y).max(), np.abs(aux["ch2"]).max() if aux else 0.0)
    y = (y * scale).astype(np.float32).astype(float)
    if aux:
        aux = {"ch2": (aux["ch2"] * scale).astype(np.float32).astype(float)}
    return y, aux, sr, truth


def fft_f0(y, sr, nominal):
    """Anchor: the strongest hum line's zero-padded FFT peak (parabolic interpolation), divided by its k."""
    n = len(y)
    nfft = int(2 ** np.ceil(np.log2(4 * n)))
    spec = np.abs(np.fft.rfft(y * np.hanning(n), nfft))
    f = np.fft.rfftfreq(nfft, 1 / sr)
    best = None
    for k in range(1, 6):
        sel = np.flatnonzero(np.abs(f - k * nominal) <= 0.5 * k)
        if len(sel) == 0:
            continue
        i = sel[np.argmax(spec[sel])]
        if best is None or spec[i] > best[0]:
            best = (spec[i], i, k)
    _, i, k = best
    a, b, c = np.log(spec[i - 1: i + 2] + 1e-300)
    shift = 0.5 * (a - c) / (a - 2 * b + c) if (a - 2 * b + c) != 0 else 0.0
    return float((f[i] + shift * (f[1] - f[0])) / k)
