"""Declared and found disturbances: what the recording carries besides the physics.

A disturbance the user declares (``--disturbance periodic:HZ``, ``lines``, ``slow``, ``none``) is
absorbed exactly: its columns are projected out of every fit (the core engine's ``Subspace``
class), so it can never be named. A disturbance the finder meets on its own (an additive
sinusoid, an offset, a drift: effects whose data cannot be told apart from an additive
component) is fitted like an effect, absorbed into the model, and reported in plain words.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.core.spectrum import spectrum
from odnn_sep.errors import InputError

KINDS_HELP = "auto, slow, none, lines, periodic:HZ (comma-separated, e.g. slow,periodic:3.7)"
MAX_DECLARED_LINES = 20


def parse_disturbance(spec):
    """Parse the ``disturbance`` option into (class, [declared Hz], lines?).

    ``class`` is "auto", "slow" or "none" (the wander class); ``periodic:HZ`` items add known
    line frequencies; ``lines`` asks to absorb every significant spectral line of the residual.

    Parameters
    ----------
    spec : str, ndarray or None
        The option; an array (user columns) or None is passed through.

    Returns
    -------
    tuple
        ``(class, declared frequencies in Hz, lines)``.

    Examples
    --------
    >>> parse_disturbance("slow,periodic:3.7")
    ('slow', [3.7], False)
    >>> parse_disturbance("lines")
    ('auto', [], True)
    """
    if isinstance(spec, np.ndarray) or spec is None:
        return spec, [], False
    cls, freqs, lines = "auto", [], False
    for item in str(spec).split(","):
        item = item.strip().lower()
        if not item:
            continue
        if item in ("auto", "slow", "none"):
            if cls != "auto" and item != cls:
                raise InputError(f"--disturbance names two wander classes, {cls!r} and {item!r}; give one of "
                                 f"auto, slow or none")
            cls = item
        elif item == "lines":
            lines = True
        elif item.startswith("periodic:"):
            try:
                f = float(item.split(":", 1)[1])
            except ValueError:
                raise InputError(f"--disturbance {item!r}: periodic needs a frequency in Hz, "
                                 f"e.g. periodic:3.7") from None
            if not np.isfinite(f) or f <= 0:
                raise InputError(f"--disturbance {item!r}: the frequency must be a positive number of Hz")
            freqs.append(f)
        else:
            raise InputError(f"unknown --disturbance kind {item!r}; use {KINDS_HELP}")
    if len(freqs) > MAX_DECLARED_LINES:
        raise InputError(f"--disturbance declares {len(freqs)} periodic lines; at most {MAX_DECLARED_LINES}")
    return cls, freqs, lines


class NyquistError(InputError):
    """A declared line at or above the Nyquist frequency; ``in_unit`` words it for another time unit.

    The finder may analyse a record on ``t / scale`` (:mod:`~odnn_sep.mismatch.timescale`), where the
    line and the Nyquist frequency are ``scale`` times the caller's: the message must give the caller's.

    Examples
    --------
    >>> str(NyquistError(1000.0, 100.0).in_unit(1e3))
    '--disturbance periodic:1: the frequency is above the Nyquist frequency 0.1 Hz of the data'
    """

    def __init__(self, freq: float, nyquist: float):
        self.freq, self.nyquist = float(freq), float(nyquist)
        super().__init__(f"--disturbance periodic:{freq:g}: the frequency is above the Nyquist frequency "
                         f"{nyquist:g} Hz of the data")

    def in_unit(self, scale: float) -> NyquistError:
        """The same error with frequencies per ``scale`` times the time unit (Hz of the caller's time)."""
        return NyquistError(self.freq / scale, self.nyquist / scale)


def periodic_columns(t, freqs):
    """cos/sin columns at each frequency (Hz) that lies below the Nyquist frequency. Shape (n, 2k).

    Parameters
    ----------
    t : ndarray
        Sample times (s).
    freqs : list of float
        Frequencies (Hz); one above the Nyquist frequency raises :class:`InputError`.

    Returns
    -------
    ndarray or None
        The columns, or None without frequencies.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(8) / 8.0
    >>> periodic_columns(t, [1.0, 2.0]).shape, periodic_columns(t, [])
    ((8, 4), None)
    """
    t = np.asarray(t, float)
    nyq = 0.5 / float(np.median(np.diff(t)))
    cols = []
    for f in freqs:
        if f >= nyq:
            raise NyquistError(f, nyq)
        cols += [np.cos(2 * np.pi * f * t), np.sin(2 * np.pi * f * t)]
    return np.column_stack(cols) if cols else None


def residual_lines(t, r, *, alpha=0.01, max_lines=MAX_DECLARED_LINES):
    """Frequencies (Hz) of the spectral lines of a residual: periodogram ordinates above the noise
    floor with a Bonferroni-corrected exponential test, strongest first, one per resolution cell.

    Parameters
    ----------
    t, r : ndarray
        Sample times (s) and residual.
    alpha : float, optional
        Family-wise false-alarm rate.
    max_lines : int, optional
        Most lines returned.

    Returns
    -------
    list of float
        Line frequencies (Hz).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(1000) / 100.0
    >>> r = np.sin(2 * np.pi * 3.7 * t) + 0.1 * np.random.default_rng(0).normal(size=1000)
    >>> [round(f, 2) for f in residual_lines(t, r)]
    [3.7]
    """
    t = np.asarray(t, float)
    r = np.asarray(r, float) - np.mean(r)
    f, X = spectrum(t, r, taper=True)
    spec = np.abs(X) ** 2
    spec[0] = 0.0
    floor = np.median(spec[1:]) / np.log(2.0)     # median of an exponential is mean * ln 2
    thresh = floor * np.log(len(spec) / alpha)
    out = []
    s = spec.copy()
    for _ in range(max_lines):
        i = int(np.argmax(s))
        if s[i] <= thresh:
            break
        # refine by the parabola through the log peak
        if 0 < i < len(s) - 1 and spec[i - 1] > 0 and spec[i + 1] > 0:
            a, b, c = np.log(spec[i - 1:i + 2])
            d = 0.5 * (a - c) / (a - 2 * b + c) if (a - 2 * b + c) != 0 else 0.0
        else:
            d = 0.0
        out.append(float((i + np.clip(d, -0.5, 0.5)) * (f[1] - f[0])))
        s[max(0, i - 3): i + 4] = 0.0
    return out


def describe(effect, params, *, model_family, linear, unit="", t0=0.0):
    """One plain sentence for a disturbance that was absorbed (see module docstring).

    Parameters
    ----------
    effect : str
        ``periodic_pickup``, ``periodic_pickup_2``, ``periodic_pattern``, ``offset``, ``drift`` or ``step_offset`` (any other name is returned as is).
    params : dict
        Fitted parameters.
    model_family : str
        Family of the model (the reason given depends on it).
    linear : bool
        Whether the model is linear (:func:`linear_model`).
    unit : str, optional
        Unit of the data.
    t0 : float, optional
        First time stamp.

    Returns
    -------
    str

    Examples
    --------
    >>> describe("offset", {"offset": 0.25}, model_family="cooling", linear=True, unit="degC")
    'a constant offset of 0.25 degC; a sensor bias and a constant disturbance give the same data'
    """
    u = f" {unit}" if unit else ""
    if effect in ("periodic_pickup", "periodic_pickup_2"):
        sfx = "2" if effect == "periodic_pickup_2" else ""
        f = params["omega_pk" + sfx] / (2 * np.pi)
        amp = float(np.hypot(params["a_pk" + sfx], params["b_pk" + sfx]))
        if model_family in ("oscillator", "pendulum"):
            why = ("for this linear model an external periodic force and a periodic pickup give the same data"
                   if linear else "a periodic force through the dynamics did not fit significantly better "
                   "than this additive component")
        else:
            why = "the data cannot tell a periodic drive from a periodic pickup in the recording"
        return f"a periodic component at {f:.4g} Hz, {amp:.3g}{u}; {why}"
    if effect == "periodic_pattern":
        wavelength = 2 * np.pi / max(float(np.hypot(params["kx_pp"], params["ky_pp"])), 1e-300)
        direction = float(np.degrees(np.arctan2(params["ky_pp"], params["kx_pp"]))) % 180.0
        amp = float(np.hypot(params["a_pp"], params["b_pp"]))
        return (f"a periodic pattern (stripes) of wavelength {wavelength:.3g}, wave vector at {direction:.0f} deg, "
                f"{amp:.3g}{u}; a pattern added by the instrument and one in the field give the same data")
    if effect == "offset":
        return (f"a constant offset of {params['offset']:.4g}{u}; a sensor bias and a constant disturbance "
                f"give the same data")
    if effect == "step_offset":
        return (f"a step of {params['h_step']:.4g}{u} at t = {params['t_step']:.6g}; a sensor bumped or "
                f"re-ranged and a sudden change of the surroundings give the same data")
    if effect == "drift":
        return (f"a linear drift of {params['drift']:.4g}{u} per time unit; a drifting sensor and a slow "
                f"disturbance give the same data")
    return effect


def linear_model(model):
    """True when no nonlinear effect is in the model (then forcing and pickup are equivalent).

    Parameters
    ----------
    model : Model
        The model.

    Returns
    -------
    bool

    Examples
    --------
    >>> from odnn_sep.mismatch.model import make_model
    >>> m = make_model("oscillator")
    >>> linear_model(m), linear_model(m.with_effect("quadratic_drag"))
    (True, False)
    """
    nonlinear = {"quadratic_drag", "coulomb_friction", "cubic_stiffness", "large_angle", "radiation",
                 "evaporation"}
    return not (set(model.effects) & nonlinear)
