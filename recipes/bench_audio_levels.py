"""Benchmark: hum removal on a second generator, built apart from the population of ``bench_audio.py``.

The population's hum is a sum of sinusoids at a steady level (2 % slow modulation). Here the hum's
waveform and level come from other mechanisms, each its own kind:

- ``saturated``: a transformer's saturated current, ``tanh(3 sin)`` (odd harmonics far up);
- ``dimmer``: a phase-cut dimmer's current (a sine cut for part of each half cycle);
- ``rectified``: a rectifier's ``|sin|`` (even harmonics only: a 100/120 Hz comb);
- ``switched``: hum of a device switched on at 8 s and off at 22 s (50 ms ramps);
- ``load``: a load that changes twice a second (40 % level modulation at 0.5 Hz);
- ``steps``: a level that steps every 5 s (0.3-1.5x);
- ``phase_jump``: the hum's phase jumps by a quarter cycle at 15 s (a source switched over);
- ``splice``: the recording is cut and joined: the hum's waveform jumps by a random fraction of a
  cycle (0.05-0.95) at a random instant (6-24 s).

The waveforms of the first three kinds are summed from their Fourier series, only the harmonics
below 0.45 of the sample rate (the version before sampled the waveform directly: the dimmer's
jumps folded their harmonics above the Nyquist frequency back between the harmonics, a comb at
k f0 +- (sr mod f0) that a sound card's anti-aliasing filter removes and no hum model can, which
capped the dimmer cases near 25-30 dB).

The hum after a jump is the same waveform drawn at shifted times (the version before the splice
kind shifted the samples and held the last one for the jump's length at the very end: a few ms of
flat hum that no hum model removes, which capped the phase_jump cases near 30-36 dB).

Hosts: speech-like bursts (16 kHz, 50 Hz mains) and tonal music tuned to A440 (44.1 kHz, 60 Hz),
from ``_audio_cases.py``; SNR 0 dB, 30 s. Per case: the SNR gain of odnn-sep (defaults, no hint)
and of MNE spectrum_fit and an iirnotch cascade, both given the true lines (harmonics 1-15 of the
true fundamental). Seeds ``--seed0`` + kind index (development: 100, the default; evaluation: 500).

    python recipes/bench_audio_levels.py                  # development seeds, print only
    python recipes/bench_audio_levels.py --seed0 500 --write
"""
from __future__ import annotations

import argparse
import copy
import time

import _audio_cases as cases
import numpy as np
from _audio_population import gain_db
from bench_audio import run_iirnotch, run_mne

KINDS = ("saturated", "dimmer", "rectified", "switched", "load", "steps", "phase_jump", "splice")
HOSTS = (("speech", 16000, 50.0), ("tonal", 44100, 60.0))


def _band_limit(s, sr):
    S = np.fft.rfft(s)
    S[np.fft.rfftfreq(len(s), 1 / sr) > 0.45 * sr] = 0
    return np.fft.irfft(S, len(s))


def _periodic(shape, ph, f0, sr, points: int = 1 << 14):
    """``shape(ph)`` (a 2 pi-periodic waveform) with only its harmonics below 0.45 ``sr``: the
    Fourier series of one period, summed at the phases ``ph``. A waveform with a corner or a jump
    sampled directly folds its harmonics above the Nyquist frequency back between the harmonics
    (a comb at k f0 +- (sr mod f0)) that no recorded hum has: a sound card's anti-aliasing
    filter removes them before sampling."""
    c = np.fft.rfft(shape(2 * np.pi * np.arange(points) / points)) / points
    K = min(len(c) - 1, int(0.45 * sr / f0))
    z = np.exp(1j * ph)
    zk = np.ones_like(z)
    out = np.full(ph.shape, c[0].real)
    for k in range(1, K + 1):
        zk *= z
        out += 2 * (c[k] * zk).real
    return out


def _waveform(kind, t, f0, rng, sr):
    ph = 2 * np.pi * f0 * t + rng.uniform(0, 2 * np.pi)
    if kind == "saturated":
        return _periodic(lambda p: np.tanh(3 * np.sin(p)), ph, f0, sr)
    if kind == "dimmer":
        cut = rng.uniform(1.2, 2.2)
        return _periodic(lambda p: np.where(np.mod(p, np.pi) > cut, np.sin(p), 0.0), ph, f0, sr)
    if kind == "rectified":
        return _periodic(lambda p: np.abs(np.sin(p)) - 2 / np.pi, ph, f0, sr)
    phases = rng.uniform(0, 2 * np.pi, 7)
    s = sum(np.cos(k * ph + phases[k - 1]) / k for k in range(1, 8))
    return _band_limit(s, sr)


def make(kind, host, sr, nominal, seed, snr_db=0.0, dur=30.0):
    """(host, hum, f0) of one case."""
    rng = np.random.default_rng(seed)
    n = int(dur * sr)
    t = np.arange(n) / sr
    h = {"tonal": lambda: cases.tonal_host(n, sr, rng, nominal), "speech": lambda: cases.speech_host(n, sr, rng)}[host]()
    f0 = nominal * (1 + rng.uniform(-3e-4, 3e-4))
    rng_again = copy.deepcopy(rng)          # the same waveform once more, at shifted times (a jump)
    hum = _waveform(kind, t, f0, rng, sr)
    if kind == "switched":
        hum *= np.clip((t - 8) / 0.05, 0, 1) * np.clip((22 - t) / 0.05, 0, 1)
    elif kind == "load":
        hum *= 1 + 0.4 * np.sin(2 * np.pi * 0.5 * t + rng.uniform(0, 2 * np.pi))
    elif kind == "steps":
        hum *= np.repeat(rng.uniform(0.3, 1.5, int(dur / 5) + 1), int(5 * sr))[:n]
    elif kind in ("phase_jump", "splice"):
        jump, at = (0.25, 15.0) if kind == "phase_jump" else (rng.uniform(0.05, 0.95), rng.uniform(6.0, 24.0))
        hum = np.where(t < at, hum, _waveform(kind, t + jump / f0, f0, rng_again, sr))
    g = np.sqrt(np.mean(h ** 2) / np.mean(hum ** 2) / 10 ** (snr_db / 10))
    hum = hum * g
    peak = np.abs(h + hum).max()
    return 0.8 * h / peak, 0.8 * hum / peak, f0


def run(seed0: int, kinds=KINDS, log=print, draws: int = 1, anchors: bool = True):
    from odnn_sep.audio import denoise

    rows, gains = [], {"odnn-sep": [], "MNE spectrum_fit": [], "iirnotch": []}
    for kind, draw in ((k, d) for k in kinds for d in range(draws)):
        for host, sr, nominal in HOSTS:
            seed = seed0 + KINDS.index(kind) + 10 * draw
            h, hum, f0 = make(kind, host, sr, nominal, seed)
            y = h + hum
            t0 = time.perf_counter()
            r = denoise(y, sr)
            t_ours = time.perf_counter() - t0
            lines = [k * f0 for k in range(1, 16) if k * f0 < 0.45 * sr]
            g = {"odnn-sep": gain_db(h, hum, r.y),
                 "MNE spectrum_fit": gain_db(h, hum, run_mne(y, sr, lines)) if anchors else float("nan"),
                 "iirnotch": gain_db(h, hum, run_iirnotch(y, sr, lines)) if anchors else float("nan")}
            for m, v in g.items():
                gains[m].append(v)
            followed = r.info.get("level_followed_s")
            row = [kind, f"{host}, {sr / 1000:g} kHz, {nominal:g} Hz", seed, f"{g['odnn-sep']:.1f}",
                   f"{g['MNE spectrum_fit']:.1f}", f"{g['iirnotch']:.1f}",
                   f"{followed:g} s" if followed else "-", f"{len(r.line_names)}", f"{t_ours:.2f}"]
            rows.append(row)
            log(" | ".join(str(v) for v in row))
    return rows, gains


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed0", type=int, default=100, help="100: development; 500: evaluation")
    ap.add_argument("--kinds", default=",".join(KINDS))
    ap.add_argument("--draws", type=int, default=1,
                    help="cases per kind and host (seeds seed0 + kind index + 10 x draw)")
    ap.add_argument("--no-anchors", action="store_true", help="odnn-sep only (no section written)")
    ap.add_argument("--write", action="store_true", help="write the BENCHMARKS.md section")
    args = ap.parse_args()
    if not 1 <= args.draws <= 50:
        ap.error("--draws must be 1-50")
    rows, gains = run(args.seed0, args.kinds.split(","), draws=args.draws, anchors=not args.no_anchors)
    from _bench_md import md_table, write_section

    head = ["kind", "host", "seed", "odnn-sep gain dB", "MNE spectrum_fit (true lines)", "iirnotch (true lines)",
            "level followed at", "lines removed", "odnn-sep s"]
    summ = "; ".join(f"{m}: median {np.median(v):.1f}, worst {np.min(v):.1f} dB" for m, v in gains.items())
    ahead = sum(all(gains["odnn-sep"][i] > gains[m][i] for m in gains if m != "odnn-sep")
                for i in range(len(rows)))
    body = (__doc__.split("\n\n", 1)[1].split("    python")[0].rstrip() + "\n\n" + md_table(head, rows)
            + f"\n\n**Summary** ({len(rows)} cases, seeds {args.seed0}+): {summ}; odnn-sep ahead of both anchors "
            f"on {ahead}/{len(rows)}.\n")
    print(body)
    if args.write and not args.no_anchors:
        write_section("audio_levels", "Audio hum removal: a second generator (hum waveforms and levels)",
                      f"python recipes/bench_audio_levels.py --seed0 {args.seed0} --write", body)


if __name__ == "__main__":
    main()
