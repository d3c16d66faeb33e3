"""Time in any unit: a record whose span is far from seconds-like is analysed on ``t / scale``.

Why: the numerics of the finder have absolute scales in them: a difference step of 1e-5 for a
parameter below 1, the neutral starts of the effects (a frequency of 1 rad per unit of time), the
ODE solver's first steps. With time in microseconds a stiffness of 4 s^-2 becomes 4e-12 and a free
fall's g 1e-11: steps, starts and tolerances no longer fit the problem, and the verdict read "the
model does not fit". With time in hours the parameters grow by 3600^k instead.

What: a record whose time span lies in ``[SPAN_LO, 1000 SPAN_LO)`` is analysed as given. Any other
span is divided by the power of 1000 that brings it into that range, so a record in ms, us or ns is
analysed on exactly the axis of the same record in seconds (and gives the same verdict, parameters
and intervals); a record in hours or days is brought to a span the finder handles. The preset's
parameters, the effects' parameters and their intervals are mapped back by the power of time in
their unit (:data:`PRESET_POWERS`, :data:`EFFECT_POWERS`): every number in the result is in the units
of the caller's time column. A user model is evaluated at the caller's times (its own parameters are
untouched); only the generic effects' parameters are mapped.

The preset defaults (``g = 9.81``, ``k = 1``) are starting values in seconds-like units and are used
on the internal axis as they are; starting values given by the caller are in the caller's units and
are converted. Not rescaled: hum records (mains frequencies are in Hz of seconds) and 2-D fields.
Joint series are rescaled by their longest series' span before they are stacked
(:func:`~odnn_sep.mismatch.timescale_result.explain_joint_in_caller_units`).
"""
from __future__ import annotations

import re
from dataclasses import replace

import numpy as np

# Spans in [SPAN_LO, 1000 SPAN_LO) are analysed as given: every preset's benchmark and golden record
# (0.6 s to 300 s) and the real recordings (0.5 s to 221 min given in minutes) lie there.
SPAN_LO = 0.3
STEP = 1000.0

# Power of the time unit in each parameter's unit (x [m], v0 [m/s]: 0, -1). Every parameter of a
# time-series preset and of every effect is listed, zeros included: tests check that none is missing.
PRESET_POWERS = {
    "oscillator": {"k": -2, "c": -1, "m": 0, "x0": 0, "v0": -1},
    "pendulum": {"w2": -2, "c": -1, "theta0": 0, "omega0": -1, "L": 0},
    "cooling": {"h": -1, "T_ambient": 0, "T0": 0},
    "freefall": {"g": -2, "h0": 0},
}
# an input's gain kd_<name> enters m x'' (oscillator, pendulum) or dT/dt (cooling)
INPUT_GAIN_POWERS = {"oscillator": -2, "pendulum": -2, "cooling": -1}
EFFECT_POWERS = {
    "b_lin": -1, "q_drag": 0, "mu": -2, "beta": -2, "s_angle": 0,
    "F": -2, "omega_f": -1, "phase_f": 0,          # a force per unit mass: an acceleration
    "a_pk": 0, "b_pk": 0, "omega_pk": -1, "offset": 0, "drift": -1, "tau": 1, "h_step": 0, "t_step": 1,
    "m_am": 0, "f_am": -1, "phase_am": 0, "r_rad": -1, "e_evap": -1, "B_2": 0, "lam_2": -1,
}


def time_scale(model, t) -> float:
    """The power of 1000 the time axis is divided by for the analysis (1.0: analysed as given).

    Parameters
    ----------
    model : str or Model
        Preset name or model.
    t : array_like
        Time stamps (anything that is not a strictly increasing 1-D series gives 1.0: explain()
        reports the problem).

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> [time_scale("oscillator", np.linspace(0, s, 50)) for s in (20.0, 2e4, 2e10, 200 / 3600)]
    [1.0, 1000.0, 1000000000.0, 0.001]
    >>> time_scale("hum", np.linspace(0, 2e4, 50))       # mains frequencies are in Hz of seconds
    1.0
    """
    if not _rescalable(model):
        return 1.0
    try:
        t = np.asarray(t, float)
    except (TypeError, ValueError):
        return 1.0
    if t.ndim != 1 or len(t) < 2 or not np.all(np.isfinite(t)) or not np.all(np.diff(t) > 0):
        return 1.0
    span = float(t[-1] - t[0])
    scale = 1.0
    while span / scale >= STEP * SPAN_LO:
        scale *= STEP
    while span / scale < SPAN_LO:
        scale /= STEP
    return scale


def _rescalable(model) -> bool:
    from odnn_sep.mismatch.model import Model
    from odnn_sep.mismatch.presets import PRESETS
    if isinstance(model, Model):
        # a joint model's preset holds its series' times in the caller's unit (see the module text)
        joint = hasattr(model.preset, "series_times")
        return model.ndim == 1 and not joint and (model.family in PRESET_POWERS or model.preset is None)
    return str(model) in PRESETS and PRESETS[str(model)].family in PRESET_POWERS


def time_power(family: str, name: str, own=frozenset()) -> int:
    """Power of the time unit in parameter ``name``'s unit (``own``: a user model's parameters, 0).

    Examples
    --------
    >>> time_power("oscillator", "k"), time_power("cooling", "kd_heater"), time_power("user", "tau")
    (-2, -1, 1)
    >>> time_power("user", "tau", own={"tau"})          # the user's own parameter: left alone
    0
    """
    if name in own:
        return 0
    if name.startswith("kd_"):
        return INPUT_GAIN_POWERS.get(family, 0)
    if name in EFFECT_POWERS:
        return EFFECT_POWERS[name]
    return PRESET_POWERS.get(family, {}).get(name, 0)


class TimeUnits:
    """Converts parameters, models and results between the caller's time unit and the internal axis.

    ``t_internal = t / scale`` and ``y_internal = y / vscale`` (:mod:`~odnn_sep.mismatch.valuescale`),
    so a parameter of time power ``q`` and value power ``r`` is ``value * scale ** -q * vscale ** -r``
    inside.

    Examples
    --------
    >>> u = TimeUnits(1e3, "oscillator")
    >>> u.inward({"k": 4e-6, "c": 1e-4, "x0": 1.0})
    {'k': 4.0, 'c': 0.1, 'x0': 1.0}
    >>> u.outward({"k": 4.0, "q_drag": 0.05, "omega_pk": 3.0})
    {'k': 4e-06, 'q_drag': 0.05, 'omega_pk': 0.003}
    >>> out = TimeUnits(1.0, "oscillator", vscale=1e-9).outward({"k": 4.0, "x0": 1.0, "beta": 0.5})
    >>> {k: float(f"{v:.6g}") for k, v in out.items()}
    {'k': 4.0, 'x0': 1e-09, 'beta': 5e+17}
    """

    def __init__(self, scale, family, own=frozenset(), aliases=None, vscale=1.0):
        self.scale, self.family, self.own = float(scale), family, frozenset(own)
        self.aliases = dict(aliases or {})    # a joint fit's per-series name -> the preset's name (h_mug1 -> h)
        self.vscale = float(vscale)           # values analysed as y / vscale (valuescale.py)

    def factor(self, name) -> float:
        """Internal value / caller's value of parameter ``name``."""
        base = self.aliases.get(name, name)
        f = self.scale ** -time_power(self.family, base, self.own)
        if self.vscale != 1.0 and base not in self.own:
            from odnn_sep.mismatch.valuescale import value_power
            f *= self.vscale ** -value_power(self.family, base)
        return f

    def _map(self, values, inverse):
        out = {}
        for k, v in values.items():
            f = self.factor(k)
            try:
                # a number given as text (a --param value) is converted too; a structural setting is not
                out[k] = v if f == 1.0 or isinstance(v, bool) else (float(v) / f if inverse else float(v) * f)
            except (TypeError, ValueError):
                out[k] = v
        return out

    def inward(self, values: dict) -> dict:
        """Caller's units -> internal units."""
        return self._map(values, inverse=False)

    def outward(self, values: dict) -> dict:
        """Internal units -> caller's units."""
        return self._map(values, inverse=True)

    def bounds_out(self, bounds: dict) -> dict:
        """Bounds in the caller's units (a positive factor keeps their order)."""
        return {k: (lo / self.factor(k), hi / self.factor(k)) for k, (lo, hi) in bounds.items()}

    def bounds_in(self, bounds: dict) -> dict:
        return {k: (lo * self.factor(k), hi * self.factor(k)) for k, (lo, hi) in bounds.items()}

    def stderr_out(self, stderr: dict) -> dict:
        return {k: (None if s is None else float(s) / self.factor(k)) for k, s in stderr.items()}


def internal_model(model, units: TimeUnits):
    """The model on the internal axis: a preset with its given starts converted; a user model
    evaluated at the caller's times (``t * scale``) with its own parameters as they are.

    Examples
    --------
    >>> internal_model("cooling", TimeUnits(1e3, "cooling"))      # a preset name passes through
    'cooling'
    """
    from odnn_sep.mismatch.model import Model
    if not isinstance(model, Model):
        return model
    if model.preset is not None:
        defaults = getattr(model.preset, "params", {})
        given = {k: v for k, v in model.start.items() if k not in defaults or defaults[k] != v}
        return replace(_input_times(model, 1 / units.scale), start={**model.start, **units.inward(given)},
                       bounds=units.bounds_in(model.bounds))
    user_builder, scale = model.builder, units.scale

    def builder(effects):
        predict = user_builder(effects)
        return lambda t, p: predict(np.asarray(t, float) * scale, p)
    builder.caller_builder = user_builder   # the caller's model is rebuilt from it (caller_model)
    return replace(model, builder=builder)


def _input_times(model, factor):
    """A driven preset's copy whose measured inputs' time stamps are multiplied by ``factor``."""
    if not getattr(model.preset, "inputs", None):
        return model
    import copy
    preset = copy.copy(model.preset)
    preset.inputs = {k: (np.asarray(tu, float) * factor, u) for k, (tu, u) in model.preset.inputs.items()}
    return replace(model, preset=preset, builder=preset.build)


def caller_model(model, units: TimeUnits):
    """The internal model (with its effects) back in the caller's units.

    Examples
    --------
    >>> from odnn_sep.mismatch.model import make_model
    >>> m = caller_model(make_model("oscillator"), TimeUnits(1e3, "oscillator"))
    >>> m.start["k"]                                  # a stiffness of 1 per s^2 in 1 per ms^2
    1e-06
    """
    model = _input_times(model, units.scale)
    builder = getattr(model.builder, "caller_builder", model.builder)
    if hasattr(model.preset, "series_times"):
        # a joint model's preset holds the internal series times: evaluate it on the internal axis
        inner, scale = model.builder, units.scale

        def builder(effects):
            predict = inner(effects)
            return lambda t, p: predict(np.asarray(t, float) / scale, units.inward(p))
    return replace(model, builder=builder, start=units.outward(model.start), bounds=units.bounds_out(model.bounds))


def inward_disturbance(spec, scale):
    """The ``disturbance`` option with its declared frequencies (Hz of the caller's time) made internal.

    Examples
    --------
    >>> inward_disturbance("periodic:0.002", 1e3)     # 0.002 per ms is 2 per s
    'auto,periodic:2.0'
    """
    from odnn_sep.mismatch.disturbances import parse_disturbance
    if spec is None or isinstance(spec, np.ndarray):
        return spec
    cls, freqs, lines = parse_disturbance(spec)   # a malformed option is refused here, in its own words
    return ",".join([cls] + [f"periodic:{f * scale!r}" for f in freqs] + (["lines"] if lines else []))


def inward_inputs(inputs, scale):
    """Inputs given with their own time stamps ``(tu, u)`` get the internal axis too.

    Examples
    --------
    >>> inward_inputs({"u": (np.array([0.0, 1000.0]), np.array([1.0, 2.0]))}, 1e3)["u"][0]
    array([0., 1.])
    """
    if not inputs:
        return inputs
    return {k: ((np.asarray(v[0], float) / scale, v[1]) if isinstance(v, tuple) else v) for k, v in inputs.items()}


_HZ = re.compile(r"(-?\d+(?:\.\d*)?(?:e[-+]?\d+)?) Hz")


def outward_hz_text(text, scale):
    """A sentence's frequencies (written ``<number> Hz``) in Hz of the caller's time unit.

    Examples
    --------
    >>> outward_hz_text("a periodic component at 3.7 Hz", 1e3)
    'a periodic component at 0.0037 Hz'
    """
    return _HZ.sub(lambda m: f"{float(m.group(1)) / scale:.4g} Hz", text)
