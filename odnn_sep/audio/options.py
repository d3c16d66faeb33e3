"""The options of :func:`~odnn_sep.audio.denoise`: one frozen :class:`DenoiseOptions`, validated
once (:meth:`DenoiseOptions.validated`) with one-line errors naming the option."""
from __future__ import annotations

import numbers
import sys
from dataclasses import dataclass, replace

import numpy as np

from odnn_sep.errors import InputError, check_option, check_type

BLOCK_S_RANGE = (0.1, 60.0)   # fit block length limits (s)


@dataclass(frozen=True)
class DenoiseOptions:
    """Every option of :func:`~odnn_sep.audio.denoise` (see there for their meaning).

    Built as given by the caller; :meth:`validated` returns the checked, normalised copy that the
    pipeline uses (``mains`` 'auto' or Hz, ``harmonics`` 'auto', N or a sorted list, ``tones`` a
    tuple of Hz, ``block_s`` 'auto' or seconds).

    Examples
    --------
    >>> DenoiseOptions(mains="60", tones=[1000]).validated(8000).mains
    60.0
    >>> DenoiseOptions(block_s=0.01).validated(8000)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: block_s must be between 0.1 and 60 s; got 0.01
    """

    mains: object = "auto"
    harmonics: object = "auto"
    tones: tuple = ()
    block_s: object = "auto"
    solver: str = "exact"
    alpha: float = 1e-3
    max_hz: float | None = None
    progress: bool = False
    random_state: object = 0

    def validated(self, sr) -> DenoiseOptions:
        """The options checked against the sample rate ``sr`` (InputError naming the first bad one)."""
        mains = parse_mains(self.mains, sr)
        harmonics = parse_harmonics(self.harmonics)
        tones = tuple(parse_tones(self.tones, sr))
        max_hz = parse_max_hz(self.max_hz, sr)
        check_option("solver", self.solver, ("exact", "network"))
        block_s = parse_block_s(self.block_s)
        check_type("alpha", self.alpha, numbers.Real, "a number between 0 and 1")
        if not 0 < float(self.alpha) < 1:
            raise InputError(f"alpha must be between 0 and 1 (a significance level); got {self.alpha!r}")
        return replace(self, mains=mains, harmonics=harmonics, tones=tones, max_hz=max_hz, block_s=block_s)

    @property
    def auto_block(self) -> bool:
        """Whether the block length is the data's choice."""
        return self.block_s == "auto"


def parse_block_s(block_s):
    """``'auto'`` or a block length in seconds within :data:`BLOCK_S_RANGE`."""
    if isinstance(block_s, str) and block_s.strip().lower() == "auto":
        return "auto"
    try:
        v = float(block_s)
    except (TypeError, ValueError):
        raise InputError(f"block_s must be 'auto' or a duration in seconds; got {block_s!r}") from None
    if not np.isfinite(v) or v * 10 < 1.0 or v > BLOCK_S_RANGE[1]:
        raise InputError(f"block_s must be between 0.1 and 60 s; got {block_s!r}")
    return v


def parse_mains(mains, sr):
    """``'auto'`` or a fundamental in Hz below Nyquist."""
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
    """``'auto'``, a count N or a sorted list of harmonic numbers."""
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
    """Tone frequencies (Hz) strictly between 0 and Nyquist."""
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
    """A tqdm bar on stderr when enabled and stderr is a terminal, else None."""
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
