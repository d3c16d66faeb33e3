"""Count channels given a harmonic that is not there: a pure 50 Hz hum in white noise.

Two channels (hum amplitude 2 and 1, unit white noise), cleaned by ``denoise_channels`` at three sample
rates, over a range of seeds; prints, per rate, how many channels got a harmonic other than the first.

    python recipes/probe_audio_false_harmonic.py --seeds 100:200
"""
from __future__ import annotations

import argparse

import numpy as np

from odnn_sep.audio.channels import denoise_channels


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="100:200", help="first:last (last excluded)")
    args = ap.parse_args()
    s0, s1 = (int(v) for v in args.seeds.split(":"))
    if not 0 <= s0 < s1 or s1 - s0 > 10_000:
        ap.error("--seeds needs first:last with 0 <= first < last and at most 10000 seeds")
    for sfreq, n in ((250.0, 2500), (500.0, 5000), (1000.0, 10000)):
        t = np.arange(n) / sfreq
        false, total, extra = 0, 0, {}
        for seed in range(s0, s1):
            rng = np.random.default_rng(seed)
            x = rng.standard_normal((2, n)) + np.outer([2.0, 1.0], np.cos(2 * np.pi * 50 * t))
            _, rep = denoise_channels(x, sfreq=sfreq, return_report=True)
            for ch in rep["channels"]:
                total += 1
                wrong = [k for k in ch["harmonics"] if k != 1]
                false += bool(wrong)
                for k in wrong:
                    extra[k] = extra.get(k, 0) + 1
        print(f"{sfreq:g} Hz, {n} samples: {false} of {total} channels with a false harmonic {extra}", flush=True)


if __name__ == "__main__":
    main()
