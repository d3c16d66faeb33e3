"""Hum removal on a third generator's hosts (``_audio_hosts.py``), against MNE and iirnotch in the same run.

    python recipes/bench_audio_hosts.py --seed 21              # 24 cases, writes the audio_hosts section
    python recipes/bench_audio_hosts.py --seed 11 --no-write   # a development seed, printed only

Per case: the SNR gain (dB: hum energy over the energy of output minus clean host) of odnn-sep
(``denoise`` with its defaults: the lines are found by the tool) and of MNE ``spectrum_fit`` and
``scipy.signal.iirnotch`` (Q = 30) given the true lines (they cannot find them); the content change
away from the lines (odnn-sep's output minus the clean host, outside +-1 Hz of every harmonic of the
true fundamental, relative to the host's energy); the fundamental odnn-sep chose. The median and the
worst case are reported, not the mean.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _audio_hosts as hosts  # noqa: E402
import _bench_md  # noqa: E402

N_CASES = 24


def _gain(hum, out, host) -> float:
    return float(10 * np.log10(np.sum(hum ** 2) / max(np.sum((out - host) ** 2), 1e-300)))


def _away_db(host, out, sr, mains_mean) -> float:
    """Energy of ``out - host`` outside +-1 Hz of every harmonic, relative to the host's energy (dB)."""
    E = np.abs(np.fft.rfft(out - host)) ** 2
    f = np.fft.rfftfreq(len(host), 1 / sr)
    near = np.abs(f / mains_mean - np.round(f / mains_mean)) * mains_mean <= 1.0
    near &= f >= mains_mean - 1.0
    H = np.sum(np.abs(np.fft.rfft(host)) ** 2)
    return float(10 * np.log10(max(np.sum(E[~near]), 1e-300) / H))


def run(seed: int, n_cases: int, anchors: bool, log=print):
    from odnn_sep.audio import denoise

    rows, stats = [], []
    for i in range(n_cases):
        x, hum, sr, d = hosts.make_case(seed, i)
        t0 = time.perf_counter()
        r = denoise(x + hum, sr)
        secs = time.perf_counter() - t0
        g = _gain(hum, r.y, x)
        away = _away_db(x, r.y, sr, d["lines"][0])      # every shape has the fundamental first
        an = []
        if anchors:
            from bench_audio import run_iirnotch, run_mne
            for fn in (run_mne, run_iirnotch):
                an.append(_gain(hum, fn(x + hum, sr, d["lines"]), x))
        chosen = "none" if r.mains_hz is None else f"{r.mains_hz:.3f} Hz h{','.join(map(str, r.harmonics[:6]))}" + \
            ("..." if len(r.harmonics) > 6 else "")
        stats.append((g, an))
        rows.append([f"{seed}/{i}", d["host"], d["shape"], f"{d['mains']:.0f} Hz, {d['drift']}", f"{sr / 1000:g} kHz",
                     f"{d['seconds']:.0f} s", f"{d['snr_db']:+.1f}", f"{g:.1f}", f"{away:.0f}",
                     *([f"{a:.1f}" for a in an] if anchors else ["not run", "not run"]), chosen, f"{secs:.1f}"])
        log(" | ".join(rows[-1]))
    return rows, stats


def summary(stats, anchors: bool) -> str:
    g = np.array([s[0] for s in stats])
    lines = [f"odnn-sep: median {np.median(g):.1f} dB, worst {g.min():.1f} dB, "
             f"{int(np.sum(g >= 35))} of {len(g)} at 35 dB or more"]
    if anchors:
        a = np.array([s[1] for s in stats])
        for j, name in enumerate(("MNE spectrum_fit (true lines)", "iirnotch Q=30 (true lines)")):
            lines.append(f"{name}: median {np.median(a[:, j]):.1f} dB, worst {a[:, j].min():.1f} dB")
        ahead = int(np.sum(g > a.max(axis=1)))
        lines.append(f"odnn-sep ahead of both anchors on {ahead} of {len(g)} cases")
    return "\n".join(f"- {s}" for s in lines) + "\n"


HEADER = ["case", "host", "hum", "mains, drift", "rate", "length", "SNR in", "odnn-sep gain",
          "change off the lines (dB re host)", "MNE", "iirnotch", "odnn-sep fundamental", "s"]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=21, help="seed of the cases (development: 7, 11)")
    ap.add_argument("--cases", type=int, default=N_CASES)
    ap.add_argument("--no-anchors", action="store_true")
    ap.add_argument("--no-write", action="store_true", help="print only; leave BENCHMARKS.md alone")
    args = ap.parse_args()
    rows, stats = run(args.seed, args.cases, not args.no_anchors)
    text = summary(stats, not args.no_anchors)
    print(text)
    if not args.no_write:
        body = (__doc__.split("\n\n", 2)[2] + "\n" + text + "\n" + _bench_md.md_table(HEADER, rows))
        _bench_md.write_section("audio_hosts", "Audio hum removal: a third generator's hosts",
                                f"python recipes/bench_audio_hosts.py --seed {args.seed}", body)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
