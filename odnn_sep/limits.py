"""Limits on every user-controlled size, each with a clear message and an environment variable
that raises it.

| name        | default    | variable                 | what                                           |
|-------------|------------|--------------------------|------------------------------------------------|
| points      | 4 000 000  | ODNN_SEP_MAX_POINTS      | samples of a `separate` signal or field        |
| rows        | 2 000 000  | ODNN_SEP_MAX_ROWS        | samples `mismatch` analyses                    |
| megapixels  | 100        | ODNN_SEP_MAX_MEGAPIXELS  | image size for `unwatermark` (input and mask)  |
| text_chars  | 200        | ODNN_SEP_MAX_TEXT        | length of `unwatermark --text`                 |
| magnitude   | 1e150      | ODNN_SEP_MAX_MAGNITUDE   | largest absolute data value (squares overflow) |
| harmonics   | 200        | ODNN_SEP_MAX_HARMONICS   | highest harmonic number `denoise --harmonics`  |
| tones       | 100        | ODNN_SEP_MAX_TONES       | distinct `denoise --tone` frequencies          |
| channels    | 1024       | ODNN_SEP_MAX_CHANNELS    | channels `denoise` cleans in an EEG/MEG array  |
| in_memory_samples | 50 000 000 | ODNN_SEP_MAX_IN_MEMORY_SAMPLES | frames x channels of `denoise --picks/--spatial` |
| shape_points | 20 000   | ODNN_SEP_MAX_SHAPE_POINTS | points a convex or monotone class is fitted on (`fit/size.py`) |
| fit_samples | 2 000    | ODNN_SEP_MAX_FIT_SAMPLES | samples a `mismatch` time series is fitted on (a longer record: an evenly spaced subsample) |
"""
from __future__ import annotations

import os

from odnn_sep.errors import InputError

DEFAULTS = {
    "points": ("ODNN_SEP_MAX_POINTS", 4_000_000),
    "rows": ("ODNN_SEP_MAX_ROWS", 2_000_000),
    "megapixels": ("ODNN_SEP_MAX_MEGAPIXELS", 100),
    "text_chars": ("ODNN_SEP_MAX_TEXT", 200),
    "magnitude": ("ODNN_SEP_MAX_MAGNITUDE", 1e150),
    "harmonics": ("ODNN_SEP_MAX_HARMONICS", 200),
    "tones": ("ODNN_SEP_MAX_TONES", 100),
    "channels": ("ODNN_SEP_MAX_CHANNELS", 1024),
    "in_memory_samples": ("ODNN_SEP_MAX_IN_MEMORY_SAMPLES", 50_000_000),
    "shape_points": ("ODNN_SEP_MAX_SHAPE_POINTS", 20_000),
    "fit_samples": ("ODNN_SEP_MAX_FIT_SAMPLES", 2_000),
}


def limit(name: str) -> float:
    """The current value of limit ``name`` (its environment variable, else the default).

    Parameters
    ----------
    name : str
        A key of :data:`DEFAULTS` (``"points"``, ``"text_chars"``, ``"harmonics"``, ...).

    Returns
    -------
    float

    Raises
    ------
    odnn_sep.errors.InputError
        When the environment variable is set to something that is not a positive number.

    Examples
    --------
    >>> import os
    >>> limit("text_chars") == float(os.environ.get("ODNN_SEP_MAX_TEXT") or 200)   # default 200 characters
    True
    """
    var, default = DEFAULTS[name]
    raw = os.environ.get(var)
    if raw is None or not raw.strip():
        return default
    try:
        v = float(raw)
    except ValueError:
        raise InputError(f"environment variable {var}={raw!r} is not a number; unset it or give e.g. "
                         f"{var}={default:g}") from None
    if not v > 0:
        raise InputError(f"environment variable {var}={raw!r} must be positive")
    return v


def check(name: str, value: float, what: str, *, hint: str = "") -> None:
    """Raise InputError if ``value`` exceeds limit ``name``; the message says how to raise it.

    Parameters
    ----------
    name : str
        The limit (a key of :data:`DEFAULTS`).
    value : float
        The size to check.
    what : str
        What the size is, for the message (e.g. the option).
    hint : str, optional
        How to reduce the size, added to the message.

    Raises
    ------
    odnn_sep.errors.InputError
        When ``value`` is above the limit.

    Examples
    --------
    >>> check("harmonics", 12, "--harmonics")
    >>> check("harmonics", 500, "--harmonics")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --harmonics is 500, above the limit of 200; to allow it, set ODNN_SEP_MAX_HARMONICS (e.g. ODNN_SEP_MAX_HARMONICS=800)
    """
    lim = limit(name)
    if value > lim:
        var = DEFAULTS[name][0]
        extra = f"; {hint}" if hint else ""
        raise InputError(f"{what} is {value:,.6g}, above the limit of {lim:,.6g}{extra}; "
                         f"to allow it, set {var} (e.g. {var}={max(lim * 4, value):.6g})")


def check_magnitude(name: str, a) -> None:
    """Refuse values so large that sums of squares overflow float64 (a unit or parsing error).

    Parameters
    ----------
    name : str
        The values' name, for the message.
    a : array_like
        Values to check (non-numeric arrays are accepted as they are).

    Raises
    ------
    odnn_sep.errors.InputError
        For values beyond the ``magnitude`` limit.

    Examples
    --------
    >>> check_magnitude("y", [1.0, 2.0])
    >>> check_magnitude("y", [1.0, 1e200])
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: y: 1 value(s) beyond +-1e+150 (first at index 1: 1e+200); ...
    """
    import numpy as np

    a = np.asarray(a)
    if a.size == 0 or not np.issubdtype(a.dtype, np.number):
        return
    with np.errstate(invalid="ignore"):
        big = np.abs(a) > limit("magnitude")
    if big.any():
        i = int(np.argmax(big.ravel()))
        raise InputError(f"{name}: {int(big.sum())} value(s) beyond +-{limit('magnitude'):g} (first at "
                         f"index {i}: {a.ravel()[i]:g}); rescale the data (squares would overflow), or set "
                         f"{DEFAULTS['magnitude'][0]}")
