"""Population of hum-removal cases for ``bench_audio.py``: several hosts, drifts, hum spectra, rates.

Hosts (each its own generator):

- ``tonal``: notes of a seven-note scale tuned to A440 (equal temperament), 4-7 partials, sustained
  0.2-4 s, three voices; about half the notes are drawn from those with a partial 0.5-3 Hz from a
  hum harmonic (F4 = 349.2 Hz is 0.8 Hz from 350 Hz), and pitches repeat;
- ``speech``: voiced syllables (glottal harmonics under three formants, gliding pitch 85-260 Hz)
  with pauses and unvoiced noise bursts;
- ``noise``: white, pink or brown noise with a slow level envelope.

Drift of the fundamental: the real grid frequency of ``../shared/data/enf_whu_mains_reference``
(phase deviation of the 50 Hz line, x1 or x3), sinusoidal FM (period 5-90 s, rate <= 50 mHz/s),
steady, or a linear ramp (up to 50 mHz/s). A sound-card clock offset (+-0.02-0.1 %) is drawn for a
third of the cases. Hum spectra: decaying, odd-dominant, 2nd-dominant (120/100 Hz) and
3rd-dominant (180/150 Hz); some harmonics are absent (the false-line count uses them).
"""
from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
from scipy import signal

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
HOSTS = ("tonal", "speech", "noise")
DRIFTS = ("enf_x1", "enf_x3", "fm", "steady", "ramp")
SHAPES = ("decay", "odd", "second", "third")
RATES = (8000, 16000, 44100, 48000)
EVAL_SEED0, DEV_SEED0 = 0, 1000


def midi_hz(m):
    return 440.0 * 2.0 ** ((np.asarray(m, float) - 69) / 12)


# ---------------------------------------------------------------------------------------- hosts
def tonal_host(n, sr, rng, mains, near_frac=0.5, voices=3, min_s=0.2, max_s=4.0):
    """Sustained A440 notes, about ``near_frac`` of them with a partial 0.5-3 Hz from k * mains."""
    t_total = n / sr
    notes = np.arange(36, 90)
    f = midi_hz(notes)
    near = []
    for m, fn in zip(notes, f, strict=True):
        for h in range(1, 7):
            d = abs(h * fn - mains * np.round(h * fn / mains))
            if 0.5 <= d <= 3.0 and h * fn < 0.45 * sr and np.round(h * fn / mains) <= 40:
                near.append(m)
                break
    scale = rng.choice(notes, size=7, replace=False)
    near_pool = rng.choice(near, size=min(4, len(near)), replace=False) if near else scale
    y = np.zeros(n)
    for _ in range(voices):
        t0 = rng.uniform(0, 0.5)
        while t0 < t_total:
            dur = float(np.exp(rng.uniform(np.log(min_s), np.log(max_s))))
            m = rng.choice(near_pool) if rng.random() < near_frac else rng.choice(scale)
            _add_note(y, sr, t0, dur, midi_hz(m), rng)
            t0 += dur + rng.uniform(0.0, 0.6)
    return y


def _add_note(y, sr, t0, dur, f, rng, piano=False, n_partials=None):
    n = y.shape[0]
    i0 = int(t0 * sr)
    i1 = min(n, i0 + int((dur + 0.08) * sr))
    if i1 <= i0:
        return
    tt = np.arange(i1 - i0) / sr
    env = np.minimum(1.0, tt / 0.01) * np.clip((dur + 0.08 - tt) / 0.08, 0, 1)
    env *= np.exp(-tt / (0.4 if piano else rng.uniform(2.0, 8.0)))
    npart = n_partials or int(rng.integers(4, 8))
    note = np.zeros_like(tt)
    for h in range(1, npart + 1):
        fh = h * f * (np.sqrt(1 + 4e-4 * h * h) if piano else 1.0)
        if fh < 0.45 * sr:
            note += (0.7 / h ** rng.uniform(0.7, 1.3)) * np.sin(2 * np.pi * fh * tt + rng.uniform(0, 2 * np.pi))
    y[i0:i1] += rng.uniform(0.3, 1.0) * env * note


def speech_host(n, sr, rng):
    """Voiced syllables with gliding pitch under three formants, pauses, unvoiced bursts."""
    y = np.zeros(n)
    t0 = rng.uniform(0, 0.3)
    base = rng.uniform(90, 220)
    while t0 < n / sr:
        dur = rng.uniform(0.1, 0.35)
        i0, i1 = int(t0 * sr), min(n, int((t0 + dur) * sr))
        if i1 - i0 > 10:
            tt = np.arange(i1 - i0) / sr
            f0 = base * (1 + rng.uniform(-0.15, 0.15)) * (1 + rng.uniform(-0.2, 0.2) * tt / dur)
            ph = 2 * np.pi * np.cumsum(f0) / sr
            fm = [rng.uniform(300, 800), rng.uniform(900, 2300), rng.uniform(2400, 3200)]
            seg = np.zeros_like(tt)
            for h in range(1, int(0.45 * sr / f0.max())):
                fh = h * f0
                gain = sum(1.0 / (1 + ((fh - F) / 90.0) ** 2) for F in fm) / h ** 0.5
                seg += gain * np.sin(h * ph)
            env = np.sin(np.pi * tt / dur) ** 0.7
            y[i0:i1] += env * seg / 3
            if rng.random() < 0.3 and i1 < n - 10:   # an unvoiced consonant after the vowel
                j1 = min(n, i1 + int(0.08 * sr))
                hp = signal.butter(2, min(2000.0, 0.3 * sr), "highpass", fs=sr, output="sos")
                y[i1:j1] += 0.2 * signal.sosfilt(hp, rng.standard_normal(j1 - i1))
        t0 += dur + (rng.uniform(0.03, 0.15) if rng.random() < 0.8 else rng.uniform(0.3, 0.8))
    return y


def noise_host(n, sr, rng, colour=None):
    colour = colour or rng.choice(["white", "pink", "brown"])
    X = np.fft.rfft(rng.standard_normal(n))
    f = np.maximum(np.fft.rfftfreq(n, 1 / sr), 20.0)
    X *= {"white": 1.0, "pink": f ** -0.5, "brown": f ** -1.0}[colour]
    x = np.fft.irfft(X, n)
    t = np.arange(n) / sr
    return x * (1 + 0.5 * np.sin(2 * np.pi * t / rng.uniform(5, 20) + rng.uniform(0, 6)))


# ---------------------------------------------------------------------------------------- drift
@lru_cache(maxsize=4)
def enf_phase(name: str):
    """Phase deviation (cycles of the fundamental) of the 50 Hz line of a mains reference, at 100 Hz."""
    import soundfile as sf

    x, sr = sf.read(DATA / "enf_whu_mains_reference" / name)
    t = np.arange(len(x)) / sr
    z = x * np.exp(-2j * np.pi * 50.0 * t)
    sos = signal.butter(4, 2.0, fs=sr, output="sos")
    z = signal.sosfiltfilt(sos, z.real) + 1j * signal.sosfiltfilt(sos, z.imag)
    q = sr // 100
    ph = np.unwrap(np.angle(z[::q])) / (2 * np.pi)
    return ph - ph[0]


def enf_files():
    d = DATA / "enf_whu_mains_reference"
    return sorted(p.name for p in d.glob("*_ref.wav")) if d.exists() else []


def drift_cycles(kind, t, rng, nominal):
    """Phase deviation of the fundamental from nominal * t, in cycles; and a description."""
    dur = t[-1] if len(t) else 0.0
    if kind.startswith("enf") and enf_files():
        scale = 3.0 if kind == "enf_x3" else 1.0
        ph = enf_phase(str(rng.choice(enf_files())))
        start = rng.integers(0, max(1, len(ph) - int(dur * 100) - 2))
        seg = ph[start: start + int(dur * 100) + 2] - ph[start]
        # deviation in cycles of the 50 Hz line -> in cycles of this fundamental
        cyc = scale * (nominal / 50.0) * np.interp(t * 100, np.arange(len(seg)), seg)
        fdev = np.diff(seg) * 100 * scale * nominal / 50
        return cyc, f"grid x{scale:g} (range {1000 * np.ptp(fdev):.0f} mHz)"
    if kind == "fm" or kind.startswith("enf"):
        period = float(np.exp(rng.uniform(np.log(5.0), np.log(90.0))))
        depth = min(rng.uniform(0.02, 0.06), 0.05 * period / (2 * np.pi))
        ph0 = rng.uniform(0, 2 * np.pi)
        cyc = depth * period / (2 * np.pi) * (np.cos(ph0) - np.cos(2 * np.pi * t / period + ph0))
        return cyc, f"FM +-{1000 * depth:.0f} mHz, period {period:.0f} s"
    if kind == "ramp":
        rate = rng.uniform(0.005, 0.05) * rng.choice([-1, 1])
        return 0.5 * rate * (t - dur / 2) ** 2 - 0.5 * rate * (dur / 2) ** 2, f"ramp {1000 * rate:+.0f} mHz/s"
    return np.zeros_like(t), "steady"


def hum_amplitudes(shape, rng, kmax):
    k = np.arange(1, kmax + 1)
    if shape == "odd":
        a = np.where(k % 2 == 1, 1.0 / k, 0.08 / k)
    elif shape == "second":
        a = 1.0 / np.abs(k - 2).clip(0.5) ** 1.2
        a[0] = rng.uniform(0.03, 0.12)
    elif shape == "third":
        a = 1.0 / np.abs(k - 3).clip(0.5) ** 1.2
        a[0] = rng.uniform(0.03, 0.12)
        a[1] *= 0.3
    else:
        a = 1.0 / k
    a = a * rng.uniform(0.7, 1.3, size=kmax)
    # a few harmonics above the strongest are absent altogether
    drop = rng.random(kmax) < 0.2
    drop[: 3] = False
    a[drop] = 0.0
    return a / a.max()


# ---------------------------------------------------------------------------------------- cases
SNR_DB = None     # one input SNR (dB) for every case instead of the drawn -5..+5 (bench_audio.py --snr)


def case_spec(i, seed0, quick=False):
    rng = np.random.default_rng(seed0 + i)
    spec = {"i": i, "seed": seed0 + i, "host": HOSTS[i % 3], "drift": DRIFTS[i % 5], "shape": SHAPES[i % 4],
            "nominal": (50.0, 60.0)[(i // 3) % 2], "sr": RATES[(i // 2) % 4],
            "snr_db": float(rng.uniform(-5, 5)), "dur": float(rng.uniform(20, 40))}
    spec["clock"] = float(rng.uniform(2e-4, 1e-3) * rng.choice([-1, 1])) if rng.random() < 1 / 3 else 0.0
    spec["kmax"] = int(rng.integers(5, 13))
    if SNR_DB is not None:
        spec["snr_db"] = float(SNR_DB)
    if quick:
        spec.update(sr=8000, dur=10.0)
    return spec


def make_case(spec):
    """(y, sr, truth) for one case: truth has host, hum, ks (present harmonics), f0_mean, f0_range."""
    rng = np.random.default_rng(spec["seed"] + 77)
    sr, nom = spec["sr"], spec["nominal"]
    n = int(spec["dur"] * sr)
    t = np.arange(n) / sr
    host = {"tonal": lambda: tonal_host(n, sr, rng, nom), "speech": lambda: speech_host(n, sr, rng),
            "noise": lambda: noise_host(n, sr, rng)}[spec["host"]]()
    host += 10 ** (-40 / 20) * host.std() * rng.standard_normal(n)
    f_base = nom * (1 + spec["clock"])
    dev, desc = drift_cycles(spec["drift"], t, rng, f_base)
    kmax = min(spec["kmax"], int(0.45 * sr / (f_base + 2)))
    amps = hum_amplitudes(spec["shape"], rng, kmax)
    ph = 2 * np.pi * (f_base * t + dev)
    am = 1 + 0.02 * np.sin(2 * np.pi * t / rng.uniform(20, 60) + rng.uniform(0, 6))
    hum = np.zeros(n)
    for k, a in enumerate(amps, start=1):
        if a > 0:
            hum += a * np.cos(k * ph + rng.uniform(0, 2 * np.pi))
    hum *= am
    g = np.sqrt(np.mean(host ** 2) / np.mean(hum ** 2) / 10 ** (spec["snr_db"] / 10))
    hum *= g
    peak = np.abs(host + hum).max()
    host, hum = 0.8 * host / peak, 0.8 * hum / peak
    fdev = np.gradient(dev, 1 / sr)
    truth = {"host": host, "hum": hum, "ks": [k for k, a in enumerate(amps, start=1) if a > 0],
             "kmax": kmax, "f0_mean": float(f_base + fdev.mean()),
             "f0_lo": float(f_base + fdev.min()), "f0_hi": float(f_base + fdev.max()), "drift_desc": desc,
             "f_base": f_base, "dev_cycles": dev[:: max(1, sr // 100)]}
    return host + hum, sr, truth


def clean_hosts(quick=False):
    """Hum-free recordings: (name, y, sr)."""
    rng = np.random.default_rng(4242)
    out = []
    for sr in ((16000,) if quick else (16000, 44100)):
        n = int((8 if quick else 20) * sr)
        piano, organ, bass = np.zeros(n), np.zeros(n), np.zeros(n)
        t0 = 0.0
        while t0 < n / sr:
            _add_note(piano, sr, t0, 0.6, midi_hz(rng.integers(40, 85)), rng, piano=True)
            t0 += rng.uniform(0.15, 0.5)
        for m in (53, 57, 60, 65):                  # F3 A3 C4 F4, held chords (F4 = 349.2 Hz)
            for t0 in np.arange(0, n / sr, 4.0):
                _add_note(organ, sr, t0, 3.9, midi_hz(m), rng, n_partials=8)
        t0 = 0.0
        while t0 < n / sr:                           # E1-E2 bass line (A1 = 55 Hz, B1 = 61.7 Hz)
            _add_note(bass, sr, t0, 0.45, midi_hz(rng.integers(28, 41)), rng, n_partials=6)
            t0 += 0.5
        cases = [("tonal (A440 scale)", tonal_host(n, sr, rng, 50.0)), ("tonal 60 (A440 scale)",
                 tonal_host(n, sr, rng, 60.0)), ("piano", piano), ("organ chords", organ), ("bass line", bass),
                 ("speech", speech_host(n, sr, rng)), ("pink noise", noise_host(n, sr, rng, "pink")),
                 ("silence", np.zeros(n))]
        for name, y in cases:
            peak = np.abs(y).max()
            out.append((f"{name}, {sr / 1000:g} kHz", 0.5 * y / peak if peak > 0 else y, sr))
    return out
