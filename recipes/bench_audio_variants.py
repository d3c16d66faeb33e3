"""Hum removal on variants of the first generator: knobs another author could set otherwise.

The population of ``bench_audio.py`` draws 5-12 hum harmonics, 20-40 s inputs and tonal hosts
with half of their notes near a hum harmonic. Each variant changes one of those choices:

- ``dense``: tonal hosts only, every note with a partial 0.5-3 Hz from a hum harmonic, 5 voices;
- ``manyh``: 15-40 hum harmonics;
- ``short``: 6-15 s inputs;
- ``long``: 60-120 s inputs.

odnn-sep against MNE spectrum_fit, iirnotch and (at 16 kHz and below) pactools, given the true lines
(``--anchors``), per case:
SNR gain / content damage (dB) and the lines removed that are not hum.

    python recipes/bench_audio_variants.py dense --seed0 2000 --cases 12            # development
    python recipes/bench_audio_variants.py dense --seed0 5000 --cases 12 --anchors  # evaluation

Seeds 2000-4999 are for development; 5000 and up are for reporting.
"""
from __future__ import annotations

import argparse
import functools
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _audio_cases as cases  # noqa: E402
import _audio_population as population  # noqa: E402

VARIANTS = ("dense", "manyh", "short", "long")


def _drawn(key: int, lo: float, hi: float, integer: bool = False):
    """A case_spec that redraws one field from the case's own seed (offset by ``key``)."""
    def draw(spec):
        rng = np.random.default_rng(spec["seed"] + key)
        return int(rng.integers(lo, hi + 1)) if integer else float(rng.uniform(lo, hi))
    return draw


def apply(variant: str) -> None:
    """Set the generator's knobs for ``variant`` (module state of ``_audio_cases``)."""
    base = cases.case_spec
    if variant == "dense":
        cases.tonal_host = functools.partial(cases.tonal_host, near_frac=1.0, voices=5)
        cases.HOSTS = ("tonal",) * 3
        return
    field, draw = {"manyh": ("kmax", _drawn(5, 15, 40, integer=True)),
                   "short": ("dur", _drawn(6, 6.0, 15.0)),
                   "long": ("dur", _drawn(7, 60.0, 120.0))}[variant]

    def spec(i, seed0, quick=False):
        s = base(i, seed0, quick)
        s[field] = draw(s)
        return s

    cases.case_spec = spec


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("variant", choices=VARIANTS)
    ap.add_argument("--seed0", type=int, default=2000, help="first seed (2000-4999 development, 5000+ evaluation)")
    ap.add_argument("--cases", type=int, default=12)
    ap.add_argument("--anchors", action="store_true", help="also run MNE spectrum_fit, iirnotch and pactools")
    ap.add_argument("--no-pactools", action="store_true", help="with --anchors: leave pactools out (40-80 s a case)")
    a = ap.parse_args(argv)
    apply(a.variant)
    if a.no_pactools:
        population.PACTOOLS_MAX_SR = 0
    rows, stats = population.run_population(a.cases, a.seed0, quick=False, anchors=a.anchors,
                                            log=lambda s: print(s, flush=True))
    g = np.array(stats["odnn-sep"]["gain"])
    print(f"{a.variant}, seeds {a.seed0}-{a.seed0 + a.cases - 1}: odnn-sep median {np.median(g):.1f} dB, worst "
          f"{g.min():.1f} dB; lines removed that are not hum on the tonal hosts {sum(stats['false_tonal'])}, "
          f"on all {sum(stats['false_all'])}; ahead of every anchor run on {sum(stats['ahead'])} of {a.cases}")
    for m in population.ANCHORS:
        if m in stats:
            ga = np.array(stats[m]["gain"])
            print(f"  {m}: median {np.median(ga):.1f} dB, worst {ga.min():.1f} dB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
