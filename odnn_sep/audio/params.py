"""Validation of the options of :func:`~odnn_sep.audio.denoise` (one-line errors naming the option)."""
from __future__ import annotations

import sys

import numpy as np

from odnn_sep.errors import InputError


def parse_mains(mains, sr):
    if isinstance(mains, str) and mains.strip().lower() == "auto":
        return "auto"
    try:
        v = float(mains)
    except (TypeError, ValueError):
        raise InputError(f"mains must be 'auto', 50, 60 or a frequency in Hz; got {mains!r}") from None
    if not np.isfinite(v) or v <= 0:
        raise InputError(f"mains must be a positive frequency in Hz; got {mains!r}")
    if v >= sr / 2:
        raise InputError(f"mains={v:g} Hz is at or above the Nyquist frequency ({sr / 2:g} Hz for sr={sr}); "
                         f"choose a fundamental below {sr / 2:g} Hz")
    return v


def parse_harmonics(harmonics):
    if isinstance(harmonics, str) and harmonics.strip().lower() == "auto":
        return "auto"
    if isinstance(harmonics, str) and "," in harmonics:  # the CLI's "1,3,5"
        harmonics = [h for h in harmonics.split(",") if h.strip()]
    if isinstance(harmonics, (list, tuple)):
        # an explicit set of harmonic numbers
        if not harmonics:
            raise InputError("harmonics must be 'auto', a positive integer or a non-empty list of them; got []")
        return sorted({parse_harmonics(h) for h in harmonics})
    try:
        v = int(harmonics)
        ok = v == float(harmonics) and v >= 1
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise InputError(f"harmonics must be 'auto', a positive integer or a list of them (1,3,5); "
                         f"got {harmonics!r}")
    return v


def parse_tones(tones, sr):
    out = []
    for t in tones or ():
        try:
            v = float(t)
        except (TypeError, ValueError):
            raise InputError(f"tone must be a frequency in Hz; got {t!r}") from None
        if not np.isfinite(v) or v <= 0 or v >= sr / 2:
            raise InputError(f"tone={t!r} Hz must be between 0 and the Nyquist frequency ({sr / 2:g} Hz)")
        out.append(v)
    return out


def progress_bar(enabled: bool, total: int, desc: str):
    if not enabled or not sys.stderr.isatty():
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="smp", unit_scale=True, file=sys.stderr, leave=False)


def parse_max_hz(max_hz, sr):
    """``None`` (0.95 x Nyquist) or a positive frequency in Hz."""
    if max_hz is None:
        return None
    try:
        v = float(max_hz)
    except (TypeError, ValueError):
        raise InputError(f"max_hz must be a frequency in Hz; got {max_hz!r}") from None
    if not np.isfinite(v) or v <= 0:
        raise InputError(f"max_hz must be a positive frequency in Hz (the highest harmonic to consider); "
                         f"got {max_hz!r}")
    return v
