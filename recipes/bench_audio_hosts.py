"""Hum removal on a third generator's hosts (``_audio_hosts.py``), against MNE and iirnotch in the same run.

    python recipes/bench_audio_hosts.py --seed 21              # 24 cases, writes the audio_hosts section
    python recipes/bench_audio_hosts.py --seed 11 --no-write   # a development seed, printed only
    python recipes/bench_audio_hosts.py --seed 300 --seeds 32 --case 17 --no-anchors --no-write
                                                 # case 17 (a bass note over a pure hum) of seeds 300-331
    python recipes/bench_audio_hosts.py --loops 200 --seeds 12   # clean drum loops (no hum), rngs 200-211

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


def run(seed: int, n_cases: int, anchors: bool, log=print, cases=None):
    """Rows and (gain, anchor gains) of cases 0..``n_cases``-1 of ``seed``, or of the (seed, case)
    pairs ``cases``."""
    from odnn_sep.audio import denoise

    rows, stats = [], []
    for seed, i in cases if cases is not None else ((seed, i) for i in range(n_cases)):
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


def clean_loops(first: int, count: int, log=print) -> int:
    """Clean drum loops (``hosts.drum_loop``, no hum; 10-25 s at 8, 16 or 22.05 kHz, drawn from rngs
    ``first``.. ``first + count - 1``) through ``denoise``: the lines removed and the change (dB re
    the loop; -inf: output identical). Returns how many were left untouched."""
    from odnn_sep.audio import denoise

    untouched = 0
    for r0 in range(first, first + count):
        rng = np.random.default_rng(r0)
        sr = int(rng.choice([8000, 16000, 22050]))
        x = 0.3 * hosts.drum_loop(int(rng.uniform(10, 25) * sr), sr, rng)
        r = denoise(x, sr)
        change = float(np.sum((r.y - x) ** 2))
        untouched += change == 0
        log(f"loop {r0} | {sr / 1000:g} kHz | {len(x) / sr:.0f} s | lines removed {len(r.harmonics)} | change "
            + (f"{10 * np.log10(change / np.sum(x ** 2)):.1f} dB" if change > 0 else "none"))
    log(f"- left untouched: {untouched} of {count}")
    return untouched


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
    ap.add_argument("--seeds", type=int, default=1, help="with --case: this many seeds from --seed on")
    ap.add_argument("--case", type=int, default=None, help="only this case of each seed (printed only)")
    ap.add_argument("--loops", type=int, default=None, metavar="RNG",
                    help="clean drum loops instead (no hum), rngs RNG.. RNG + --seeds - 1 (printed only)")
    args = ap.parse_args()
    if args.case is not None and not 0 <= args.case < N_CASES:
        ap.error(f"--case must be in 0..{N_CASES - 1}")
    if not 1 <= args.seeds <= 1000:
        ap.error("--seeds must be in 1..1000")
    if args.loops is not None:
        clean_loops(args.loops, args.seeds)
        return 0
    cases = None if args.case is None else [(args.seed + k, args.case) for k in range(args.seeds)]
    rows, stats = run(args.seed, args.cases, not args.no_anchors, cases=cases)
    text = summary(stats, not args.no_anchors)
    print(text)
    if not args.no_write and cases is None:
        body = (__doc__.split("\n\n", 2)[2] + "\n" + text + "\n" + _bench_md.md_table(HEADER, rows))
        _bench_md.write_section("audio_hosts", "Audio hum removal: a third generator's hosts",
                                f"python recipes/bench_audio_hosts.py --seed {args.seed}", body)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
