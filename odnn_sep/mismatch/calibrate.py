"""Calibration: refit the simulation's own parameters, with the disturbance kept in its class.

The disturbance class for oscillatory records ("slow") is a set of slowly varying cosine modes
below half the dominant physical frequency (at most 10 modes), plus a constant and a straight line.
It cannot imitate the physics (which lives at the oscillation frequency). A constant offset and a
linear drift are inside it on purpose: the mean and trend of a slow wander cannot be told apart
from a sensor offset or drift, so under this class those two effects are reported as part of the
disturbance instead of being offered as candidates (with ``disturbance="none"`` they are offered). Slow presets (cooling, free fall, 2D fields) and user
models default to no disturbance class: their physics is itself slow, so any slow class would
imitate it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from odnn_sep.core.linalg import orthonormal_basis
from odnn_sep.errors import InputError, NotIdentifiableError
from odnn_sep.mismatch.fitting import Fit, fit
from odnn_sep.mismatch.presets import dominant_omega
from odnn_sep.mismatch.starts import difference_jacobian

SLOW_FAMILIES = {"oscillator", "pendulum", "hum"}
# at most 10 modes: with 20 cross-validation blocks the slowest held-out gap must stay
# interpolable by the disturbance fitted on the other blocks
MAX_SLOW_MODES = 10


def slow_cutoff(t, y, model=None):
    """Half the dominant frequency of the physics: the oscillation and its sidebands stay above it.

    With a preset, the frequency is read off the preset's data-driven starting model (for hum,
    the mains frequency, not whatever dominates the recording); otherwise off the data.

    Parameters
    ----------
    t, y : ndarray
        Sample times and samples.
    model : Model, optional
        The model; a preset's starting model gives the frequency.

    Returns
    -------
    float
        Cut-off frequency (Hz, i.e. cycles per unit of ``t``).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 20, 400)
    >>> round(float(slow_cutoff(t, np.cos(2.0 * t))), 3)   # (2 / 2 pi) / 2
    0.158
    """
    if model is not None and model.preset is not None:
        try:
            guess = {**model.start, **model.preset.initial_guess(t, y, dict(model.start))}
            return dominant_omega(t, model.predict(t, guess)) / (2 * np.pi) / 2.0
        except (InputError, ValueError, np.linalg.LinAlgError):
            pass
    return dominant_omega(t, y) / (2 * np.pi) / 2.0


def slow_disturbance(t, *, cutoff_hz=None, y=None, model=None):
    """Orthonormal columns spanning a constant, a line and cosine modes below ``cutoff_hz``. Shape (n, q).

    Parameters
    ----------
    t : ndarray
        Sample times.
    cutoff_hz : float, optional
        Highest mode frequency; found with :func:`slow_cutoff` from ``y`` when not given.
    y : ndarray, optional
        Samples (only to find the cut-off).
    model : Model, optional
        The model (only to find the cut-off).

    Returns
    -------
    ndarray, shape (n, q)
        Orthonormal columns, at most 2 + 10 of them.

    Examples
    --------
    >>> import numpy as np
    >>> G = slow_disturbance(np.linspace(0, 20, 400), cutoff_hz=0.2)
    >>> G.shape, bool(np.allclose(G.T @ G, np.eye(G.shape[1])))
    ((400, 10), True)
    """
    t = np.asarray(t, float)
    T = float(t[-1] - t[0])
    if cutoff_hz is None:
        if y is None:
            raise InputError("slow_disturbance needs cutoff_hz or y to find the dominant frequency")
        cutoff_hz = slow_cutoff(t, y, model)
    # cosine mode k has frequency k / (2 T); keep modes strictly below the cut-off
    K = int(np.floor(2 * T * cutoff_hz))
    K = min(K, MAX_SLOW_MODES, len(t) // 10)
    u = (t - t[0]) / max(T, 1e-300)
    cols = np.column_stack([np.ones_like(u), u - 0.5] + [np.cos(np.pi * k * u) for k in range(1, K + 1)])
    return orthonormal_basis(cols, method="qr", rtol=1e-8)


def disturbance_columns(disturbance, model, t, y):
    """Resolve the ``disturbance`` option into a column matrix (or None).

    Parameters
    ----------
    disturbance : {"auto", "slow", "none"} or ndarray
        The option, or user columns of shape (n, q).
    model : Model
        The model; ``"auto"`` is ``"slow"`` for oscillatory families, else ``"none"``.
    t, y : ndarray
        Sample times and samples.

    Returns
    -------
    ndarray or None
        Disturbance columns, or None for no disturbance class.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 20, 400); y = np.cos(2.0 * t)
    >>> disturbance_columns("auto", make_model("oscillator"), t, y).shape
    (400, 8)
    >>> disturbance_columns("auto", make_model("cooling"), t, y) is None
    True
    """
    if isinstance(disturbance, np.ndarray):
        G = np.asarray(disturbance, float)
        if G.ndim != 2 or G.shape[0] != len(y):
            raise InputError(f"disturbance columns must have shape (n, q) with n = {len(y)}; got {G.shape}")
        return G
    if disturbance == "auto":
        disturbance = "slow" if model.family in SLOW_FAMILIES and np.ndim(t) == 1 else "none"
    if disturbance == "none":
        return None
    if disturbance == "slow":
        return slow_disturbance(t, y=y, model=model)
    raise InputError(f"disturbance must be 'auto', 'slow', 'none' or an (n, q) array; got {disturbance!r}")


def tangent_separation(model, t, y, params, G):
    """The separation step on the model's tangent space, done by the core engine.

    At the calibrated parameters the model is linear in small parameter changes: its columns are
    the sensitivities d prediction / d parameter. Separating ``y - prediction`` into those columns
    plus a disturbance confined to ``Subspace(G)`` (or ``Orthogonal()`` without a class) with
    ``odnn_sep.core.Separator`` checks that the class cannot imitate the physics (the fraction of
    each sensitivity outside the class, the conditioning after projecting the class out) and that
    no further parameter change is asked for (the Gauss-Newton correction, ~0 at convergence).

    Parameters
    ----------
    model : Model
        The calibrated model.
    t, y : ndarray
        Sample times and samples.
    params : dict
        Calibrated parameters.
    G : ndarray or None
        Disturbance columns (None: no class).

    Returns
    -------
    dict
        ``outside_fraction``, ``projected_condition``, ``disturbance_in_basis_span`` and
        ``gauss_newton_step`` (per free parameter); empty when nothing is free.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> m = make_model("oscillator", {"k": 4.0})
    >>> t = np.linspace(0, 20, 400)
    >>> d = tangent_separation(m, t, m.predict(t), m.start, None)
    >>> sorted(d), max(abs(v) for v in d["gauss_newton_step"].values()) < 1e-6
    (['disturbance_in_basis_span', 'gauss_newton_step', 'outside_fraction', 'projected_condition'], True)
    """
    from odnn_sep.core import Basis, Orthogonal, Separator, Subspace

    free = list(model.free)
    if not free:
        return {}
    pred = model.predict(t, params)
    F = difference_jacobian(model, params, t, pred, 1e-5, abs_step=1e-5)
    dist = Subspace(G) if G is not None else Orthogonal()
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # conditioning is reported below, not warned about per fit
        r = Separator(Basis.from_matrix(F, names=free), disturbance=dist).fit(
            np.arange(len(y), dtype=float), y - pred).result_
    d = r.diagnostics
    return {"outside_fraction": d.get("outside_fraction"), "projected_condition": d.get("projected_condition"),
            "disturbance_in_basis_span": d.get("disturbance_in_basis_span"),
            "gauss_newton_step": dict(zip(free, (float(v) for v in r.theta), strict=True))}


def _calibration_starts(model, t, y, user_params):
    """Starts of the calibration: the preset's data-driven guess with and without the user's values."""
    if model.preset is None:
        return [dict(model.start)]
    guess = model.preset.initial_guess(t, y, {**model.start, **user_params})
    s = dict(model.start)
    s.update(guess)
    s.update({k: v for k, v in user_params.items() if k in s and not isinstance(v, str)
              and k not in model.fixed})
    s2 = dict(model.start)
    s2.update({k: v for k, v in guess.items() if k not in user_params})
    g2 = dict(model.start)
    g2.update(guess)
    # data-driven but honouring what the user set; the user's values as given; purely data-driven
    return [s, s2, g2]


@dataclass
class Calibration:
    """Result of :func:`calibrate`: the best fit, the disturbance columns and identifiability checks.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 50)
    >>> cal = calibrate(make_model("freefall"), t, 5.0 - 4.9 * t ** 2)
    >>> d = cal.as_dict()
    >>> d["model"], round(d["parameters"]["g"]["value"], 6), d["disturbance"]["class"], cal.G is None
    ('freefall', 9.8, 'none', True)
    """

    fit: Fit
    G: np.ndarray | None
    identifiability: dict | None = None

    def as_dict(self) -> dict:
        """JSON-ready record: model, parameters with intervals, fixed values, disturbance, residual."""
        f = self.fit
        iv = f.intervals()
        return {
            "model": f.model.name,
            "parameters": {k: {"value": f.params[k], "stderr": f.reported_stderr(k),
                               "interval95": list(iv[k]) if k in iv else None} for k in f.free},
            "fixed": {k: f.params[k] for k in f.model.fixed if k in f.params},
            "disturbance": {"class": "slow band (constant, drift and slow cosine modes)" if self.G is not None
                            else "none", "columns": 0 if self.G is None else int(self.G.shape[1]),
                            "rms": float(np.sqrt(np.mean(f.disturbance ** 2)))},
            "residual_rms": f.rms,
            "converged": f.converged,
            "identifiability": self.identifiability,
        }


def calibrate(model, t, y, *, user_params=None, G=None, max_nfev=400) -> Calibration:
    """Refit the model's parameters from the user's starts and from data-driven starts; keep the best.

    Parameters
    ----------
    model : Model
        The model to calibrate.
    t, y : ndarray
        Sample times (or 2D coordinates) and samples.
    user_params : dict, optional
        Starting values the user gave (they win over the data-driven ones).
    G : ndarray, optional
        Disturbance columns (:func:`disturbance_columns`).
    max_nfev : int, optional
        Most model evaluations per start.

    Returns
    -------
    Calibration

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 20, 400); y = np.cos(2.0 * t) * np.exp(-0.05 * t)
    >>> cal = calibrate(make_model("oscillator"), t, y)
    >>> round(cal.fit.params["k"], 4), round(cal.fit.params["c"], 3)   # k = 2^2 + c^2/4
    (4.0025, 0.1)
    """
    starts = _calibration_starts(model, t, y, dict(user_params or {}))
    best = None
    seen = []
    for s in starts:
        key = tuple(sorted((k, v) for k, v in s.items() if not isinstance(v, str)))
        if key in seen:
            continue
        seen.append(key)
        f = fit(model, t, y, start=s, G=G, max_nfev=max_nfev)
        if best is None or f.rss < best.rss:
            best = f
    try:
        ident = tangent_separation(model, t, y, best.params, G)
    except NotIdentifiableError:
        raise
    except (InputError, np.linalg.LinAlgError) as exc:
        ident = {"error": str(exc)}
    return Calibration(best, G, ident)
