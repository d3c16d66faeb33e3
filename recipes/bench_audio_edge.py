"""Inputs the hum populations do not cover: short switched hum, one-channel hum, a tone on the comb, real EEG.

    python recipes/bench_audio_edge.py          # prints one line per case (odnn-sep only, a minute)

Each case is small and has a known truth (except the EEG file, scored by its line level):

- ``half_on A-B``: 12 s of noise and a 440 Hz tone (rms 0.086) with 50 + 100 Hz hum (rms 0.079)
  on from A to B s only; score: the hum left where it is on, relative to the hum (dB), and the
  content changed where it is off (more than 0.5 s from the switch), relative to the content;
- ``one_channel``: stereo noise and a 440 Hz tone, a 0.003 amplitude 50 Hz hum on channel 1 only;
  score: the 50 Hz amplitude left on channel 1 relative to the hum's, the change of channel 0;
- ``tone_on_comb``: a 1 kHz tone (0.3) beside 50 Hz hum (0.05), both steady: the data cannot tell
  the tone from a 20th harmonic; score: what is left of the tone and whether a warning names it;
- ``short_excerpts``: 0.7-1.95 s excerpts of the hum population's evaluation cases (seeds 0+) and
  of its hum-free recordings; score: the median and worst gain, and hum found where there is none;
- ``harmonic_wander``: speech-like or noise hosts (20-40 s, 8/16/44.1 kHz, 50/60 Hz, SNR -5..+5 dB)
  with a 1/k hum of 10 harmonics whose phases against the fundamental wander, each on its own
  (a sinusoid of DEPTH rad and a 15-60 s period), on top of the shared drift; seeds 0-5, DEPTH 0,
  0.1, 0.3 and 1 rad; score: the median and worst gain of odnn-sep and of MNE spectrum_fit given
  the true lines, and on how many cases odnn-sep is ahead;
- ``harmonic_am``: the same hosts and comb, each harmonic's amplitude varying on its own by
  ``1 + DEPTH sin`` (10-40 s periods); seeds 300-305, DEPTH 0, 0.1 and 0.3;
- ``eeg``: ``../shared/data/meegkit_eeg_line_noise/eeg_raw.npy``, per-channel mode: the 50 Hz line
  level over its flanks (Welch, 0.25 Hz) per channel before and after.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EEG = ROOT.parent / "shared" / "data" / "meegkit_eeg_line_noise" / "eeg_raw.npy"


def _db(a, b) -> str:
    """``10 log10`` of the energy of ``a`` over that of ``b``, or "unchanged" where ``a`` is zero."""
    ea = float(np.sum(a ** 2))
    return "unchanged" if ea == 0 else f"{10 * np.log10(ea / max(float(np.sum(b ** 2)), 1e-300)):.1f} dB"


def half_on(on_s: float, off_s: float, sr: int = 8000, dur: float = 12.0):
    from odnn_sep.audio import denoise

    rng = np.random.default_rng(2)
    t = np.arange(int(dur * sr)) / sr
    content = 0.05 * rng.standard_normal(t.size) + 0.1 * np.sin(2 * np.pi * 440 * t)
    on = (t >= on_s) & (t < off_s)
    hum = on * (0.1 * np.sin(2 * np.pi * 50 * t) + 0.05 * np.sin(2 * np.pi * 100 * t))
    r = denoise(content + hum, sr)
    err = r.y - content
    switch = [s for s in (on_s, off_s) if 0 < s < dur]
    off = ~on & np.all([np.abs(t - s) > 0.5 for s in switch], axis=0)
    return (f"half_on {on_s:g}-{off_s:g} s | lines {r.harmonics} | hum left where on {_db(err[on], hum[on])}"
            f" | content changed where off {_db(err[off], content[off])}")


def one_channel(sr: int = 8000, dur: float = 10.0):
    from odnn_sep.audio import denoise

    rng = np.random.default_rng(5)
    t = np.arange(int(dur * sr)) / sr
    content = 0.05 * rng.standard_normal((t.size, 2)) + 0.1 * np.sin(2 * np.pi * 440 * t)[:, None]
    hum = np.zeros_like(content)
    hum[:, 1] = 0.003 * np.sin(2 * np.pi * 50 * t)
    r = denoise(content + hum, sr)
    line = lambda a: 2 * abs(np.mean(a * np.exp(-2j * np.pi * 50 * t)))  # noqa: E731
    left = 20 * np.log10(max(line(r.y[:, 1] - content[:, 1]), 1e-12) / line(hum[:, 1]))
    return (f"one_channel | lines {r.harmonics} | 50 Hz left on channel 1 {left:.1f} dB"
            f" | channel 0 changed {_db(r.y[:, 0] - content[:, 0], content[:, 0])}")


def tone_on_comb(sr: int = 8000, dur: float = 10.0):
    from odnn_sep.audio import denoise

    rng = np.random.default_rng(5)
    t = np.arange(int(dur * sr)) / sr
    tone = 0.3 * np.sin(2 * np.pi * 1000 * t)
    y = 0.01 * rng.standard_normal(t.size) + tone + 0.05 * np.sin(2 * np.pi * 50 * t)
    r = denoise(y, sr)
    amp = lambda a: 2 * abs(np.mean(a * np.exp(-2j * np.pi * 1000 * t)))  # noqa: E731
    return (f"tone_on_comb | lines {r.harmonics} | 1 kHz tone left {amp(r.y) / amp(tone):.3f} of it"
            f" | warned as isolated {r.info.get('isolated_lines', 'no such report field')}")


def short_excerpts(seed0: int = 0, n: int = 24, offsets=(1.1, 5.3, 9.7)):
    """0.7-1.95 s excerpts of the population's cases (``_audio_cases``, seeds ``seed0``..; the
    development seeds are 1000+) and of its hum-free recordings: gain, and hum found where none is."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import _audio_cases as cases

    from odnn_sep.audio import denoise

    gains = []
    for i in range(n):
        y, sr, tr = cases.make_case(cases.case_spec(i, seed0))
        rng = np.random.default_rng(seed0 + i)
        a = int(rng.uniform(0, len(y) / sr - 2) * sr)
        b = a + int(rng.uniform(0.7, 1.95) * sr)
        h, x = tr["hum"][a:b], tr["host"][a:b]
        r = denoise(x + h, sr)
        gains.append(10 * np.log10(np.sum(h ** 2) / max(np.sum((r.y - x) ** 2), 1e-300)))
    false, tested = 0, 0
    for _, y, sr in cases.clean_hosts(False):
        for dur in (0.7, 1.0, 1.5, 1.9):
            for off in offsets:
                seg = y[int(off * sr): int((off + dur) * sr)]
                if len(seg) == int(dur * sr):
                    tested += 1
                    false += bool(denoise(seg, sr).line_names)
    g = np.array(gains)
    return (f"short_excerpts seeds {seed0}+ | hum gain median {np.median(g):.1f} dB, worst {g.min():.1f} dB, "
            f"{int(np.sum(g > 0.5))} of {len(g)} with hum removed | hum found in {false} of {tested} hum-free excerpts")


def eeg():
    from scipy import signal

    from odnn_sep.audio import denoise

    if not EEG.exists():
        return "eeg | skipped: ../shared/data/meegkit_eeg_line_noise is not present"
    x = np.load(EEG)
    y = denoise(x, sfreq=250.0)

    def level(a):
        f, p = signal.welch(a, fs=250, nperseg=1000, axis=-1)
        i = np.argmin(np.abs(f - 50))
        nb = (np.abs(f - 50) > 2) & (np.abs(f - 50) < 6)
        return np.round(10 * np.log10(p[:, i] / p[:, nb].mean(axis=1)), 1).tolist()

    return f"eeg per-channel | line over flanks before {level(x)} dB | after {level(y)} dB"


def harmonic_wander(depth: float, seeds=range(6), amplitude: bool = False):
    """Each harmonic's phase (or, with ``amplitude``, its amplitude, by ``1 + depth x``) varies
    on its own by a slow sinusoid; see the module text."""
    import _audio_cases as cases
    from bench_audio import run_mne

    from odnn_sep.audio import denoise

    ours, mne = [], []
    for seed in seeds:
        rng = np.random.default_rng(seed)
        sr = int(rng.choice([8000, 16000, 44100]))
        n = int(sr * rng.uniform(20, 40))
        t = np.arange(n) / sr
        host = [cases.speech_host, cases.noise_host][seed % 2](n, sr, rng)
        nominal = float(rng.choice([50.0, 60.0]))
        f = nominal + rng.uniform(-0.03, 0.03) + 0.02 * np.sin(2 * np.pi * t / rng.uniform(10, 60))
        ph = 2 * np.pi * np.cumsum(f) / sr
        hum = np.zeros(n)
        for k in range(1, 11):
            if amplitude:
                am = 1 + depth * np.sin(2 * np.pi * t / rng.uniform(10, 40) + rng.uniform(0, 2 * np.pi))
                hum += am * np.cos(k * ph + rng.uniform(0, 2 * np.pi)) / k
            else:
                wander = depth * np.sin(2 * np.pi * t / rng.uniform(15, 60) + rng.uniform(0, 2 * np.pi))
                hum += np.cos(k * ph + rng.uniform(0, 2 * np.pi) + wander) / k
        hum *= np.std(host) / np.std(hum) * 10 ** (-rng.uniform(-5, 5) / 20)
        r = denoise(host + hum, sr)
        ours.append(-float(_db_value(r.y - host, hum)))
        mne.append(-float(_db_value(run_mne(host + hum, sr, [k * float(np.mean(f)) for k in range(1, 11)]) - host, hum)))
    ahead = sum(a > b for a, b in zip(ours, mne))
    name = "harmonic_am" if amplitude else "harmonic_wander"
    return (f"{name} {depth:g}{'' if amplitude else ' rad'} seeds {seeds[0]}-{seeds[-1]} | odnn-sep median {np.median(ours):.1f} dB,"
            f" worst {min(ours):.1f} dB | MNE spectrum_fit (true lines) median {np.median(mne):.1f} dB, worst {min(mne):.1f} dB"
            f" | odnn-sep ahead on {ahead} of {len(ours)}")


def _db_value(a, b) -> float:
    """``10 log10`` of the energy of ``a`` over that of ``b``."""
    return 10 * np.log10(max(float(np.sum(a ** 2)), 1e-300) / max(float(np.sum(b ** 2)), 1e-300))


def main() -> int:
    import logging

    logging.disable(logging.WARNING)
    for case in (lambda: half_on(6, 12), lambda: half_on(0, 6), lambda: half_on(3, 9), one_channel,
                 tone_on_comb, short_excerpts,
                 *[lambda d=d: harmonic_wander(d) for d in (0.0, 0.1, 0.3, 1.0)],
                 *[lambda d=d: harmonic_wander(d, range(300, 306), amplitude=True) for d in (0.0, 0.1, 0.3)], eeg):
        print(case(), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
