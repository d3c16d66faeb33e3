"""A free fall timed by a clock that did not start at the release: analysed from the first sample.

The freefall preset releases the body at ``t = 0``. A record whose time stamps are a logger's clock
(``t = 1000.0 ... 1000.6``) or Unix time (``1.7e9 + ...``) puts the release long before the record:
the fit then expressed the offset as a drift of 1.9e4 m/s and a height of millions of metres (and
missed the drag), or crashed on non-finite numbers with Unix time. When the record starts more than
:data:`FAR` times its own span away from ``t = 0``, a release at ``t = 0`` is not what the clock
means: time is counted from the first sample instead, and the (unknown) release instant near the
record's start is the height offset and drift the finder already treats as a disturbance.
"""
from __future__ import annotations

import numpy as np

FAR = 10.0   # first time stamp, in record spans from t = 0, beyond which the clock is not the release's


def _is_freefall(model):
    if isinstance(model, str):
        return model.strip().lower() == "freefall"
    preset = getattr(model, "preset", None)
    return getattr(model, "family", None) == "freefall" and not hasattr(preset, "series_times")


def far_clock(model, t):
    """Whether ``t`` is a clock far from the free fall's release at 0 (then it is counted from ``t[0]``).

    Parameters
    ----------
    model : str or Model
        The model given to :func:`~odnn_sep.mismatch.explain.explain`.
    t : array_like
        Time stamps.

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 0.6, 50)
    >>> far_clock("freefall", t), far_clock("freefall", t + 1000.0), far_clock("cooling", t + 1000.0)
    (False, True, False)
    """
    if not _is_freefall(model):
        return False
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or len(t) < 2 or not np.all(np.isfinite(t)):
        return False
    span = float(t[-1] - t[0])
    return span > 0 and abs(float(t[0])) > FAR * span


def explain_from_first_sample(model, t, y, options):
    """:func:`~odnn_sep.mismatch.explain.explain` on ``t - t[0]`` when :func:`far_clock`, else None.

    The result's times, the located windows and the spikes' instants are given back on the
    record's own clock, with a note.

    Parameters
    ----------
    model : str or Model
    t, y : array_like
    options : dict
        The keyword options of ``explain``.

    Returns
    -------
    MismatchResult or None

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch import make_model
    >>> t = np.linspace(0, 0.6, 120)
    >>> y = make_model("freefall", {"g": 9.81, "h0": 2.0}).predict(t)
    >>> y = y + 0.001 * np.random.default_rng(0).normal(size=120)
    >>> res = explain_from_first_sample("freefall", t + 1000.0, y, {})
    >>> round(res.final_fit.params["g"], 1), float(res.t[0]), res.notes[-1][:40]
    (9.8, 1000.0, 'time counted from the first sample (t = ')
    """
    if not far_clock(model, t):
        return None
    from odnn_sep.mismatch.explain import explain
    from odnn_sep.mismatch.locate import locate
    t = np.asarray(t, dtype=float)
    t0 = float(t[0])
    res = explain(model, t - t0, y, **options)
    res.t = np.asarray(res.t, float) + t0
    res.where = locate(res.t, res.calibration.fit.residual, sigma=res.noise_sigma, alpha=options.get("alpha", 0.05))
    for d in res.disturbances:
        if d.get("effect") == "spikes" and "at" in d:
            d["at"] = [a + t0 for a in d["at"]]
    res.notes.append(f"time counted from the first sample (t = {t0:.10g}): the record starts {abs(t0):.3g} time "
                     f"units from t = 0, far from a release there; h0 is the height at the first sample, and a "
                     f"release just before it is a height offset and drift")
    return res
