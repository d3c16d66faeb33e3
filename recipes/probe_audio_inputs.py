"""Inputs a user brings to ``denoise`` that no generator draws: digital silence around and inside
a take, hum clipped by the recorder, arrays far from unit scale, rates too low for the mains
family asked for. One line per case; about a minute.

    python recipes/probe_audio_inputs.py
    PYTHONPATH=<checkout of another version> python recipes/probe_audio_inputs.py   # to compare

Hosts and hum: ``make_hum_mix`` (16 kHz, 20 s, seeds 3 and 5). Gains are the hum's energy over
the energy of (output - clean host), taken where the input sounds.
"""
from __future__ import annotations

import logging
import warnings

import numpy as np

from odnn_sep.audio import denoise
from odnn_sep.audio.synth import make_hum_demo, make_hum_mix
from odnn_sep.errors import InputError


def _db(num, den) -> float:
    return float(10 * np.log10(np.sum(num ** 2) / max(np.sum(den ** 2), 1e-300)))


def silence():
    for seed in (3, 5):
        _, sr, t = make_hum_mix(20.0, 16000, snr_db=0.0, random_state=seed)
        host, hum = t["host"], t["hum"]
        layouts = {"none": [(0, 20)], "3 s of zeros first": ["z3", (0, 20)],
                   "5 s of zeros first, 3 s last": ["z5", (0, 20), "z3"],
                   "3 s of zeros inside": [(0, 10), "z3", (10, 20)],
                   "0.5 s of zeros inside": [(0, 10), "z0.5", (10, 20)]}
        for name, lay in layouts.items():
            hs, hm = [], []
            for p in lay:
                if isinstance(p, str):
                    n = int(float(p[1:]) * sr)
                    hs.append(np.zeros(n))
                    hm.append(np.zeros(n))
                else:
                    hs.append(host[p[0] * sr: p[1] * sr])
                    hm.append(hum[p[0] * sr: p[1] * sr])
            hs, hm = np.concatenate(hs), np.concatenate(hm)
            y = hs + hm
            r = denoise(y, sr)
            zeros = (hs == 0) & (hm == 0)
            left = float(np.abs(r.y[zeros]).max()) if zeros.any() else 0.0
            print(f"silence | seed {seed} | {name} | gain {_db(hm, (r.y - hs)[y != 0]):.1f} dB | "
                  f"largest sample written into the zeros {left:.3g}")


def clipped():
    _, sr, t = make_hum_mix(20.0, 16000, snr_db=0.0, random_state=3)
    host = 0.1 * t["host"]
    for g in (2.0, 5.0, 20.0):
        y = host + g * t["hum"]
        r = denoise(np.clip(y, -1, 1), sr)
        print(f"clipped | hum x{g:g} | {100 * np.mean(np.abs(y) >= 1):.1f} % clipped | error re music "
              f"{_db(r.y - host, host):.1f} dB | warned: {r.info.get('input_clipped') is not None}")


def units():
    y, sr, _ = make_hum_demo(duration_s=4.0, sr=8000)
    for scale in (2.0 ** -100, 2.0 ** -40, 1.0, 2.0 ** 40, 2.0 ** 70):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            r = denoise(y * scale, sr)
        print(f"units | x 2^{int(np.log2(scale))} | lines {','.join(r.line_names) or '-'} | "
              f"NumPy warnings {len(w)}")


def low_rates():
    rng = np.random.default_rng(0)
    for sr, f0, kw in ((96, 60.02, {}), (96, 60.02, {"mains": 36}), (100, 50.0, {}), (128, 60.02, {}),
                       (128, 60.02, {"mains": 60}), (8000, 50.0, {"mains": 50, "max_hz": 49.6}),
                       (250, 50.0, {})):
        t = np.arange(30 * sr) / sr
        host, hum = 0.1 * rng.standard_normal(t.size), 0.1 * np.cos(2 * np.pi * f0 * t + 1)
        try:
            r = denoise(host + hum, sr, **kw)
            out = f"lines {','.join(r.line_names) or '-'} | gain {_db(hum, r.y - host):.1f} dB"
        except InputError as e:
            out = f"error: {e}"
        print(f"rate | {sr} Hz, hum {f0:g} Hz, {kw or 'defaults'} | {out}")


def main() -> int:
    logging.getLogger("odnn_sep").setLevel(logging.ERROR)
    silence()
    clipped()
    units()
    low_rates()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
