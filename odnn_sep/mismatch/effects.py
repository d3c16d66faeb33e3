"""The fixed vocabulary of physical effects the mismatch finder can name.

Each effect is a small record: its name (the string that appears in reports), a one-line
description, its extra parameters with neutral values (the value at which the effect vanishes)
and bounds, and the model families it applies to. *How* an effect enters a model lives with the
model: presets fold family-specific effects into their ODE right-hand side or closed form, and the
generic effects (offset, drift, time_delay, periodic_forcing, amplitude_modulation) wrap any model's
output, including user callables (see :func:`apply_generic`). ``channel_coupling`` needs the other
channels of the recording and lives in :mod:`odnn_sep.mismatch.coupling`.

Effects that a family's own parameters already absorb exactly are not offered for that family
(a time delay in an autonomous ODE whose initial state is refitted, a constant offset in Newton
cooling whose ambient temperature is refitted): they could never be told apart from the
calibration and would only add look-elsewhere false alarms.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Effect:
    """One named effect: extra parameters, their neutral values and bounds.

    The registry :data:`EFFECTS` maps every effect name to its record.

    Examples
    --------
    >>> e = EFFECTS["offset"]
    >>> e.name, e.params, e.generic, e.n_params()
    ('offset', {'offset': 0.0}, True, 1)
    >>> "cooling" in EFFECTS["radiation"].families
    True
    """

    name: str
    description: str
    params: dict            # parameter -> neutral value (effect absent)
    bounds: dict            # parameter -> (lo, hi)
    families: frozenset     # model families it applies to ("*" = any, via the generic wrapper)
    generic: bool = False   # True: implemented by apply_generic on the model output
    discrete: dict = field(default_factory=dict)  # parameter -> number of discrete choices searched

    def n_params(self) -> int:
        """Number of extra parameters the effect adds (see the class example)."""
        return len(self.params)


_MECH = frozenset({"oscillator", "pendulum"})
INF = np.inf
STEP_CHOICES = 1000   # a step's instant: a choice among about this many samples (its BIC cost)

EFFECTS: dict[str, Effect] = {e.name: e for e in [
    Effect("linear_damping", "linear (viscous, Stokes) damping force -b v missing from the model",
           {"b_lin": 0.0}, {"b_lin": (0.0, INF)}, frozenset({"freefall"})),
    Effect("quadratic_drag", "quadratic (air) drag force -q v|v| missing from the model",
           {"q_drag": 0.0}, {"q_drag": (0.0, INF)}, _MECH | {"freefall"}),
    Effect("coulomb_friction", "Coulomb (dry) friction force -mu sign(v) missing from the model",
           {"mu": 0.0}, {"mu": (0.0, INF)}, _MECH),
    Effect("cubic_stiffness", "cubic (Duffing) stiffness -beta x^3 missing from the restoring force",
           {"beta": 0.0}, {"beta": (-INF, INF)}, frozenset({"oscillator"})),
    Effect("large_angle", "large-angle restoring force: sin(theta) instead of theta (s=1 is the full sine)",
           {"s_angle": 0.0}, {"s_angle": (-5.0, 5.0)}, frozenset({"pendulum"})),
    Effect("periodic_forcing", "periodic forcing F cos(omega t + phase) at an unknown frequency",
           {"F": 0.0, "omega_f": 1.0, "phase_f": 0.0},
           {"F": (-INF, INF), "omega_f": (0.0, INF), "phase_f": (-INF, INF)},
           _MECH, generic=True),
    # an additive sinusoid (a pickup, a vibration of the sensor): for a linear model it gives the same
    # data as a periodic force, so it is reported as a disturbance, never as physics
    Effect("periodic_pickup", "an additive periodic component a cos(omega t) + b sin(omega t) in the recording",
           {"a_pk": 0.0, "b_pk": 0.0, "omega_pk": 1.0},
           {"a_pk": (-INF, INF), "b_pk": (-INF, INF), "omega_pk": (0.0, INF)},
           _MECH | {"cooling", "freefall", "hum", "user"}, generic=True),
    # a second additive sinusoid (two pickups at once, a pickup and its mirror): offered by the forward
    # selection only once periodic_pickup is in the model, so it belongs to no family of its own
    Effect("periodic_pickup_2", "a second additive periodic component a cos(omega t) + b sin(omega t) in the "
           "recording",
           {"a_pk2": 0.0, "b_pk2": 0.0, "omega_pk2": 1.0},
           {"a_pk2": (-INF, INF), "b_pk2": (-INF, INF), "omega_pk2": (0.0, INF)},
           frozenset(), generic=True),
    # its 2D counterpart: a stripe across a field (interference, a scanner artefact), wave vector (kx, ky)
    Effect("periodic_pattern", "an additive spatial periodic pattern a cos(kx x + ky y) + b sin(kx x + ky y) "
           "(a stripe across the field)",
           {"a_pp": 0.0, "b_pp": 0.0, "kx_pp": 1.0, "ky_pp": 0.0},
           {"a_pp": (-INF, INF), "b_pp": (-INF, INF), "kx_pp": (-INF, INF), "ky_pp": (-INF, INF)},
           frozenset({"heat2d"}), generic=True),
    Effect("offset", "constant offset added to the observations (sensor bias)",
           {"offset": 0.0}, {"offset": (-INF, INF)},
           _MECH | {"hum", "heat2d", "user"}, generic=True),
    Effect("drift", "linear drift d (t - t_start) added to the observations",
           {"drift": 0.0}, {"drift": (-INF, INF)},
           _MECH | {"cooling", "freefall", "hum", "user"}, generic=True),
    # a step of the recording's level at one instant (a sensor bumped, a range switched, a
    # recalibration): where it sits is a discrete choice among the samples (searched by the start,
    # held during the fit)
    Effect("step_offset", "a step h_step of the observations' level at the time t_step",
           {"h_step": 0.0, "t_step": 0.0}, {"h_step": (-INF, INF)},
           _MECH | {"cooling", "freefall", "user"}, generic=True, discrete={"t_step": STEP_CHOICES}),
    Effect("time_delay", "time delay / clock offset: observations follow the model at t - tau",
           {"tau": 0.0}, {"tau": (-INF, INF)}, frozenset({"freefall", "user"}), generic=True),
    Effect("amplitude_modulation", "amplitude modulation (1 + m cos(2 pi f_am t + phase)) of the output",
           {"m_am": 0.0, "f_am": 0.1, "phase_am": 0.0},
           {"m_am": (-1.0, 1.0), "f_am": (0.0, INF), "phase_am": (-INF, INF)},
           _MECH | {"hum", "user"}, generic=True),
    Effect("radiation", "radiative heat loss (T^4 - T_amb^4), linearised coefficient r",
           {"r_rad": 0.0}, {"r_rad": (-INF, INF)}, frozenset({"cooling"})),
    Effect("evaporation", "evaporative heat loss following the vapour pressure psat(T) - psat(T_amb)",
           {"e_evap": 0.0}, {"e_evap": (-INF, INF)}, frozenset({"cooling"})),
    Effect("two_body_heat", "second body exchanging heat (two-exponential cooling B exp(-lam t))",
           {"B_2": 0.0, "lam_2": 1.0}, {"B_2": (-INF, INF), "lam_2": (0.0, INF)}, frozenset({"cooling"})),
    Effect("missing_harmonic", "a harmonic k f0 of the hum that the model leaves out",
           {"k_h": 2.0, "a_h": 0.0, "b_h": 0.0}, {"a_h": (-INF, INF), "b_h": (-INF, INF)},
           frozenset({"hum"}), discrete={"k_h": 6}),
    Effect("frequency_drift", "mains frequency drifting linearly, f(t) = f0 + f1 (t - t_mid) (FM)",
           {"f1": 0.0}, {"f1": (-INF, INF)}, frozenset({"hum"})),
    # implemented on the audio engine's basebands (odnn_sep.mismatch.hum_engine), where the slow phase
    # of every harmonic is seen; short records on their samples do not offer it
    Effect("frequency_wander", "mains frequency wandering slowly, f(t) = f0 + df_w cos(2 pi f_w t + phase_w) (FM)",
           {"df_w": 0.0, "f_w": 0.02, "phase_w": 0.0},
           {"df_w": (-INF, INF), "f_w": (0.0, INF), "phase_w": (-INF, INF)}, frozenset({"hum"})),
    # parameters kappa_<channel>, kappaq_<channel> per aux channel (their names depend on the data:
    # see odnn_sep.mismatch.coupling); offered only when explain() is given aux channels
    Effect("channel_coupling", "crosstalk: a scaled (and phase-shifted: quadrature gain) copy of another "
           "channel's non-hum content coupled into this channel",
           {}, {}, frozenset({"hum"})),
    Effect("extra_source", "an extra point source (position xs, ys; strength S_extra) in the 2D field",
           {"xs": 0.0, "ys": 0.0, "S_extra": 0.0},
           {"xs": (-INF, INF), "ys": (-INF, INF), "S_extra": (-INF, INF)}, frozenset({"heat2d"})),
    Effect("source_moved", "a given source sits elsewhere: source k_src displaced by (dx_src, dy_src)",
           {"k_src": 1.0, "dx_src": 0.0, "dy_src": 0.0}, {"dx_src": (-INF, INF), "dy_src": (-INF, INF)},
           frozenset({"heat2d"}), discrete={"k_src": 2}),
]}

VOCABULARY = tuple(EFFECTS)

# effects the data cannot tell apart from an additive disturbance: found, absorbed and reported as
# disturbances (verdict.disturbances), never named as missing physics
DISTURBANCE_EFFECTS = ("periodic_pickup", "periodic_pickup_2", "periodic_pattern", "offset", "drift", "step_offset")

# effects that are alternatives, never added together (two drag laws for one falling body)
EXCLUSIVE = (frozenset({"linear_damping", "quadratic_drag"}),
             # a moved given source and an extra source beside it explain the same residual
             frozenset({"extra_source", "source_moved"}))


def compatible(effect: str, present) -> bool:
    """False when ``effect`` is an alternative to one already in the model.

    Parameters
    ----------
    effect : str
        Candidate effect name.
    present : iterable of str
        Effects already in the model.

    Returns
    -------
    bool
        Whether ``effect`` may be added beside ``present``.

    Examples
    --------
    >>> compatible("quadratic_drag", ["linear_damping"]), compatible("quadratic_drag", ["offset"])
    (False, True)
    """
    return not any(effect in g and (g - {effect}) & set(present) for g in EXCLUSIVE)


def effect_param_names(effect: str, params: dict) -> list[str]:
    """The parameters of ``effect`` present in ``params`` (coupling gains are named per channel).

    Parameters
    ----------
    effect : str
        Effect name.
    params : dict
        Parameter values of a fit.

    Returns
    -------
    list of str
        Names of the effect's parameters found in ``params``.

    Examples
    --------
    >>> effect_param_names("offset", {"k": 1.0, "offset": 0.2})
    ['offset']
    >>> effect_param_names("channel_coupling", {"k": 1.0, "kappa_ref": 0.3})
    ['kappa_ref']
    """
    if effect == "channel_coupling":
        return [k for k in params if k.startswith(("kappa_", "kappaq_"))]
    return [k for k in EFFECTS[effect].params if k in params]


def applicable(family: str) -> list[str]:
    """Names of the effects that apply to a model family (``"user"`` for callables).

    Parameters
    ----------
    family : str
        Model family (``"oscillator"``, ``"cooling"``, ..., ``"user"``).

    Returns
    -------
    list of str
        Effect names, in the order of :data:`EFFECTS`.

    Examples
    --------
    >>> applicable("freefall")
    ['linear_damping', 'quadratic_drag', 'periodic_pickup', 'drift', 'step_offset', 'time_delay']
    """
    return [name for name, e in EFFECTS.items() if family in e.families]


def apply_generic(names, predict_fn, *, t0: float):
    """Wrap ``predict_fn(t, p)`` with the generic effects named in ``names``.

    The caller passes only the generic effects its model does not implement natively (a preset
    folds periodic forcing into its equation of motion, for instance). ``t0`` is the first time
    stamp, so drift is anchored at the start of the record.

    Parameters
    ----------
    names : iterable of str
        Generic effects to add.
    predict_fn : callable
        ``predict_fn(t, p) -> y``, the model without them.
    t0 : float
        First time stamp.

    Returns
    -------
    callable
        ``wrapped(t, p) -> y`` (``predict_fn`` itself when ``names`` is empty).

    Examples
    --------
    >>> import numpy as np
    >>> f = apply_generic(["offset", "drift"], lambda t, p: 0 * t, t0=1.0)
    >>> f(np.array([1.0, 3.0]), {"offset": 2.0, "drift": 0.5}).tolist()
    [2.0, 3.0]
    """
    names = list(names)
    if not names:
        return predict_fn

    def wrapped(t, p):
        tt = t - p["tau"] if "time_delay" in names else t
        out = predict_fn(tt, p)
        if "amplitude_modulation" in names:
            out = out * (1.0 + p["m_am"] * np.cos(2 * np.pi * p["f_am"] * t + p["phase_am"]))
        if "periodic_forcing" in names:
            out = out + p["F"] * np.cos(p["omega_f"] * t + p["phase_f"])
        for name, sfx in (("periodic_pickup", ""), ("periodic_pickup_2", "2")):
            if name in names:
                w = p["omega_pk" + sfx]
                out = out + p["a_pk" + sfx] * np.cos(w * t) + p["b_pk" + sfx] * np.sin(w * t)
        if "periodic_pattern" in names:
            ph = p["kx_pp"] * t[:, 0] + p["ky_pp"] * t[:, 1]
            out = out + p["a_pp"] * np.cos(ph) + p["b_pp"] * np.sin(ph)
        if "offset" in names:
            out = out + p["offset"]
        if "drift" in names:
            out = out + p["drift"] * (t - t0)
        if "step_offset" in names:
            out = out + p["h_step"] * (t >= p["t_step"])
        return out

    return wrapped
