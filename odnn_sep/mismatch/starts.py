"""Starting values for an effect's parameters, read off the calibrated residual.

Effects with a nonlinear parameter (a frequency, a decay rate, a position) have many local
minima; a handful of data-driven starts (residual periodogram peaks, residual maxima) make the
refit reliable without a global search. Linear amplitudes are started at their least-squares value
given the nonlinear guess.
"""
from __future__ import annotations

import functools

import numpy as np

from odnn_sep.core.linalg import solve
from odnn_sep.core.spectrum import spectrum


def _peaks(t, r, *, n_peaks=3, fmin=0.0, fmax=None):
    n = len(r)
    nfft = int(2 ** np.ceil(np.log2(4 * n)))
    f, X = spectrum(t, r - r.mean(), nfft=nfft, taper=True)
    spec = np.abs(X)
    ok = (f > max(fmin, 0.5 / (t[-1] - t[0]))) & (f <= (fmax if fmax is not None else f[-1]))
    spec = np.where(ok, spec, 0.0)
    out = []
    width = max(1, nfft // n)  # one natural-resolution bin
    for _ in range(n_peaks):
        i = int(np.argmax(spec))
        if spec[i] <= 0:
            break
        out.append(float(f[i]))
        spec[max(0, i - 2 * width): i + 2 * width + 1] = 0.0
    return out


def _ls(cols, r):
    return solve(np.column_stack(cols), r, method="lstsq")


def difference_jacobian(model, start, t, base_pred, rel_step, abs_step=1e-3):
    """Forward-difference Jacobian of the prediction in the free parameters, one column each.

    Parameters
    ----------
    model : Model
        The model.
    start : dict
        Parameters to differentiate at.
    t : ndarray
        Sample times (or coordinates).
    base_pred : ndarray
        ``model.predict(t, start)``.
    rel_step : float
        Relative step.
    abs_step : float, optional
        Step of a parameter at (about) zero.

    Returns
    -------
    ndarray, shape (n, free parameters)

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> m = make_model("freefall"); t = np.array([0.0, 1.0])
    >>> np.round(difference_jacobian(m, m.start, t, m.predict(t), 1e-6), 3).tolist()
    [[0.0, 1.0], [-0.5, 1.0]]
    """
    cols = []
    for k in model.free:
        # parameters at their neutral value 0 get an absolute step: a relative one would be
        # lost in the ODE solver's error
        x = abs(float(start[k]))
        h = rel_step * x if x > 1e-6 else abs_step
        p = dict(start)
        p[k] = float(start[k]) + h
        cols.append((model.predict(t, p) - base_pred) / h)
    return np.column_stack(cols)


def one_step(model, start, t, y, G=None, rel_step=1e-4):
    """One Gauss-Newton step from ``start`` (finite-difference Jacobian), or None if it fails.

    Needed because a trust-region solver started exactly on a bound (drag = 0) barely moves that
    parameter: the step is scaled by the distance to the bound. The one-step estimate is the score
    direction, i.e. how much of the effect the calibrated residual asks for.

    Parameters
    ----------
    model : Model
        The model (with the effect).
    start : dict
        Parameters to step from.
    t, y : ndarray
        Sample times and samples.
    G : ndarray, optional
        Disturbance columns, projected out.
    rel_step : float, optional
        Relative finite-difference step.

    Returns
    -------
    dict or None
        The stepped parameters (kept strictly inside the bounds).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60); y = 5.0 - 4.9 * t ** 2 - 0.3 * t   # free fall + a drift
    >>> base = fit(make_model("freefall"), t, y)
    >>> m = base.model.with_effect("drift")
    >>> s = one_step(m, {**m.start, **base.params}, t, y)
    >>> {k: round(v, 4) for k, v in s.items()}   # exact: the model is linear in its parameters
    {'g': 9.8, 'h0': 5.0, 'drift': -0.3}
    """
    free = model.free
    try:
        base_pred = model.predict(t, start)
        J = difference_jacobian(model, start, t, base_pred, rel_step)
    except Exception:  # noqa: BLE001 - any failure just means "no extra start"
        return None
    r = y - base_pred
    from odnn_sep.mismatch.fitting import disturbance_projector

    P = disturbance_projector(G)
    if P is not None:
        J = P.project_out(J)
        r = P.project_out(r)
    delta = solve(J, r, method="lstsq")
    out = dict(start)
    for k, d in zip(free, delta, strict=True):
        out[k] = _inside_bounds(float(start[k]), float(d), model.bounds.get(k, (-np.inf, np.inf)))
    return out


def _inside_bounds(v0, d, bounds):
    """``v0 + d``, reflected off a bound it reaches so that it stays strictly inside."""
    lo, hi = bounds
    v = v0 + d
    if v <= lo:
        v = lo + max(abs(d), 1e-12)
    if v >= hi:
        v = hi - max(abs(d), 1e-12)
    return v


def _forcing_starts(p, r, tt, base, model, t):
    out = []
    fam = base.model.family
    for f in _peaks(tt, r, n_peaks=2):
        w = 2 * np.pi * f
        a, b = _ls([np.cos(w * tt), np.sin(w * tt)], r)
        X = a - 1j * b   # response phasor: a cos + b sin = Re[X e^{i w t}]
        if fam in ("oscillator", "pendulum"):
            k = p["k"] if fam == "oscillator" else p["w2"]
            m = p.get("m", 1.0)
            X = X * (k - m * w ** 2 + 1j * p["c"] * w)
        out.append({**p, "omega_f": w, "F": float(abs(X)), "phase_f": float(np.angle(X))})
    return out


def _pickup_starts(p, r, tt, base, model, t, sfx=""):
    """Starts of an additive sinusoid at the residual's two strongest peaks off the system's lines;
    ``sfx`` "2" names the second pickup's parameters (``omega_pk2``, ...)."""
    out = []
    for f in _not_harmonics(_peaks(tt, r, n_peaks=4), base, tt)[:2]:
        w = 2 * np.pi * f
        a, b = _ls([np.cos(w * tt), np.sin(w * tt)], r)
        out.append({**p, "omega_pk" + sfx: w, "a_pk" + sfx: float(a), "b_pk" + sfx: float(b)})
    return out


def _modulation_starts(p, r, tt, base, model, t):
    out = []
    pred = base.prediction
    env = r * pred / max(np.mean(pred ** 2), 1e-300)
    for f in _peaks(tt, env, n_peaks=2, fmax=_nyq_quarter(tt)):
        w = 2 * np.pi * f
        a, b = _ls([pred * np.cos(w * tt), pred * np.sin(w * tt)], r)
        m = float(np.hypot(a, b))
        out.append({**p, "f_am": f, "m_am": float(np.clip(m, -0.9, 0.9)), "phase_am": float(np.arctan2(-b, a))})
    return out


def _two_body_starts(p, r, tt, base, model, t):
    out = []
    tau = tt - tt[0]
    for mult in (0.2, 3.0, 10.0):
        lam = mult * p["h"]
        col = np.exp(-lam * tau) - np.exp(-p["h"] * tau)
        B = float(_ls([col], r)[0]) if np.any(col) else 0.0
        out.append({**p, "lam_2": lam, "B_2": B})
    return out


def _harmonic_starts(p, r, tt, base, model, t):
    H = int(p.get("harmonics", 1))
    nyq = 0.5 / float(np.median(np.diff(tt)))
    best = None
    for k in range(H + 1, H + 7):
        if k * p["f0"] >= nyq:
            break
        # the harmonic's own columns from the model, so it follows a frequency drift already found
        cols = _harmonic_columns(model, {**model.start, **p}, tt, k)
        a, b = _ls(cols, r)
        gain = a * a + b * b
        if best is None or gain > best[0]:
            best = (gain, k, a, b)
    if best is None:
        return []
    return [{**p, "k_h": float(best[1]), "a_h": float(best[2]), "b_h": float(best[3])}]


def _source_starts(p, r, tt, base, model, t):
    out = []
    xy = np.asarray(t)
    s2 = 4 * p["alpha"] * p["t"]
    for i in np.argsort(-np.abs(r))[:1]:
        xs, ys = xy[i]
        col = np.exp(-((xy[:, 0] - xs) ** 2 + (xy[:, 1] - ys) ** 2) / s2) / (np.pi * s2)
        S = float(_ls([col], r)[0])
        out.append({**p, "xs": float(xs), "ys": float(ys), "S_extra": S})
    return out


def _pattern_starts(p, r, tt, base, model, t, *, max_cycles=8.0, step=0.25):
    """Wave vectors of the two strongest plane waves in the residual of a field (up to ``max_cycles``
    cycles across its span, on a grid of ``step`` cycles), with least-squares amplitudes."""
    xy = np.asarray(t, float)
    span = np.maximum(np.ptp(xy, axis=0), 1e-300)
    u = np.arange(0.0, max_cycles + step / 2, step)
    v = np.arange(-max_cycles, max_cycles + step / 2, step)
    K = 2 * np.pi * np.array([(a, b) for a in u for b in v if a > 0 or b > 0]) / span
    phase = xy @ K.T
    power = (r @ np.cos(phase)) ** 2 + (r @ np.sin(phase)) ** 2
    out = []
    for j in np.argsort(-power)[:2]:
        a, b = _ls([np.cos(phase[:, j]), np.sin(phase[:, j])], r)
        out.append({**p, "kx_pp": float(K[j, 0]), "ky_pp": float(K[j, 1]), "a_pp": float(a), "b_pp": float(b)})
    return out


def _wander_starts(p, r, tt, base, model, t):
    from odnn_sep.mismatch.hum_wander import wander_starts  # the rule lives with the hum engine
    return wander_starts(p, r, tt, base, model, t)


def _moved_starts(p, r, tt, base, model, t):
    from odnn_sep.mismatch.presets_heat2d import moved_starts  # the rule lives with the heat2d preset
    return moved_starts(p, r, tt, base, model, t)


# effect -> (start rule, needs a time series (True) or 2D coordinates (False) or either (None))
_START_RULES = {
    "periodic_forcing": (_forcing_starts, True),
    "periodic_pickup": (_pickup_starts, True),
    "periodic_pickup_2": (functools.partial(_pickup_starts, sfx="2"), True),
    "amplitude_modulation": (_modulation_starts, True),
    "two_body_heat": (_two_body_starts, True),
    "missing_harmonic": (_harmonic_starts, True),
    "frequency_wander": (lambda *a: _wander_starts(*a), True),
    "extra_source": (_source_starts, False),
    "source_moved": (lambda *a: _moved_starts(*a), False),
    "periodic_pattern": (_pattern_starts, False),
    "offset": (lambda p, r, tt, base, model, t: [{**p, "offset": float(np.mean(r))}], None),
    "step_offset": (lambda p, r, tt, base, model, t: _step_starts(p, r, tt), True),
}

STEP_EDGE = 0.05   # a step is looked for away from the record's ends (there it is an offset or a transient)


def _step_starts(p, r, tt):
    """Starts of a step of the level at the residual's strongest change of mean (the split that
    best separates the means of the two sides), and at the second strongest.

    Examples
    --------
    >>> tt = np.arange(100.0); r = 0.01 * np.sin(tt) + 0.5 * (tt >= 60)
    >>> s = _step_starts({}, r, tt)[0]
    >>> s["t_step"], round(s["h_step"], 2)
    (59.5, 0.5)
    """
    n = len(r)
    lo, hi = max(1, int(STEP_EDGE * n)), min(n - 1, int((1 - STEP_EDGE) * n))
    if hi - lo < 2:
        return []
    c = np.cumsum(r - r.mean())
    k = np.arange(1, n)
    # between-sides contrast of a split after sample k-1: k (n - k) / n (mean_right - mean_left)^2
    score = c[:-1] ** 2 * n / (k * (n - k))
    score[: lo - 1], score[hi:] = -np.inf, -np.inf
    out = []
    for j in np.argsort(score)[::-1][:2]:
        if not np.isfinite(score[j]):
            break
        kk = j + 1
        out.append({**p, "t_step": float(0.5 * (tt[kk - 1] + tt[kk])), "h_step": float(r[kk:].mean() - r[:kk].mean())})
    return out


def effect_starts(effect, base, t, y, model=None, G=None):
    """List of starting dicts (base parameters + effect parameters) for refitting with ``effect``.

    Effects with a rule in ``_START_RULES`` start from the calibrated residual (periodogram peaks,
    residual maxima, least-squares amplitudes); the others, and any rule that finds nothing, from
    one Gauss-Newton step off the calibrated model.

    Parameters
    ----------
    effect : str
        Effect name.
    base : Fit
        Calibrated current model.
    t, y : ndarray
        Sample times (or 2D coordinates) and samples.
    model : Model, optional
        The model with the effect (needed for the Gauss-Newton fallback).
    G : ndarray, optional
        Disturbance columns.

    Returns
    -------
    list of dict
        Starting values, at least one.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60); y = 5.0 - 4.9 * t ** 2 - 0.3 * t   # free fall + a drift
    >>> base = fit(make_model("freefall"), t, y)
    >>> m = base.model.with_effect("drift")
    >>> [{k: round(v, 4) for k, v in s.items()} for s in effect_starts("drift", base, t, y, m)]
    [{'g': 9.8, 'h0': 5.0, 'drift': -0.3}]
    """
    p = dict(base.params)
    tt = t if np.ndim(t) == 1 else None
    out = []
    rule = _START_RULES.get(effect)
    if rule is not None and (rule[1] is None or rule[1] == (tt is not None)):
        out = rule[0](p, base.residual, tt, base, model, t)
    if not out:
        s = one_step(model, {**model.start, **p}, t, y, G) if model is not None else None
        out.append(p if s is None else s)
    return out


# oscillators whose own line an additive sinusoid close to it can beat against: over a record of a
# few cycles the beat is a slow change of amplitude and phase, which damping laws, a cubic stiffness
# or an amplitude modulation fit as well. A pickup there competes with physics like any other
# disturbance (absorbed first on a tie, the physics tested again on top of it); at the harmonics it
# stays set aside, since a nonlinearity puts its own lines there
BEATING_FAMILIES = ("oscillator", "pendulum")


def system_frequency(fit):
    """The system's own frequency (Hz) under a calibrated fit: an oscillator's sqrt(k/m) / 2 pi, a
    pendulum's sqrt(w2) / 2 pi, hum's f0; None for other families.

    Parameters
    ----------
    fit : Fit
        Calibrated fit (``fit.params``, ``fit.model.family``).

    Returns
    -------
    float or None

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> round(system_frequency(NS(params={"w2": 4.0}, model=NS(family="pendulum"))), 4)
    0.3183
    >>> system_frequency(NS(params={}, model=NS(family="cooling"))) is None
    True
    """
    p = fit.params
    fam = fit.model.family
    if fam == "oscillator":
        return float(np.sqrt(max(p["k"] / p.get("m", 1.0), 0.0)) / (2 * np.pi))
    if fam == "pendulum":
        return float(np.sqrt(max(p["w2"], 0.0)) / (2 * np.pi))
    if fam == "hum":
        return float(p["f0"])
    return None


def system_line_number(f, fit, t, *, harmonics=8):
    """Which of the system's own lines (1 = its frequency, k = the k-th harmonic) ``f`` lies within
    1.5 resolution cells of; 0 when none (or the family has no own frequency).

    Parameters
    ----------
    f : float
        Frequency (Hz).
    fit : Fit
        Calibrated fit (oscillator, pendulum or hum; other families give 0).
    t : ndarray
        Sample times (the resolution is 1 / record length).
    harmonics : int, optional
        Harmonics checked.

    Returns
    -------
    int

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 20, 400)
    >>> f = fit(make_model("oscillator", {"k": 4.0}), t, np.cos(2.0 * t))   # 2 rad/s = 0.318 Hz
    >>> [system_line_number(hz, f, t) for hz in (0.318, 0.637, 0.5)]
    [1, 2, 0]
    """
    f_sys = system_frequency(fit)
    if f_sys is None:
        return 0
    cell = 1.5 / float(t[-1] - t[0])
    dist = [abs(f - k * f_sys) for k in range(1, harmonics + 1)]
    k = int(np.argmin(dist))
    return k + 1 if dist[k] <= cell else 0


def _not_harmonics(freqs, base, t):
    """The frequencies an additive pickup may start at: off the system's own lines, except the
    fundamental of a beating family (see ``BEATING_FAMILIES``)."""
    keep = 1 if base.model.family in BEATING_FAMILIES else 0
    return [f for f in freqs if system_line_number(f, base, t) <= keep]


def _harmonic_columns(model, p, t, k):
    q = {**p, "k_h": float(k), "a_h": 0.0, "b_h": 0.0}
    base = model.predict(t, q)
    return [model.predict(t, {**q, "a_h": 1.0}) - base, model.predict(t, {**q, "b_h": 1.0}) - base]


def _nyq_quarter(t):
    return 0.125 / float(np.median(np.diff(t)))
