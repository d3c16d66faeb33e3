"""The options of :func:`~odnn_sep.audio.denoise`: one frozen :class:`DenoiseOptions`, validated
once (:meth:`DenoiseOptions.validated`) with one-line errors naming the option."""
from __future__ import annotations

import logging
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
        lowest = 0.99 * (mains if isinstance(mains, (int, float)) else 50.0)
        if max_hz is not None and max_hz < lowest:
            # every line would be cut off: "no hum found" would be the option's doing, not the data's
            raise InputError(f"max_hz={max_hz:g} Hz is below the mains fundamental ({lowest / 0.99:g} Hz): no line "
                             f"could be removed; raise it (it is the highest harmonic frequency to consider)")
        if not tones:
            check_testable(mains, harmonics, max_hz, sr)
        check_type("alpha", self.alpha, numbers.Real, "a number between 0 and 1")
        if not 0 < float(self.alpha) < 1:
            raise InputError(f"alpha must be between 0 and 1 (a significance level); got {self.alpha!r}")
        return replace(self, mains=mains, harmonics=harmonics, tones=tones, max_hz=max_hz, block_s=block_s)

    @property
    def auto_block(self) -> bool:
        """Whether the block length is the data's choice."""
        return self.block_s == "auto"


def families_in_reach(mains, harmonics, max_hz, sr) -> list[float]:
    """The hum fundamentals asked for (50 and 60 Hz for ``'auto'``) with a line the detection
    can test at ``sr`` under ``max_hz`` (:func:`~odnn_sep.audio.detect.candidate_harmonics`).

    Examples
    --------
    >>> families_in_reach("auto", "auto", None, 8000), families_in_reach("auto", "auto", None, 128)
    ([50.0, 60.0], [50.0])
    """
    from odnn_sep.audio import detect as _detect

    fams = (50.0, 60.0) if mains == "auto" else (float(mains),)
    return [f for f in fams if _detect.candidate_harmonics(f, sr, harmonics, max_hz)]


def check_testable(mains, harmonics, max_hz, sr) -> None:
    """InputError when no line of the hum asked for can be tested at ``sr`` (a line needs a few Hz
    under the Nyquist frequency) or under ``max_hz``: "no hum found" would then be the rate's or
    the option's doing, not the data's (it said "tested 60 Hz" of a 128 Hz recording, where the
    line at 60 Hz is never looked at). Names the alias of 50 and 60 Hz hum where that can be tested.

    Parameters
    ----------
    mains, harmonics, max_hz
        As validated (``'auto'`` or Hz; ``'auto'``, N or a list; Hz or None).
    sr : int
        Sample rate (Hz).

    Raises
    ------
    InputError
        When no harmonic of ``mains`` (of 50 or of 60 Hz for ``'auto'``) can be tested.

    Examples
    --------
    >>> check_testable("auto", "auto", None, 250)
    >>> check_testable("auto", "auto", None, 100)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: no line of 50 or 60 Hz hum can be tested at sr=100: ... 60 Hz hum folds to 40 Hz here (--mains 40 removes it)
    >>> check_testable(50.0, "auto", 51.0, 8000)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: no line of 50 Hz hum can be tested under max_hz=51 Hz ... raise max_hz ...
    """
    from odnn_sep.audio import detect as _detect

    if families_in_reach(mains, harmonics, max_hz, sr):
        if isinstance(harmonics, list):
            _warn_named_out_of_reach(mains, harmonics, max_hz, sr)
        return
    what = "50 or 60 Hz" if mains == "auto" else f"{mains:g} Hz"
    if isinstance(harmonics, list):
        what += f" (harmonics {', '.join(map(str, harmonics))})"
    if max_hz is not None and max_hz < _detect.top_hz(sr):
        raise InputError(f"no line of {what} hum can be tested under max_hz={max_hz:g} Hz (a line needs about "
                         f"2 Hz of room under it): raise max_hz (the highest harmonic frequency to consider)")
    # where the hum shows at this rate, folded about the Nyquist frequency: a line the user can name
    folds = []
    for f in ((50.0, 60.0) if mains == "auto" else (float(mains),)):
        a = round(abs(f - sr * round(f / sr)), 3)
        if a != f and a > 0 and families_in_reach(a, "auto", None, sr):
            folds.append(f"{f:g} Hz hum folds to {a:g} Hz here (--mains {a:g} removes it)")
    hint = "; ".join(folds) or "a line there needs an input sampled at a higher rate"
    raise InputError(f"no line of {what} hum can be tested at sr={sr:g}: a line needs about 2 Hz of room under "
                     f"the highest frequency tested, {_detect.top_hz(sr):g} Hz (a little under the Nyquist "
                     f"frequency, {sr / 2:g} Hz); {hint}")


OUT_OF_REACH = "lie above the highest line tested"   # the warning of _warn_named_out_of_reach


def _warn_named_out_of_reach(mains, harmonics: list, max_hz, sr) -> None:
    """A warning naming the harmonics of the list given that lie above the highest line tested
    (they are left out: --harmonics 1,2,190 at 16 kHz removed h1 and h2 without a word on h190)."""
    from odnn_sep.audio import detect as _detect

    f0 = 50.0 if mains == "auto" else float(mains)     # out of reach of 50 Hz: of 60 Hz as well
    kept = set(_detect.candidate_harmonics(f0, sr, harmonics, max_hz))
    out = [k for k in harmonics if k not in kept]
    if out:
        logging.getLogger("odnn_sep.audio").warning(
            "harmonic(s) %s of %g Hz " + OUT_OF_REACH + " (%g Hz at sr=%g%s): left out",
            ", ".join(map(str, out)), f0, _detect.top_hz(sr, max_hz), sr, " and max_hz" if max_hz else "")


def parse_block_s(block_s):
    """``'auto'`` or a block length in seconds within :data:`BLOCK_S_RANGE`.

    Parameters
    ----------
    block_s : str or float
        ``'auto'`` (any case) or a duration in seconds.

    Returns
    -------
    'auto' or float

    Raises
    ------
    InputError
        When it is neither, or outside 0.1-60 s.

    Examples
    --------
    >>> parse_block_s(" Auto "), parse_block_s("16")
    ('auto', 16.0)
    >>> parse_block_s(120)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: block_s must be between 0.1 and 60 s; got 120
    """
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
    """``'auto'`` or a fundamental in Hz below Nyquist.

    Parameters
    ----------
    mains : str or float
        ``'auto'`` (any case) or a frequency in Hz.
    sr : int
        Sample rate (Hz).

    Returns
    -------
    'auto' or float

    Raises
    ------
    InputError
        When it is not a positive frequency below ``sr / 2``.

    Examples
    --------
    >>> parse_mains("AUTO", 8000), parse_mains("60", 8000)
    ('auto', 60.0)
    >>> parse_mains(50, 80)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: mains=50 Hz is at or above the Nyquist frequency (40 Hz for sr=80); ...
    """
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
    """``'auto'``, a count N or a sorted list of harmonic numbers.

    Parameters
    ----------
    harmonics : str, int or sequence of int
        ``'auto'``, a count N (harmonics 1..N), a sequence of harmonic numbers, or the command
        line's comma-separated ``"1,3,5"``.

    Returns
    -------
    'auto', int or list of int
        A list is sorted with duplicates removed.

    Raises
    ------
    InputError
        When a value is not a positive integer.

    Examples
    --------
    >>> parse_harmonics("auto"), parse_harmonics(4.0), parse_harmonics("5,1,3,3")
    ('auto', 4, [1, 3, 5])
    >>> parse_harmonics(0)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: harmonics must be 'auto', a positive integer or a list of them (1,3,5); got 0
    """
    if isinstance(harmonics, (bool, np.bool_)):
        raise InputError(f"harmonics must be 'auto', a positive integer or a list of them (1,3,5); got {harmonics!r}")
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
    """Tone frequencies (Hz) strictly between 0 and Nyquist, each once, in the order given.

    Parameters
    ----------
    tones : float, sequence of float or None
        Tone frequencies (Hz); None or empty for none; one number for one tone.
    sr : int
        Sample rate (Hz).

    Returns
    -------
    list of float

    Raises
    ------
    InputError
        When a tone is not a frequency strictly between 0 and ``sr / 2``, or there are more distinct
        tones than the limit ``tones`` (odnn_sep.limits: every tone is a column of every block's fit).

    Examples
    --------
    >>> parse_tones(["1000", 440, 1000.0], 8000), parse_tones(None, 8000), parse_tones(1000, 8000)
    ([1000.0, 440.0], [], [1000.0])
    >>> parse_tones([5000], 8000)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: tone=5000 Hz must be between 0 and the Nyquist frequency (4000 Hz)
    """
    from odnn_sep import limits

    if isinstance(tones, (int, float, np.integer, np.floating)) and not isinstance(tones, bool):
        tones = [tones]
    out = []
    for t in tones or ():
        try:
            v = float(t)
        except (TypeError, ValueError):
            raise InputError(f"tone must be a frequency in Hz; got {t!r}") from None
        if not np.isfinite(v) or v <= 0 or v >= sr / 2:
            raise InputError(f"tone={t!r} Hz must be between 0 and the Nyquist frequency ({sr / 2:g} Hz)")
        if v not in out:      # a tone given twice is one line (two equal columns make the fit singular)
            out.append(v)
    limits.check("tones", len(out), "the number of tones (--tone)", hint="give the tones that are really there")
    return out


def progress_bar(enabled: bool, total: int, desc: str):
    """A tqdm bar on stderr when enabled and stderr is a terminal, else None.

    Parameters
    ----------
    enabled : bool
        Whether a bar was asked for.
    total : int
        Samples to process (the bar's length).
    desc : str
        The bar's label.

    Returns
    -------
    tqdm.tqdm or None

    Examples
    --------
    >>> progress_bar(False, 1000, "denoise") is None
    True
    """
    if not enabled or not sys.stderr.isatty():
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="smp", unit_scale=True, file=sys.stderr, leave=False)


def parse_max_hz(max_hz, sr):
    """``None`` (0.95 x Nyquist) or a positive frequency in Hz.

    Parameters
    ----------
    max_hz : float or None
        Highest harmonic frequency to consider (Hz).
    sr : int
        Sample rate (Hz); not used by the check.

    Returns
    -------
    float or None

    Raises
    ------
    InputError
        When it is not a positive frequency.

    Examples
    --------
    >>> parse_max_hz(None, 8000) is None, parse_max_hz("1000", 8000)
    (True, 1000.0)
    >>> parse_max_hz(-5, 8000)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: max_hz must be a positive frequency in Hz (the highest harmonic to consider); got -5
    """
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
