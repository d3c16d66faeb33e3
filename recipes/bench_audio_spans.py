"""Hum over part of the input only: switched on and off, or in bursts (``humspans.py``), against MNE
and iirnotch in the same run; and hum-free inputs, where nothing may be removed.

    python recipes/bench_audio_spans.py --seeds 7 8 9           # evaluation seeds (5, 6: development)
    python recipes/bench_audio_spans.py --seeds 5 6 --no-anchors
    python recipes/bench_audio_spans.py --hum-free 0 20         # hum-free hosts of rngs 0..19

Cases: the hosts of ``_audio_hosts.py`` (plucked string, drum loop, sweep, voice with vibrato, pink
noise, bass note beside the fundamental), their hum shapes, drifts, rates (8-48 kHz) and input SNR
(-5..+5 dB, over the time the hum sounds), the hum ``gated`` (on once, between 10 % and 90 % of a
10-30 s input) or in ``bursts`` (2-4 bursts of 1.5-4 s), each edge a 10 ms ramp. Per case the SNR
gain (dB) of odnn-sep (its defaults: the lines are found by the tool) and of MNE ``spectrum_fit`` and
``scipy.signal.iirnotch`` given the true lines. The median and worst case are printed, not the mean.

Hum-free inputs: the six hosts of ``_audio_hosts.py``, two tonal hosts of ``_audio_cases.py`` (A440
notes near the harmonics) and one held note near a harmonic (3-10 s, 5-8 partials) over pink noise,
per rng; with rng 0 also the hum-free recordings of ``bench_audio.py``. Each should come out
unchanged; every input from which lines were removed is printed.
"""
from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _audio_cases as cases  # noqa: E402
import _audio_hosts as hosts  # noqa: E402

EVENTS = ("gated", "bursts")


def make_case(seed: int, i: int):
    """Case ``i`` of ``seed``: host ``i % 6``, event ``i // 6 % 2``; the clean host, the hum, the rate
    and a description with the true lines."""
    rng = np.random.default_rng((seed, i, 4711))
    name, event = hosts.HOSTS[i % len(hosts.HOSTS)], EVENTS[(i // len(hosts.HOSTS)) % len(EVENTS)]
    shape = hosts.SHAPES[int(rng.integers(len(hosts.SHAPES)))]
    sr, mains = int(rng.choice(hosts.RATES)), float(rng.choice([50.0, 60.0]))
    n = int(rng.uniform(10, 30) * sr)
    t = np.arange(n) / sr
    x = hosts.host(name, n, sr, rng, mains)
    f, drift = hosts.fundamental(n, sr, rng, mains)
    gate = np.zeros(n)
    if event == "gated":
        a, b = sorted(rng.uniform(0.1, 0.9, 2) * t[-1])
        gate[(t > a) & (t < b)] = 1.0
    else:
        for _ in range(int(rng.integers(2, 5))):
            s0 = int(rng.uniform(0, 0.8) * n)
            gate[s0: s0 + int(rng.uniform(1.5, 4) * sr)] = 1.0
    ramp = max(1, int(0.01 * sr))
    gate = np.convolve(gate, np.ones(ramp) / ramp, "same")
    ph = 2 * np.pi * np.cumsum(f) / sr
    amps = hosts.harmonic_amplitudes(shape, sr, mains)
    hum = gate * sum(a * np.cos(k * ph + rng.uniform(0, 2 * np.pi)) for k, a in amps.items())
    snr = rng.uniform(-5, 5)
    if np.any(gate > 0.5):
        hum *= np.std(x) / np.std(hum[gate > 0.5]) * 10 ** (-snr / 20)
    return 0.1 * x, 0.1 * hum, sr, dict(host=name, event=event, shape=shape, drift=drift, seconds=n / sr,
                                         on_s=float(np.sum(gate > 0.5) / sr), snr_db=snr,
                                         lines=[k * float(np.mean(f)) for k in amps])


def _gain(hum, out, host) -> float:
    return float(10 * np.log10(np.sum(hum ** 2) / max(np.sum((out - host) ** 2), 1e-300)))


def run(seeds, anchors: bool):
    from odnn_sep.audio import denoise

    g_all, m_all, i_all = [], [], []
    for seed in seeds:
        for i in range(2 * len(hosts.HOSTS)):
            x, hum, sr, d = make_case(seed, i)
            r = denoise(x + hum, sr)
            g = _gain(hum, r.y, x)
            an = [np.nan, np.nan]
            if anchors:
                from bench_audio import run_iirnotch, run_mne
                an = [_gain(hum, fn(x + hum, sr, d["lines"]), x) for fn in (run_mne, run_iirnotch)]
            spans = ", ".join(f"{s['start_s']:.1f}-{s['end_s']:.1f}" for s in r.info.get("hum_spans") or [])
            print(f"{seed}/{i} | {d['host']} | {d['event']} | {d['shape']} | {sr / 1000:g} kHz | {d['seconds']:.0f} s, "
                  f"hum {d['on_s']:.1f} s | {d['drift']} | {d['snr_db']:+.1f} | odnn-sep {g:.1f} | MNE {an[0]:.1f} | "
                  f"iirnotch {an[1]:.1f} | lines {len(r.line_names)} | spans {spans or '-'}", flush=True)
            g_all.append(g), m_all.append(an[0]), i_all.append(an[1])
    g, m, i = map(np.array, (g_all, m_all, i_all))
    print(f"- odnn-sep: median {np.median(g):.1f} dB, worst {g.min():.1f} dB ({len(g)} cases)")
    if anchors:
        print(f"- MNE spectrum_fit (true lines): median {np.median(m):.1f} dB, worst {m.min():.1f} dB")
        print(f"- iirnotch Q=30 (true lines): median {np.median(i):.1f} dB, worst {i.min():.1f} dB")
        print(f"- odnn-sep ahead of MNE on {int(np.sum(g > m))} of {len(g)}, of both anchors on "
              f"{int(np.sum((g > m) & (g > i)))}")


def hum_free(first: int, last: int):
    from odnn_sep.audio import denoise

    found, n = 0, 0

    def check(name, y, sr):
        nonlocal found, n
        r = denoise(y, sr)
        n += 1
        if r.line_names:
            found += 1
            print(f"lines removed from hum-free {name}: {', '.join(r.line_names[:8])}"
                  f"{' ...' if len(r.line_names) > 8 else ''}; spans {r.info.get('hum_spans') or '-'}", flush=True)

    for s in range(first, last):
        rng = np.random.default_rng((s, 777))
        for h in hosts.HOSTS:
            sr, mains = int(rng.choice(hosts.RATES)), float(rng.choice([50.0, 60.0]))
            check(f"{h}/{s}", 0.1 * hosts.host(h, int(rng.uniform(8, 30) * sr), sr, rng, mains), sr)
        for near in (0.5, 0.9):
            sr, mains = int(rng.choice([8000, 16000, 44100])), float(rng.choice([50.0, 60.0]))
            check(f"tonal{near}/{s}", 0.1 * cases.tonal_host(int(rng.uniform(10, 30) * sr), sr, rng, mains,
                                                            near_frac=near), sr)
        sr = int(rng.choice([8000, 16000, 44100]))
        y = cases.noise_host(int(rng.uniform(12, 30) * sr), sr, rng, "pink") * 0.05
        near = [f for f in hosts.A440 if f > 90 and min(abs(f - k * m) for m in (50, 60) for k in range(1, 30)) < 1.5]
        f, dur = float(rng.choice(near)), rng.uniform(3, 10)
        t0 = rng.uniform(0, len(y) / sr - dur)
        t = np.arange(int(dur * sr)) / sr
        env = np.minimum(1, np.minimum(t, dur - t) / 0.05)
        note = sum(np.cos(2 * np.pi * j * f * t + rng.uniform(0, 6.3)) / j for j in range(1, int(rng.integers(5, 9))))
        y[int(t0 * sr): int(t0 * sr) + len(t)] += 0.3 * env * note
        check(f"held note {f:.1f} Hz, {dur:.1f} s/{s}", y, sr)
    if first == 0:
        for name, y, sr in cases.clean_hosts(False):
            check(f"recording {name}", y, sr)
    print(f"- lines removed from {found} of {n} hum-free inputs")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[7, 8, 9], help="case seeds (development: 5, 6)")
    ap.add_argument("--no-anchors", action="store_true")
    ap.add_argument("--hum-free", type=int, nargs=2, metavar=("FIRST", "STOP"),
                    help="instead: hum-free inputs of rngs FIRST..STOP-1")
    args = ap.parse_args()
    logging.disable(logging.WARNING)
    if args.hum_free:
        hum_free(*args.hum_free)
    else:
        run(args.seeds, not args.no_anchors)


if __name__ == "__main__":
    main()
