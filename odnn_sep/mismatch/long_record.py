"""Long records: the fits run on an evenly spaced subsample of bounded size, never on every sample.

The cost of the analysis grows with the samples fitted: every Jacobian is ``n x q`` and is
decomposed many times, and the frequencies an effect may take (a periodic force, a pickup) reach up
to the record's Nyquist frequency, so a dense record lets the optimiser try forces the ODE solver
must follow with tiny steps. A 20 000-point oscillator ran for more than ten minutes.

A record longer than the ``fit_samples`` limit (:mod:`odnn_sep.limits`, 2000) is therefore
analysed on every ``q``-th sample. A plain subsample keeps the noise of one sample per point, so
its intervals and tests are those of the subsample: wider than the full record could give, never
overconfident. It is taken only when it cannot alias: the record's content (periodogram bins far
above the white-noise level, of the values and of every input) must lie below the subsample's
Nyquist frequency by a margin. When the content is too fast for a subsample of that size, a
denser one (up to :data:`HARD_FACTOR` times the limit) is taken; beyond that the record is refused
with a one-line error that says to analyse a window.
"""
from __future__ import annotations

from contextvars import ContextVar

import numpy as np

from odnn_sep.errors import InputError

# a periodogram bin above this many times the white-noise level is content (exp(-25) per bin by chance)
CONTENT_FACTOR = 25.0
# the subsample's Nyquist frequency stays this far above the highest content
NYQUIST_MARGIN = 1.5
# a record whose content needs a subsample larger than this many times the limit is refused
HARD_FACTOR = 4
# set while a subsample is analysed: the subsample is fitted as it is, never subsampled again
_ON_SUBSAMPLE: ContextVar[bool] = ContextVar("on_subsample", default=False)


def content_top(t, y) -> float:
    """Highest frequency of ``y``'s content: periodogram bins above :data:`CONTENT_FACTOR` noise levels.

    The white-noise level is read off the upper half of the band (a long record's content lies far
    below its Nyquist frequency; where it does not, no subsample is taken anyway). Irregular times
    are first interpolated onto an even grid of as many points (only for this check).

    Parameters
    ----------
    t : array_like
        Increasing sample times.
    y : array_like
        Samples.

    Returns
    -------
    float
        Frequency in cycles per unit of ``t``; 0 when nothing stands above the noise.

    Examples
    --------
    >>> t = np.linspace(0, 20, 20000); rng = np.random.default_rng(0)
    >>> round(content_top(t, np.cos(2 * np.pi * 0.3 * t) + 0.01 * rng.normal(size=t.size)), 1)
    0.3
    >>> content_top(t, rng.normal(size=t.size))
    0.0
    >>> content_top(t, np.cos(2 * np.pi * 0.3 * t)) < 25   # no noise: the window's side lobes over the resolution
    True
    """
    from odnn_sep.mismatch.resolution import resolution
    t = np.asarray(t, float)
    y = y_in = np.asarray(y, float)
    n = len(y)
    grid = np.linspace(t[0], t[-1], n)
    y = np.interp(grid, t, y)
    u = (grid - grid[0]) / max(float(grid[-1] - grid[0]), 1e-300)
    y = y - np.polyval(np.polyfit(u, y, 1), u)     # a trend's leakage is not content
    p = np.abs(np.fft.rfft(y * np.hanning(n))) ** 2
    f = np.fft.rfftfreq(n, float(grid[1] - grid[0]))
    upper = p[len(p) // 2:]
    level = float(np.median(upper)) / np.log(2.0)  # the median of an exponential is ln 2 of its mean
    # a record without noise (a simulation): its resolution is the noise (resolution.py), so rounding
    # and the window's far side lobes are not content
    level = max(level, resolution(y_in) ** 2 * float(np.sum(np.hanning(n) ** 2)), 1e-300)
    hot = np.nonzero(p[2:] > CONTENT_FACTOR * level)[0]   # the first bins hold the window's own leakage
    return float(f[hot[-1] + 2]) if hot.size else 0.0


def subsample_step(t, y, inputs=None, *, limit=None) -> int:
    """The step ``q`` of the evenly spaced subsample a long record is fitted on (1: every sample).

    Parameters
    ----------
    t, y : array_like
        The record.
    inputs : dict name -> array, optional
        Measured inputs sampled with ``y``; their content must survive the subsample too.
    limit : int, optional
        Samples to fit at most (default: the ``fit_samples`` limit, ``ODNN_SEP_MAX_FIT_SAMPLES``).

    Returns
    -------
    int

    Raises
    ------
    odnn_sep.errors.InputError
        When the record's content is too fast for a subsample of at most ``HARD_FACTOR * limit`` samples.

    Examples
    --------
    >>> t = np.linspace(0, 20, 20000); rng = np.random.default_rng(0)
    >>> y = np.cos(2 * np.pi * 0.3 * t) + 0.01 * rng.normal(size=t.size)
    >>> subsample_step(t, y), subsample_step(t[:1500], y[:1500])
    (10, 1)
    """
    from odnn_sep.limits import DEFAULTS
    from odnn_sep.limits import limit as current_limit
    n = len(y)
    cap = int(current_limit("fit_samples")) if limit is None else int(limit)
    if n <= cap:
        return 1
    q = int(np.ceil(n / cap))
    t = np.asarray(t, float)
    top = max([content_top(t, y)] + [content_top(t, u) for u in (inputs or {}).values()])
    if top > 0:
        fs = (n - 1) / float(t[-1] - t[0])
        q = min(q, max(1, int(fs / (2 * NYQUIST_MARGIN * top))))
    if int(np.ceil(n / q)) > HARD_FACTOR * cap:
        var = DEFAULTS["fit_samples"][0]
        keep = cap * q / n * float(t[-1] - t[0])
        raise InputError(f"the record has {n} samples with content up to {top:.4g} per time unit: a subsample "
                         f"that keeps it needs {int(np.ceil(n / q))} samples, above {HARD_FACTOR} x the limit of "
                         f"{cap}; analyse a window of it (--start/--duration, e.g. --duration {keep:.4g}) or "
                         f"raise {var}")
    return q


def explain_on_subsample(model, t, y, options):
    """explain() of a long time series on every ``q``-th sample, with a note; None when fitted as given.

    Hum records keep their own decimation (:mod:`odnn_sep.mismatch.rate`, the audio engine), fields
    and joint series are fitted as given.

    Parameters
    ----------
    model : str or Model
        What explain() was given.
    t, y : array_like
        The caller's record.
    options : dict
        explain()'s keyword options (``inputs``, an array ``disturbance`` and ``aux`` are subsampled alike).

    Returns
    -------
    MismatchResult or None

    Examples
    --------
    >>> t = np.linspace(0, 0.6, 6000); rng = np.random.default_rng(0)
    >>> y = 2.0 - 4.905 * t ** 2 + 0.001 * rng.normal(size=t.size)
    >>> res = explain_on_subsample("freefall", t, y, {})
    >>> len(res.y), res.notes[0].split(":")[0], round(res.final_fit.params["g"], 2)
    (2000, 'long record', 9.81)
    >>> explain_on_subsample("freefall", t[:100], y[:100], {}) is None
    True
    """
    q = _step(model, t, y, options)
    if q == 1:
        return None
    from odnn_sep.mismatch.explain import explain
    n = len(y)
    keep = np.arange(0, n, q)
    opts = dict(options)
    if opts.get("inputs"):
        opts["inputs"] = {k: np.asarray(v)[keep] for k, v in opts["inputs"].items()}
    if opts.get("aux") is not None:
        aux = opts["aux"]
        opts["aux"] = {k: np.asarray(v)[keep] for k, v in aux.items()} if isinstance(aux, dict) \
            else np.asarray(aux)[keep]
    if isinstance(opts.get("disturbance"), np.ndarray):
        opts["disturbance"] = opts["disturbance"][keep]
    if options.get("progress"):
        import sys
        print(f"long record: {n} samples; fitting one sample in {q} ({len(keep)})", file=sys.stderr, flush=True)
    token = _ON_SUBSAMPLE.set(True)
    try:
        res = explain(model, np.asarray(t)[keep], np.asarray(y)[keep], **opts)
    finally:
        _ON_SUBSAMPLE.reset(token)
    res.subsample = {"step": q, "record": n}
    full = full_record_rms(res, np.asarray(t, float), np.asarray(y, float), with_inputs=bool(opts.get("inputs")))
    if full is not None:
        res.notes.insert(0, f"residual RMS over all {n} samples of the record: {full:.4g} (over the {len(res.y)} "
                            f"fitted: {(res.final_fit or res.calibration.fit).rms:.4g})")
    res.notes.insert(0, f"long record: fitted on one sample in {q} ({len(keep)} of {n}; the limit is "
                        f"ODNN_SEP_MAX_FIT_SAMPLES), whose intervals and tests are those of the subsample; the "
                        f"record's content lies below the subsample's Nyquist frequency, so nothing is aliased")
    return res


def full_record_rms(res, t, y, *, with_inputs=False):
    """RMS residual of a subsample's final fit over every sample of the record, or None where it is not cheap.

    The model is evaluated at every time (one evaluation) and its fitted disturbance, smooth and
    resolved by the subsample, is carried to every time by a cubic spline. Not done when the
    analysed record does not start with the record's first sample (its initial state refers to
    another time) or when measured inputs drive the model (known at the subsample only).

    Parameters
    ----------
    res : MismatchResult
        The result of the subsample.
    t, y : ndarray
        The whole record.
    with_inputs : bool
        Whether inputs drove the model.

    Returns
    -------
    float or None

    Examples
    --------
    >>> from odnn_sep.mismatch import explain
    >>> t = np.linspace(0, 100, 3000); y = 20 + 70 * np.exp(-0.03 * t) + 0.1 * np.random.default_rng(0).normal(size=3000)
    >>> res = explain("cooling", t[::2], y[::2])
    >>> round(full_record_rms(res, t, y), 2)
    0.1
    """
    from odnn_sep.errors import ModelIntegrationError
    fit = res.final_fit or res.calibration.fit
    t_fit = np.asarray(res.t, float)
    if with_inputs or np.ndim(t_fit) != 1 or len(t_fit) < 4 or t_fit[0] != t[0]:
        return None
    try:
        pred = np.asarray(fit.model.predict(t, fit.params), float)
    except ModelIntegrationError:
        return None
    d = np.asarray(fit.disturbance, float) if fit.disturbance is not None else np.zeros(0)
    if d.shape == t_fit.shape and np.any(d):
        from scipy.interpolate import CubicSpline
        pred = pred + CubicSpline(t_fit, d)(t)
    r = y - pred
    return float(np.sqrt(np.mean(r[np.isfinite(r)] ** 2))) if np.any(np.isfinite(r)) else None


def _step(model, t, y, options):
    """The subsample step for this call, 1 when the case is not a long single time series."""
    from odnn_sep.mismatch.model import Model
    from odnn_sep.mismatch.presets import PRESETS
    if _ON_SUBSAMPLE.get():
        return 1
    if np.ndim(t) != 1 or np.ndim(y) != 1 or len(np.asarray(y)) != len(np.asarray(t)):
        return 1      # fields, and malformed input explain() reports itself
    if isinstance(model, Model):
        if model.family == "hum" or model.ndim != 1 or hasattr(getattr(model, "preset", None), "series_times"):
            return 1
    elif str(model) in PRESETS and PRESETS[str(model)].family == "hum":
        return 1
    try:
        t = np.asarray(t, float)
        y = np.asarray(y, float)
    except (TypeError, ValueError):
        return 1
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(y)) and np.all(np.diff(t) > 0)):
        return 1
    return subsample_step(t, y, options.get("inputs"))


def subsample_series(series, *, limit=None):
    """Series of a joint fit, each on its own evenly spaced subsample so that together they stay in the limit.

    Every series gets an equal share of the ``fit_samples`` limit; a series within its share is
    kept whole, a longer one is subsampled as a single record would be (:func:`subsample_step`).

    Parameters
    ----------
    series : dict
        ``{name: (t, y)}``.
    limit : int, optional
        Samples to fit at most in all (default: the ``fit_samples`` limit).

    Returns
    -------
    series : dict
        ``{name: (t, y)}``, subsampled where needed.
    note : str or None
        What was done, in words; None when every series is kept whole.

    Examples
    --------
    >>> t = np.linspace(0, 100, 3000); rng = np.random.default_rng(0)
    >>> s = {"a": (t, 20 + 70 * np.exp(-0.03 * t) + 0.1 * rng.normal(size=3000)), "b": (t[:50], t[:50])}
    >>> out, note = subsample_series(s)
    >>> len(out["a"][0]), len(out["b"][0]), note.split(";")[0]
    (1000, 50, 'long series: a fitted on one sample in 3 (1000 of 3000)')
    """
    from odnn_sep.limits import limit as current_limit
    cap = int(current_limit("fit_samples")) if limit is None else int(limit)
    share = max(cap // max(len(series), 1), 1)
    out, said = {}, []
    for name, (t, y) in series.items():
        t, y = np.asarray(t, float), np.asarray(y, float)
        q = subsample_step(t, y, limit=share) if len(t) == len(y) and np.all(np.diff(t) > 0) else 1
        if q > 1:
            keep = np.arange(0, len(t), q)
            said.append(f"{name} fitted on one sample in {q} ({len(keep)} of {len(t)})")
            t, y = t[keep], y[keep]
        out[name] = (t, y)
    if not said:
        return out, None
    return out, ("long series: " + ", ".join(said) + f"; each series' share of the limit is {share} samples "
                 "(ODNN_SEP_MAX_FIT_SAMPLES), and the intervals are those of the subsamples")


# hum harmonics a model may carry: each adds two columns to every solve of the fit (a 4000-sample
# record took 28 s of CPU with 30 harmonics, 47 s with 39; its cost grows with samples x harmonics^2)
MAX_HUM_HARMONICS = 20


def check_hum_harmonics(model, t, params):
    """Refuse a hum model whose ``harmonics`` exceed :data:`MAX_HUM_HARMONICS` or reach the Nyquist frequency.

    A harmonic at or above the Nyquist frequency is not in the record at all (its columns alias onto
    lower ones), and the cost of a fit grows with the square of the count.

    Parameters
    ----------
    model : str or Model
        What explain() was given (anything but the hum preset passes).
    t : array_like
        Sample times (s).
    params : dict or None
        The starting values given (``harmonics``, ``f0``).

    Raises
    ------
    odnn_sep.errors.InputError

    Examples
    --------
    >>> t = np.arange(4000) / 4000.0
    >>> check_hum_harmonics("hum", t, {"harmonics": 12})
    >>> check_hum_harmonics("hum", t, {"harmonics": 40, "f0": 50})
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --param harmonics=40 is above the limit of 20 hum harmonics (each adds two parameters to every fit); give at most 20
    >>> check_hum_harmonics("hum", t[:400] * 10, {"harmonics": 5, "f0": 50})
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --param harmonics=5 puts harmonic 5 at 250 Hz, at or above the record's Nyquist frequency (200 Hz): it is not in the record; give at most 3
    """
    from odnn_sep.mismatch.model import Model
    start = dict(model.start) if isinstance(model, Model) else {}
    start.update({k: v for k, v in (params or {}).items() if not isinstance(v, str)})
    family = model.family if isinstance(model, Model) else str(model)
    if family != "hum" or "harmonics" not in start or np.ndim(t) != 1 or len(t) < 2:
        return
    if getattr(getattr(model, "preset", None), "baseband", False):
        return     # the audio engine's demodulated bands: their low rate is not the recording's
    H = int(float(start["harmonics"]))
    if H > MAX_HUM_HARMONICS:
        raise InputError(f"--param harmonics={H} is above the limit of {MAX_HUM_HARMONICS} hum harmonics (each "
                         f"adds two parameters to every fit); give at most {MAX_HUM_HARMONICS}")
    t = np.asarray(t, float)
    nyq = 0.5 / float(np.median(np.diff(t)))
    f0 = float(start.get("f0", 50.0))
    if H * f0 >= nyq:
        raise InputError(f"--param harmonics={H} puts harmonic {H} at {H * f0:.4g} Hz, at or above the record's "
                         f"Nyquist frequency ({nyq:.4g} Hz): it is not in the record; give at most "
                         f"{max(int(np.ceil(nyq / f0)) - 1, 1)}")
