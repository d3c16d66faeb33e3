"""EEG/MEG input for :func:`odnn_sep.audio.denoise`: channels-first arrays with a float ``sfreq``, or an
MNE ``Raw`` (MNE is optional and imported only when a Raw is passed).

The output has the input's type: a Raw copy with the picked channels cleaned (``info`` untouched),
or an array of the input's shape and dtype. By default every picked channel goes through the
single-channel engine on its own (one channel in memory at a time besides the output); with
``spatial=True`` the hum's spatial components are found first (spatial.py).

Examples
--------
>>> import numpy as np
>>> from odnn_sep.audio import denoise
>>> sfreq = 512.5
>>> t = np.arange(int(20 * sfreq)) / sfreq
>>> rng = np.random.default_rng(0)
>>> brain = rng.standard_normal((3, t.size))
>>> hum = np.outer([2.0, 1.5, 1.0], np.cos(2 * np.pi * 50.02 * t))
>>> clean, report = denoise(brain + hum, sfreq=sfreq, return_report=True)
>>> clean.shape, clean.dtype
((3, 10250), dtype('float64'))
>>> [(ch["nominal_hz"], ch["harmonics"], round(ch["mains_hz"], 1)) for ch in report["channels"]]
[(50.0, [1], 50.0), (50.0, [1], 50.0), (50.0, [1], 50.0)]
>>> band = slice(990, 1011)                      # 49.5-50.5 Hz (0.05 Hz bins)
>>> power = lambda a: np.sum(np.abs(np.fft.rfft(a)[:, band]) ** 2, axis=1)
>>> bool(np.all(power(clean - brain) < 0.1 * power(hum)))    # > 10 dB of the hum removed
True
"""
from __future__ import annotations

import logging
import sys

import numpy as np

from odnn_sep import limits
from odnn_sep.audio.channel_engine import ENGINE_OPTIONS, check_engine_options, clean_columns
from odnn_sep.audio.channel_picks import resolve_picks
from odnn_sep.errors import InputError

log = logging.getLogger(__name__)

CHANNEL_OPTIONS = ("sfreq", "picks", "channel_axis", "spatial", "return_report")


def is_raw(obj) -> bool:
    """True for an MNE Raw; never imports MNE (an object of MNE's has already imported it).

    Parameters
    ----------
    obj : object
        Anything.

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> is_raw(np.zeros((2, 100)))
    False
    """
    if sys.modules.get("mne") is None:
        return False
    from mne.io import BaseRaw

    return isinstance(obj, BaseRaw)


def is_channel_call(y, sr, channel_options: dict) -> bool:
    """Whether :func:`denoise` was called the EEG/MEG way (a Raw, or any channel option given).

    Otherwise checks what the audio call needs (an array and an integer ``sr``).

    Parameters
    ----------
    y : array or mne.io.Raw
        The data passed to :func:`denoise`.
    sr : int, float or None
        The ``sr`` passed to :func:`denoise`.
    channel_options : dict
        The keyword options beyond the engine's (``sfreq``, ``picks``, ...).

    Returns
    -------
    bool

    Raises
    ------
    TypeError
        For an unknown keyword option.
    InputError
        For an audio call without a usable integer ``sr``.

    Examples
    --------
    >>> import numpy as np
    >>> y = np.zeros(8000)
    >>> is_channel_call(y, 8000, {}), is_channel_call(y, None, {"sfreq": 512.5})
    (False, True)
    >>> is_channel_call(y, 512.5, {})
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: sr=512.5 is not an integer audio rate; ...
    """
    unknown = sorted(set(channel_options) - set(CHANNEL_OPTIONS))
    if unknown:
        raise TypeError(f"denoise() got unexpected keyword argument(s) {', '.join(map(repr, unknown))}")
    if is_raw(y) or any(v is not None and v is not False for v in channel_options.values()):
        return True
    check_signal_type(y)
    if sr is None:
        raise InputError("denoise needs the sampling rate: sr=... for audio (samples along the first axis), "
                         "sfreq=... for an EEG/MEG array (channels first), or pass an MNE Raw")
    try:
        fractional = np.isfinite(float(sr)) and float(sr) > 0 and float(sr) != int(float(sr))
    except (TypeError, ValueError):
        fractional = False
    if fractional:
        raise InputError(f"sr={sr!r} is not an integer audio rate; for EEG/MEG data at a fractional rate pass "
                         f"sfreq={sr!r} (channels-first array)")
    return False


def check_signal_type(y) -> None:
    """Refuse anything that is neither an array (or list) nor an MNE Raw, saying what to pass.

    Parameters
    ----------
    y : object
        The data passed to :func:`denoise`.

    Raises
    ------
    InputError
        When ``y`` is not an array, list, tuple or Raw.

    Examples
    --------
    >>> check_signal_type([0.0, 1.0]) is None
    True
    >>> check_signal_type("hum.wav")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: y must be a NumPy array or an MNE Raw; got str
    """
    if isinstance(y, (np.ndarray, list, tuple)) or is_raw(y):
        return
    hint = ""
    if type(y).__module__.startswith("mne"):
        hint = " (for MNE Epochs or Evoked, remove the hum from the continuous Raw before epoching)"
    raise InputError(f"y must be a NumPy array or an MNE Raw; got {type(y).__name__}{hint}")


def check_sfreq(sfreq) -> float:
    """A finite, positive sampling frequency in Hz (fractional rates such as 512.5 are fine).

    Parameters
    ----------
    sfreq : float, str or None
        The sampling frequency given.

    Returns
    -------
    float

    Raises
    ------
    InputError
        When it is missing, not a number, or not finite and positive.

    Examples
    --------
    >>> check_sfreq("512.5")
    512.5
    >>> check_sfreq(0)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: sfreq must be a finite, positive sampling frequency in Hz; got 0
    """
    if sfreq is None:
        raise InputError("sfreq is missing: an EEG/MEG array needs its sampling frequency, e.g. "
                         "denoise(data, sfreq=512.5)")
    try:
        v = float(sfreq)
    except (TypeError, ValueError):
        raise InputError(f"sfreq must be a sampling frequency in Hz; got {sfreq!r}") from None
    if not np.isfinite(v) or v <= 0:
        raise InputError(f"sfreq must be a finite, positive sampling frequency in Hz; got {sfreq!r}")
    return v


def denoise_channels(y, sr=None, *, sfreq=None, picks=None, channel_axis=None, spatial=False,
                     return_report=False, **engine_options):
    """Remove mains hum from the picked channels of an EEG/MEG array or MNE Raw.

    Parameters
    ----------
    y : ndarray, shape (n_channels, n_times) or (n_times,), or mne.io.Raw
        Not modified. A 2-D array may also be samples-first: the shorter axis is taken as the
        channels unless ``channel_axis`` says otherwise (a square array needs ``channel_axis``).
    sr, sfreq : float
        Sampling frequency in Hz (either name; a Raw's own is used and must agree).
    picks : str, int, list, slice or None
        Channels to clean, as in MNE (names, indices, types such as ``'eeg'``, ``'meg'``,
        ``'data'``); the others are returned unchanged. None: all data channels.
    channel_axis : {0, 1}, optional
        The axis of the channels in a 2-D array.
    spatial : bool
        Find the hum's spatial components across the picked channels first (spatial.py); needs
        at least 2 channels.
    return_report : bool
        Also return a dict of what was found per channel.
    **engine_options
        ``mains``, ``harmonics``, ``tones``, ``block_s``, ``solver``, ``alpha``, ``max_hz``,
        ``progress``, ``random_state`` as in :func:`odnn_sep.audio.denoise`.

    Returns
    -------
    Same type as ``y`` (and the report dict when ``return_report``).

    Examples
    --------
    >>> import numpy as np
    >>> sfreq = 250.0; t = np.arange(2500) / sfreq
    >>> rng = np.random.default_rng(0)
    >>> x = rng.standard_normal((2, t.size)) + np.outer([2.0, 1.0], np.cos(2 * np.pi * 50 * t))
    >>> out, rep = denoise_channels(x, sfreq=sfreq, return_report=True)
    >>> out.shape, rep["method"], rep["picks"], [ch["harmonics"] for ch in rep["channels"]]
    ((2, 2500), 'per-channel', [0, 1], [[1], [1]])
    """
    bad = sorted(set(engine_options) - set(ENGINE_OPTIONS))
    if bad:
        raise TypeError(f"denoise() got unexpected keyword argument(s) {', '.join(map(repr, bad))}")
    if sfreq is not None and sr is not None and float(sfreq) != float(sr):
        raise InputError(f"sr={sr!r} and sfreq={sfreq!r} disagree; pass one of them")
    rate = sfreq if sfreq is not None else sr
    if is_raw(y):
        out, report = _denoise_raw(y, rate, picks, bool(spatial), engine_options)
    else:
        out, report = _denoise_array(y, rate, picks, channel_axis, bool(spatial), engine_options)
    _log_summary(report)
    return (out, report) if return_report else out


def channels_view(arr: np.ndarray, channel_axis) -> np.ndarray:
    """A (n_channels, n_times) view of a 1-D or 2-D array (the orientation rule of :func:`denoise_channels`).

    Parameters
    ----------
    arr : ndarray
        1-D (one channel) or 2-D data.
    channel_axis : {0, 1, -1, -2} or None
        The axis of the channels; None: the shorter axis (a square array is refused).

    Returns
    -------
    ndarray
        A view (no copy) of ``arr``, channels first.

    Raises
    ------
    InputError
        For other dimensions, a square array without ``channel_axis``, or a bad axis.

    Examples
    --------
    >>> import numpy as np
    >>> channels_view(np.zeros(10), None).shape, channels_view(np.zeros((10, 3)), None).shape
    ((1, 10), (3, 10))
    >>> channels_view(np.zeros((4, 4)), 1).shape
    (4, 4)
    """
    if arr.ndim == 1:
        return arr[None, :]
    if arr.ndim != 2:
        raise InputError(f"data must be 1-D (one channel) or 2-D (channels x times); got shape {arr.shape} "
                         f"(for epochs, clean the continuous data before epoching)")
    if channel_axis is None:
        if arr.shape[0] == arr.shape[1]:
            raise InputError(f"data has shape {arr.shape}: a square array does not say which axis holds the "
                             f"channels; pass channel_axis=0 (channels first) or channel_axis=1")
        return arr if arr.shape[0] < arr.shape[1] else arr.T
    if channel_axis not in (0, 1, -1, -2):
        raise InputError(f"channel_axis must be 0 or 1 for a 2-D array; got {channel_axis!r}")
    return arr if channel_axis in (0, -2) else arr.T


def _denoise_array(y, rate, picks, channel_axis, spatial, opts):
    check_signal_type(y)
    arr = np.asarray(y)
    if arr.dtype.kind not in "fiu":
        raise InputError(f"data must be real numbers (float or integer); got dtype {arr.dtype}")
    sfreq = check_sfreq(rate)
    view = channels_view(arr, channel_axis)
    idx = resolve_picks(picks, view.shape[0])
    _check_picked(view, idx, sfreq, opts, spatial)
    out = arr.copy()
    out_view = channels_view(out, channel_axis)  # same shape, so the same orientation as view
    report = {"sfreq": sfreq, "picks": idx.tolist(), "method": "spatial" if spatial else "per-channel"}
    if spatial:
        from odnn_sep.audio.spatial import spatial_hum

        x = view[idx].astype(np.float64)
        hum, report["spatial"], report["channels"] = spatial_hum(x, sfreq, opts)
        np.subtract(x, hum, out=x)
        del hum
        out_view[idx] = _cast(x, arr.dtype)
        return out, report
    report["channels"] = []
    for c in idx:
        x = view[c].astype(np.float64)
        hum, summary = clean_columns(x, sfreq, opts)
        out_view[c] = _cast(x - hum, arr.dtype)
        report["channels"].append(summary)
    return out, report


def _denoise_raw(raw, rate, picks, spatial, opts):
    sfreq = float(raw.info["sfreq"])
    if rate is not None and float(rate) != sfreq:
        raise InputError(f"sfreq={rate!r} differs from the Raw's own ({sfreq:g} Hz); leave sfreq out for a Raw")
    idx = resolve_picks(picks, len(raw.ch_names), raw.ch_names, raw.get_channel_types())
    check_engine_options(opts, sfreq, raw.n_times)
    _check_count(len(idx), spatial)
    out = raw.copy().load_data()
    names = [raw.ch_names[i] for i in idx]
    report = {"sfreq": sfreq, "picks": names, "method": "spatial" if spatial else "per-channel", "channels": []}

    def clean_one(x):
        _check_nan(x[None, :], [names[len(report["channels"])]])
        hum, summary = clean_columns(x, sfreq, opts)
        report["channels"].append(summary)
        return x - hum

    def clean_all(x):
        from odnn_sep.audio.spatial import spatial_hum

        _check_nan(x, names)
        hum, report["spatial"], report["channels"] = spatial_hum(x, sfreq, opts)
        return x - hum

    # apply_function hands over one channel at a time (channel_wise) or the picked block
    out.apply_function(clean_all if spatial else clean_one, picks=idx, channel_wise=not spatial)
    return out, report


def _check_picked(view, idx, sfreq, opts, spatial):
    check_engine_options(opts, sfreq, view.shape[1])
    _check_count(len(idx), spatial)
    if view.dtype.kind == "f":
        _check_nan((view[i] for i in idx), [int(i) for i in idx])


def _check_count(n: int, spatial: bool) -> None:
    limits.check("channels", n, "number of channels to clean",
                 hint="check that the array is channels x times, or pick fewer channels (picks=)")
    if spatial and n < 2:
        raise InputError(f"spatial=True needs at least 2 channels sharing the hum; got {n}: "
                         f"pick more channels or leave spatial out")


def _check_nan(x, labels) -> None:
    """Refuse NaN/inf in the rows of ``x``, one row at a time (no copy of the whole block)."""
    for row, label in zip(x, labels, strict=True):
        bad = ~np.isfinite(row)
        if bad.any():
            s = int(np.argmax(bad))
            kind = "NaN" if np.isnan(row[s]) else "inf"
            raise InputError(f"channel {label!r} contains {int(bad.sum())} NaN or inf value(s) (first: {kind} at "
                             f"sample {s}); interpolate them or crop that stretch before removing the hum")


def _cast(v: np.ndarray, dtype) -> np.ndarray:
    if np.dtype(dtype).kind == "f":
        return v                    # the assignment into the output casts
    info = np.iinfo(dtype)
    r = np.rint(v)
    n = int(np.count_nonzero((r < info.min) | (r > info.max)))
    if n:
        log.warning("%d sample(s) clipped to the %s range after removing the hum; pass float data to keep them",
                    n, np.dtype(dtype).name)
    return np.clip(r, info.min, info.max).astype(dtype)


def _log_summary(report) -> None:
    chans = report["channels"]
    found = [i for i, s in enumerate(chans) if s["harmonics"] or s.get("tones_hz") or s.get("spatial_harmonics")]
    if not found:
        log.warning("no mains hum found on any of the %d picked channel(s); the output equals the input",
                    len(chans))
    else:
        log.info("hum removed on %d of %d picked channel(s)", len(found), len(chans))
