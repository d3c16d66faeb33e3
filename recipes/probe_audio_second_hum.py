"""Two mains hums in one take (a 50 Hz and a 60 Hz source), and how often the warning that names
the second one fires where there is only one hum or none.

    python recipes/probe_audio_second_hum.py                 # all three parts (about 6 minutes)
    python recipes/probe_audio_second_hum.py --part mixes    # the two-hum mixes only

Parts:
- ``mixes``: ``make_hum_mix`` hosts (20 s, 16 kHz) with a 50 Hz and a 60 Hz hum (seeds 3-8, the
  60 Hz hum at 0.7, 0.3 and 0.1 of its drawn level): the gain (dB, both hums' energy over the
  error) of one run and of a second run on its output with ``--mains`` of the other family, and
  whether the first run warned;
- ``single``: one hum only: the first generator's development cases 1000-1023
  (``_audio_cases.py``) and the third generator's hosts, development seed 7 (``_audio_hosts.py``):
  runs that warn (each is a false warning);
- ``clean``: the hum-free recordings of ``_audio_cases.clean_hosts`` and clean drum loops (rngs
  100-111): runs that warn.
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

from odnn_sep.audio import denoise  # noqa: E402
from odnn_sep.audio.synth import make_hum_mix  # noqa: E402


def _gain(hum, out, host) -> float:
    return float(10 * np.log10(np.sum(hum ** 2) / np.sum((out - host) ** 2)))


def mixes():
    print("| seed | 60 Hz hum x | one run (dB) | warned | second run (dB) |")
    print("|---|---|---|---|---|")
    for seed in range(3, 9):
        _, sr, t50 = make_hum_mix(20.0, 16000, snr_db=0, random_state=seed, mains_hz=50.0)
        _, _, t60 = make_hum_mix(20.0, 16000, snr_db=0, random_state=seed + 100, mains_hz=60.0)
        for g in (0.7, 0.3, 0.1):
            hum = t50["hum"] + g * t60["hum"]
            r = denoise(t50["host"] + hum, sr)
            second = r.info.get("second_hum")
            again = ""
            if second:
                other = 60.0 if r.nominal_hz == 50.0 else 50.0
                again = f"{_gain(hum, denoise(r.y, sr, mains=other).y, t50['host']):.1f}"
            print(f"| {seed} | {g} | {_gain(hum, r.y, t50['host']):.1f} | {'yes' if second else 'no'} | {again} |")


def single():
    warned = total = 0
    for i in range(24):
        y, sr, truth = cases.make_case(cases.case_spec(i, 1000))
        total += 1
        if denoise(y, sr).info.get("second_hum"):
            warned += 1
            print(f"warned: first generator case {1000 + i}")
    for i in range(24):
        x, hum, sr, desc = hosts.make_case(7, i)
        total += 1
        if denoise(x + hum, sr).info.get("second_hum"):
            warned += 1
            print(f"warned: hosts seed 7 case {i} ({desc['host']}, {desc['shape']})")
    print(f"single hum: {warned} of {total} runs warned")


def clean():
    warned = total = 0
    for name, y, sr in cases.clean_hosts():
        total += 1
        if denoise(y, sr).info.get("second_hum"):
            warned += 1
            print(f"warned: {name}")
    for r0 in range(100, 112):
        rng = np.random.default_rng(r0)
        sr = int(rng.choice([8000, 16000, 22050]))
        total += 1
        if denoise(0.3 * hosts.drum_loop(int(rng.uniform(10, 25) * sr), sr, rng), sr).info.get("second_hum"):
            warned += 1
            print(f"warned: drum loop {r0}")
    print(f"hum-free: {warned} of {total} runs warned")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", choices=("mixes", "single", "clean", "all"), default="all")
    args = ap.parse_args()
    logging.getLogger("odnn_sep").setLevel(logging.ERROR)
    for name, fn in (("mixes", mixes), ("single", single), ("clean", clean)):
        if args.part in (name, "all"):
            fn()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
