"""The audio engine (:func:`odnn_sep.audio.api.denoise`) run on EEG/MEG channels at any sampling rate.

The engine counts in integer sample rates. A recording at a fractional rate (``sfreq=512.5``) is
handed to it at the nearest integer rate ``sr`` with every frequency option scaled by ``sr/sfreq``:
the samples are the same, only their time labels change, so a 50 Hz line sits at
``50 * sr/sfreq`` Hz for the engine (0.1 % away at 512.5 Hz, inside its +-1 % refinement), and the
frequencies it reports are scaled back.
"""
from __future__ import annotations

import contextlib
import logging

import numpy as np

from odnn_sep.audio import options as engine_options
from odnn_sep.errors import InputError

ENGINE_OPTIONS = ("mains", "harmonics", "tones", "block_s", "solver", "alpha", "max_hz", "progress",
                  "random_state")
MIN_SECONDS = 0.2   # the engine's own minimum (pipeline.py)


def engine_rate(sfreq: float) -> tuple[int, float]:
    """The integer rate the engine runs at and the factor ``sr / sfreq`` frequencies are scaled by.

    Parameters
    ----------
    sfreq : float
        True sampling frequency (Hz), possibly fractional.

    Returns
    -------
    sr : int
        ``round(sfreq)``, at least 1.
    scale : float
        ``sr / sfreq``.

    Examples
    --------
    >>> engine_rate(512.5)
    (512, 0.9990243902439024)
    """
    sr = max(1, int(round(sfreq)))
    return sr, sr / sfreq


def check_engine_options(opts: dict, sfreq: float, n_times: int) -> None:
    """Check the frequency options against the true ``sfreq`` (so messages quote the user's values).

    Parameters
    ----------
    opts : dict
        Engine options (``mains``, ``tones``, ``max_hz``, ...).
    sfreq : float
        Sampling frequency (Hz).
    n_times : int
        Samples per channel.

    Raises
    ------
    InputError
        For too short an input or a bad frequency option.

    Examples
    --------
    >>> check_engine_options({"mains": 50}, 512.5, 5000) is None
    True
    >>> check_engine_options({}, 512.5, 50)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: input is too short (50 samples = 0.098 s at 512.5 Hz) to resolve mains hum; ...
    """
    if n_times < MIN_SECONDS * sfreq:
        raise InputError(f"input is too short ({n_times} samples = {n_times / sfreq:.3f} s at {sfreq:g} Hz) to "
                         f"resolve mains hum; pass at least {MIN_SECONDS:g} s of data")
    mains = engine_options.parse_mains(opts.get("mains", "auto"), sfreq)
    tones = engine_options.parse_tones(opts.get("tones", ()), sfreq)
    max_hz = engine_options.parse_max_hz(opts.get("max_hz"), sfreq)
    if not tones:
        # here, once, at the true rate: each engine call runs at a rate scaled to an integer, and
        # its own check would speak of that rate, once per channel (clean_columns drops it)
        engine_options.check_testable(mains, engine_options.parse_harmonics(opts.get("harmonics", "auto")),
                                      max_hz, sfreq)


def scaled_options(opts: dict, scale: float) -> dict:
    """Engine options with every frequency multiplied (and every duration divided) by ``scale``.

    Parameters
    ----------
    opts : dict
        Engine options; not modified.
    scale : float
        ``sr / sfreq`` (see :func:`engine_rate`).

    Returns
    -------
    dict
        A copy with ``mains``, ``tones``, ``max_hz`` and ``block_s`` scaled ('auto' kept).

    Examples
    --------
    >>> scaled_options({"mains": 50, "tones": [10], "block_s": 8.0}, 0.5)
    {'mains': 25.0, 'tones': [5.0], 'block_s': 16.0}
    >>> scaled_options({"mains": "auto"}, 0.5)
    {'mains': 'auto', 'tones': []}
    """
    out = dict(opts)
    if scale == 1.0:
        return out
    mains = out.get("mains", "auto")
    if not (isinstance(mains, str) and mains.strip().lower() == "auto"):
        out["mains"] = float(mains) * scale
    out["tones"] = [float(t) * scale for t in out.get("tones", ()) or ()]
    if out.get("max_hz") is not None:
        out["max_hz"] = float(out["max_hz"]) * scale
    block_s = out.get("block_s", "auto")
    if not (isinstance(block_s, str) and block_s.strip().lower() == "auto"):
        out["block_s"] = float(block_s) / scale
    return out


def clean_columns(x: np.ndarray, sfreq: float, opts: dict) -> tuple[np.ndarray, dict]:
    """Remove the hum from the columns of ``x`` (n_times,) or (n_times, k) with one engine call.

    Columns share the engine's tracked fundamental and line choice; each gets its own amplitudes and
    phases. Each column is scaled to unit RMS for the call (EEG in volts is ~1e-5) and back.

    Parameters
    ----------
    x : (n_times,) or (n_times, k) array
        Samples, float64.
    sfreq : float
        Sampling frequency (Hz), possibly fractional.
    opts : dict
        Engine options (``mains``, ``harmonics``, ...; see :data:`ENGINE_OPTIONS`).

    Returns
    -------
    hum : ndarray, shape of ``x``
        The fitted hum (``x - hum`` is the cleaned signal).
    summary : dict
        ``mains_hz`` (true Hz or None), ``nominal_hz``, ``harmonics``, ``line_freqs_hz``,
        ``level_before_db``, ``level_after_db`` (per line, per column).

    Examples
    --------
    >>> sfreq = 250.0; t = np.arange(2500) / sfreq
    >>> x = np.random.default_rng(0).standard_normal(t.size) + 2 * np.cos(2 * np.pi * 50 * t)
    >>> hum, summary = clean_columns(x, sfreq, {})
    >>> hum.shape, summary["nominal_hz"], summary["harmonics"], round(summary["mains_hz"], 1)
    ((2500,), 50.0, [1], 50.0)
    """
    from odnn_sep.audio.api import denoise  # the engine; imported here (api imports this module lazily)

    sr, scale = engine_rate(sfreq)
    rms = np.sqrt(np.mean(np.square(x - x.mean(axis=0)), axis=0))
    rms = np.where(rms > 0, rms, 1.0)
    with quiet_no_hum_warnings():
        res = denoise(x / rms, sr, **scaled_options(opts, scale))
    hum = np.asarray(res.hum) * rms
    summary = {"mains_hz": None if not res.harmonics or res.mains_hz is None else res.mains_hz / scale,
               "nominal_hz": res.nominal_hz if res.harmonics else None,
               "harmonics": list(res.harmonics),
               "tones_hz": [t / scale for t in res.tones],
               "line_freqs_hz": [f / scale for f in res.line_freqs],
               "level_before_db": [d["level_db"] for d in res.levels_before],
               "level_after_db": [d["level_db"] for d in res.levels_after]}
    return hum, summary


class _DropNoHum(logging.Filter):
    def filter(self, record):
        msg = record.getMessage()
        # the second: said once by check_engine_options
        return "no mains hum found" not in msg and engine_options.OUT_OF_REACH not in msg


@contextlib.contextmanager
def quiet_no_hum_warnings():
    """Silence the engine's per-call "no mains hum found" warning: over many channels the caller
    reports once how many channels had none.

    Returns
    -------
    context manager
        The filters are removed on exit.

    Examples
    --------
    >>> import logging
    >>> with quiet_no_hum_warnings():
    ...     logging.getLogger("odnn_sep.audio.pipeline").warning("no mains hum found in the input")
    """
    flt = _DropNoHum()
    names = [n for n in list(logging.root.manager.loggerDict) if n.startswith("odnn_sep.audio")]
    loggers = [logging.getLogger(n) for n in names]
    for lg in loggers:
        lg.addFilter(flt)
    try:
        yield
    finally:
        for lg in loggers:
            lg.removeFilter(flt)
