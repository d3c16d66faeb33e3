"""explain() on the internal time axis (:mod:`odnn_sep.mismatch.timescale`), its result in the caller's units.

Every fit of the result (calibration, candidates, their rivals, the final fit) gets its model,
parameters and standard errors back in the caller's units; intervals follow (they are computed from
those, and the log / logit intervals of bounded parameters scale with them). What is computed from
the time axis (where the residual exceeds the noise, the plain sentences, the warnings) is computed
again on the caller's times.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from odnn_sep.mismatch import timescale as ts
from odnn_sep.mismatch.disturbances import NyquistError


def explain_in_caller_units(model, t, y, options):
    """explain() on ``t / scale`` when the span calls for it, mapped back; None when analysed as given.

    Parameters
    ----------
    model : str or Model
        What explain() was given.
    t, y : array_like
        The caller's record.
    options : dict
        explain()'s keyword options.

    Returns
    -------
    MismatchResult or None

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch import explain
    >>> t = np.linspace(0, 0.6, 120); rng = np.random.default_rng(0)
    >>> y = 2.0 - 4.905 * t ** 2 + 0.001 * rng.normal(size=120)
    >>> s, ns = explain("freefall", t, y), explain("freefall", t * 1e9, y)    # time in ns
    >>> round(s.final_fit.params["g"], 3), round(ns.final_fit.params["g"] * 1e18, 3), ns.effects
    (9.81, 9.81, [])
    """
    from odnn_sep.mismatch.model import Model
    from odnn_sep.mismatch.presets import PRESETS
    from odnn_sep.mismatch.valuescale import value_scale
    scale, vscale = ts.time_scale(model, t), value_scale(model, y)
    if scale == 1.0 and vscale == 1.0:
        return None
    from odnn_sep.mismatch.explain import explain
    user = isinstance(model, Model) and model.preset is None
    family = model.family if isinstance(model, Model) else PRESETS[str(model)].family
    units = ts.TimeUnits(scale, family, own=set(model.start) if user else set(), vscale=vscale)
    opts = dict(options)
    if opts.get("params"):
        opts["params"] = units.inward(opts["params"])
    opts["disturbance"] = ts.inward_disturbance(opts.get("disturbance"), scale)
    opts["inputs"] = ts.inward_inputs(opts.get("inputs"), scale)
    t = np.asarray(t, float)
    y_in = np.asarray(y, float) / vscale if vscale != 1.0 else y
    try:
        res = explain(ts.internal_model(model, units), t / scale, y_in, **opts)
    except NyquistError as exc:
        raise exc.in_unit(scale) from None
    return _caller_result(res, t, units, options.get("alpha", 0.05))


def explain_joint_in_caller_units(name, series, params, shared, options):
    """explain_joint() of series whose times are far from seconds-like, mapped back; None when analysed as given.

    Every series is divided by the scale its longest span calls for (:func:`~odnn_sep.mismatch.timescale.time_scale`)
    before the series are stacked, so the stacked axis and the per-series parameters are internal together.

    Parameters
    ----------
    name : str
        Preset.
    series : dict
        ``{series name: (t, y)}`` in the caller's time unit.
    params, shared, options
        As given to :func:`~odnn_sep.mismatch.joint.explain_joint`.

    Returns
    -------
    MismatchResult or None

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 100, 40) * 1e9; rng = np.random.default_rng(0)     # ns
    >>> s = {f"mug{i}": (t, 21 + 70 * np.exp(-h * t) + 0.05 * rng.normal(size=40)) for i, h in enumerate((2e-11, 4e-11))}
    >>> res = explain_joint_in_caller_units("cooling", s, None, None, {})
    >>> res.effects, round(res.final_fit.params["h_mug1"] * 1e9, 3)
    ([], 0.04)
    """
    try:
        longest = max((np.asarray(t, float) for t, _ in series.values()), key=lambda a: float(np.ptp(a)))
    except (TypeError, ValueError):
        return None      # explain_joint() says what is wrong with the series
    scale = ts.time_scale(name, longest)
    if scale == 1.0:
        return None
    from odnn_sep.mismatch.joint import explain_joint
    from odnn_sep.mismatch.presets import PRESETS
    units = ts.TimeUnits(scale, PRESETS[str(name)].family)
    opts = dict(options)
    opts["disturbance"] = ts.inward_disturbance(opts.get("disturbance", "auto"), scale)
    inner = {n: (np.asarray(t, float) / scale, y) for n, (t, y) in series.items()}
    try:
        res = explain_joint(name, inner, params=units.inward(params) if params else params, shared=shared, **opts)
    except NyquistError as exc:
        raise exc.in_unit(scale) from None
    jp = res.joint
    units.aliases = {f"{k}_{lab}": k for k in jp.own for lab in jp.labels}
    return _caller_result(res, np.asarray(res.t, float) * scale, units, opts.get("alpha", 0.05), float(np.ptp(longest)))


def _caller_result(res, t, units, alpha, span=None):
    from odnn_sep.mismatch.inputs import physical_warnings
    from odnn_sep.mismatch.locate import locate
    res.t = t
    v = units.vscale
    if v != 1.0:     # levels in the caller's value unit (valuescale.py)
        res.y = np.asarray(res.y) * v
        res.noise_sigma = None if res.noise_sigma is None else res.noise_sigma * v
        res.heldout_rmse_before = None if res.heldout_rmse_before is None else res.heldout_rmse_before * v
        res.heldout_rmse_after = None if res.heldout_rmse_after is None else res.heldout_rmse_after * v
    res.model = ts.caller_model(res.model, units)
    res.calibration = replace(res.calibration, fit=_fit(res.calibration.fit, units),
                              identifiability=_identifiability(res.calibration.identifiability, units))
    res.final_fit = _fit(res.final_fit, units)
    res.candidates = [_candidate(c, units) for c in res.candidates]
    res.named = [_candidate(c, units) for c in res.named]
    res.disturbances = [_disturbance(d, res.final_fit, units, res.unit) for d in res.disturbances]
    res.declared = [ts.outward_hz_text(s, units.scale) for s in res.declared]
    res.where = locate(t, res.calibration.fit.residual, sigma=res.noise_sigma, alpha=alpha)
    from odnn_sep.mismatch.identifiability import unidentified_warnings
    res.warnings = physical_warnings(res.final_fit.params) + unidentified_warnings(res.calibration.fit, res.final_fit)
    span = float(np.ptp(t)) if span is None else span
    if units.scale != 1.0:
        res.notes.append(f"time analysed as t / {units.scale:g} (the span of t, {span:.4g}, is far from "
                         f"seconds-like); every parameter and interval is reported in the units of t")
    if v != 1.0:
        top = float(np.max(np.abs(res.y)))
        res.notes.append(f"values analysed as y / {v:g} (the largest, {top:.3g}, is far under 1); every "
                         f"parameter, interval and level is reported in the units of y")
    return res


def _fit(f, units):
    """A fit in the caller's units (residuals and sums of squares scale with the values' unit only)."""
    if f is None:
        return None
    from odnn_sep.mismatch.valuescale import fit_outward
    return replace(fit_outward(f, units.vscale), model=ts.caller_model(f.model, units), params=units.outward(f.params),
                   stderr=units.stderr_out(f.stderr))


def _candidate(c, units, seen=None):
    seen = {} if seen is None else seen
    if id(c) in seen:
        return seen[id(c)]
    out = replace(c, fit=_fit(c.fit, units))
    v = units.vscale
    if v != 1.0:
        out.heldout_rmse = None if c.heldout_rmse is None else c.heldout_rmse * v
        out.heldout_mse = None if c.heldout_mse is None else np.asarray(c.heldout_mse) * v * v
    seen[id(c)] = out
    out.rival_candidates = [_candidate(r, units, seen) for r in c.rival_candidates]
    return out


def _identifiability(d, units):
    if not d or "gauss_newton_step" not in d:
        return d
    return {**d, "gauss_newton_step": units.outward(d["gauss_newton_step"])}


def _disturbance(d, final, units, unit):
    """A found disturbance's entry with its parameters, intervals, times and sentence in the caller's units."""
    from odnn_sep.mismatch.disturbances import describe, linear_model
    d = dict(d)
    v = units.vscale
    if d["effect"] == "spikes":
        d["at"] = [a * units.scale for a in d.get("at", [])]
        if v != 1.0:
            from odnn_sep.mismatch.spikes import Spikes
            d["excess"] = [e * v for e in d.get("excess", [])]
            d["largest"], d["noise_level"] = d["largest"] * v, d["noise_level"] * v
            count = int(d["parameters"]["count"])
            fake = Spikes(index=np.zeros(count, int), excess=np.full(count, d["largest"]), sigma=d["noise_level"])
            d["description"] = fake.description(unit)
        return d
    if d["effect"] == "clipping":
        if v != 1.0:
            from odnn_sep.mismatch.saturation import Saturation
            rails = [(side, val * v, k) for side, val, k in d["rails"]]
            d = Saturation(keep=np.zeros(0, bool), rails=rails).entry(unit)
        return d
    d["parameters"] = units.outward(d["parameters"])
    d["interval95"] = {k: (None if v is None else [x / units.factor(k) for x in v]) for k, v in d["interval95"].items()}
    d["description"] = describe(d["effect"], final.params, model_family=final.model.family,
                                linear=linear_model(final.model), unit=unit)
    return d
