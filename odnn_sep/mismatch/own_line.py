"""A strong periodic component the finder could not name: at the system's own frequency or a harmonic.

An additive sinusoid is never taken at a harmonic of an oscillator's own frequency (a nonlinearity puts
its lines there), and a periodic force there is not named when an additive sinusoid fits as well. A
pickup exactly at twice the own frequency then leaves the verdict at "the model does not fit ... check
the starting values", although the calibration converged and the candidates' table shows a periodic
component with a BIC drop in the thousands. This module finds that component so the verdict can say
what is there, why it is not named, and how to declare it when it is a known pickup.
"""
from __future__ import annotations

import numpy as np

# periodic candidates and the parameter that holds their angular frequency
FREQUENCY_KEY = {"periodic_forcing": "omega_f", "periodic_pickup": "omega_pk", "periodic_pickup_2": "omega_pk2"}


def unnamed_periodic(candidates, calibration_fit, t, bic_threshold):
    """The strongest periodic candidate that passed the BIC threshold but was not eligible (noted).

    Parameters
    ----------
    candidates : list of Candidate
        The first step's candidates (``MismatchResult.candidates``).
    calibration_fit : Fit
        The calibrated base fit (for the system's own frequency).
    t : ndarray
        Sample times.
    bic_threshold : float
        BIC drop a candidate needs.

    Returns
    -------
    dict or None
        ``{"effect", "frequency_hz", "harmonic", "score"}`` (``harmonic`` 0 when not on an own line).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> c = NS(effect="periodic_forcing", score=900.0, note="not significantly better than an additive",
    ...        fit=NS(params={"omega_f": 4.0}))
    >>> d = unnamed_periodic([c], None, None, 10.0)
    >>> d["effect"], round(d["frequency_hz"], 4), d["harmonic"]
    ('periodic_forcing', 0.6366, 0)
    """
    best = None
    for c in candidates:
        key = FREQUENCY_KEY.get(c.effect)
        if key is None or not getattr(c, "note", None) or c.fit is None or key not in c.fit.params:
            continue
        if not np.isfinite(c.score) or c.score <= bic_threshold:
            continue
        if best is None or c.score > best.score:
            best = c
    if best is None:
        return None
    hz = float(best.fit.params[FREQUENCY_KEY[best.effect]]) / (2 * np.pi)
    harmonic = 0
    if calibration_fit is not None and t is not None and np.ndim(t) == 1:
        from odnn_sep.mismatch.starts import system_line_number
        try:
            harmonic = int(system_line_number(hz, calibration_fit, np.asarray(t, float)))
        except (KeyError, TypeError, ValueError):
            harmonic = 0
    return {"effect": best.effect, "frequency_hz": hz, "harmonic": harmonic, "score": float(best.score)}


def unnamed_sentence(d):
    """The verdict's sentence for a component from :func:`unnamed_periodic`.

    Examples
    --------
    >>> print(unnamed_sentence({"effect": "periodic_forcing", "frequency_hz": 0.63662, "harmonic": 2,
    ...                         "score": 1495.7}))   # doctest: +NORMALIZE_WHITESPACE
    the residual holds a periodic component at 0.6366 Hz (2x the system's own frequency; BIC drop 1496 as
    periodic_forcing): at that frequency a periodic force, an additive pickup and the harmonic of a
    nonlinearity give the same data, so it is not named; if it is a known pickup, declare it
    (--disturbance periodic:0.6366)
    """
    k = d["harmonic"]
    where = ("the system's own frequency" if k == 1 else f"{k}x the system's own frequency") if k else ""
    head = f"the residual holds a periodic component at {d['frequency_hz']:.4g} Hz"
    why = ("at that frequency a periodic force, an additive pickup and the harmonic of a nonlinearity give the same data"
           if k else "a periodic force and an additive pickup give the same data there")
    return (f"{head} ({where + '; ' if where else ''}BIC drop {d['score']:.0f} as {d['effect']}): {why}, so it "
            f"is not named; if it is a known pickup, declare it (--disturbance periodic:{d['frequency_hz']:.4g})")
