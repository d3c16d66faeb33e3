"""Values in any unit: a mechanical record of tiny values is analysed on ``y / scale``.

Why: the finder's steps and starts are sized for values near 1 (a parameter at 0 is stepped by
1e-5, a cubic stiffness starts from one Gauss-Newton step off 0). A motion of nanometres given in
metres has a cubic stiffness of 1e17 per m^2 s^2: the step of 1e-5 moves the model by 1e-32 m, the
effect never leaves 0, and a Duffing oscillator at 1e-7 m was reported "nothing missing" (at 1e-8 m,
as two periodic pickups). Like time (:mod:`~odnn_sep.mismatch.timescale`), the record is analysed in
a unit where its values are near 1, and every parameter, interval, residual and level is mapped back.

What: an oscillator or free-fall record whose largest absolute value is under ``VALUE_LO`` is divided
by the power of 1000 that brings it to ``[0.1, 100)``. Every other record is analysed as given (the
benchmarks' and real recordings' values are all far above ``VALUE_LO``). Not rescaled: cooling
(absolute temperatures), the pendulum (angles in radians, accelerations in m/s^2), hum, 2-D fields,
user models and joint series.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

VALUE_LO = 1e-4
STEP = 1000.0
# Power of the value unit in each parameter's unit (x0 [m]: 1; k [1/s^2]: 0; beta [1/(m^2 s^2)]: -2).
# Every parameter of the two presets and of every effect they are tested for is listed.
PRESET_VALUE_POWERS = {
    "oscillator": {"k": 0, "c": 0, "m": 0, "x0": 1, "v0": 1},
    "freefall": {"g": 1, "h0": 1},
}
EFFECT_VALUE_POWERS = {
    "b_lin": 0, "q_drag": -1, "mu": 1, "beta": -2, "F": 1, "omega_f": 0, "phase_f": 0,
    "a_pk": 1, "b_pk": 1, "omega_pk": 0, "a_pk2": 1, "b_pk2": 1, "omega_pk2": 0,
    "offset": 1, "drift": 1, "tau": 0, "h_step": 1, "t_step": 0, "m_am": 0, "f_am": 0, "phase_am": 0,
}


def value_scale(model, y) -> float:
    """The power of 1000 the values are divided by for the analysis (1.0: analysed as given).

    Parameters
    ----------
    model : str or Model
        Preset name or model.
    y : array_like
        The record's values.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> [value_scale("oscillator", a * np.ones(3)) for a in (1.0, 2e-4, 5e-5, 1e-9)]
    [1.0, 1.0, 1e-06, 1e-09]
    >>> value_scale("cooling", 1e-9 * np.ones(3))      # temperatures are absolute
    1.0
    """
    from odnn_sep.mismatch.model import Model
    from odnn_sep.mismatch.presets import PRESETS
    if isinstance(model, Model):
        if model.preset is None or hasattr(model.preset, "series_times") or model.family not in PRESET_VALUE_POWERS:
            return 1.0
    elif str(model) not in PRESETS or PRESETS[str(model)].family not in PRESET_VALUE_POWERS:
        return 1.0
    try:
        a = np.abs(np.asarray(y, float))
    except (TypeError, ValueError):
        return 1.0
    a = a[np.isfinite(a)]
    top = float(a.max()) if a.size else 0.0
    if not 0 < top < VALUE_LO:
        return 1.0
    k = 0
    while top * STEP ** k < 0.1:
        k += 1
    return STEP ** -k


def value_power(family: str, name: str) -> int:
    """Power of the value unit in parameter ``name``'s unit (an input's gain ``kd_*``: 1).

    Examples
    --------
    >>> value_power("oscillator", "x0"), value_power("oscillator", "beta"), value_power("freefall", "kd_u")
    (1, -2, 1)
    """
    if name.startswith("kd_"):
        return 1
    if name in EFFECT_VALUE_POWERS:
        return EFFECT_VALUE_POWERS[name]
    return PRESET_VALUE_POWERS.get(family, {}).get(name, 0)


def fit_outward(f, vscale: float):
    """A fit's residual, prediction, disturbance and sums of squares in the caller's value unit.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 30); f = fit(make_model("freefall"), t, 5.0 - 4.9 * t ** 2 + 0.01 * np.sin(9 * t))
    >>> g = fit_outward(f, 1e-6)
    >>> bool(np.allclose(g.residual, 1e-6 * f.residual)), bool(np.isclose(g.rss, 1e-12 * f.rss))
    (True, True)
    """
    if f is None or vscale == 1.0:
        return f
    v2 = vscale * vscale
    return replace(f, prediction=f.prediction * vscale, disturbance=f.disturbance * vscale,
                   residual=f.residual * vscale, rss=f.rss * v2, floor2=f.floor2 * v2)
