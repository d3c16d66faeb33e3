"""Thermal and mains-hum presets: Newton cooling, hum (heat2d lives in presets_heat2d)."""
from __future__ import annotations

import numpy as np

from odnn_sep.core.linalg import solve
from odnn_sep.mismatch.inputs import (
    drive_function,
    drive_on_grid,
    gain_names,
    linear_response,
    regression_start,
)
from odnn_sep.mismatch.presets_base import INF, Preset, integrate_ode
from odnn_sep.mismatch.presets_heat2d import Heat2D, parse_sources  # noqa: F401  (re-exported)


def _psat(T):
    """Saturation vapour pressure (hPa, Magnus formula), T in deg C."""
    return 6.1094 * np.exp(17.625 * T / (T + 243.04))


def _newton_fit(t, y):
    """Variable projection over h: for each decay rate, T_amb and amplitude are linear."""
    tau = t - t[0]
    span = max(tau[-1], 1e-12)
    best = None
    for h in np.geomspace(0.05 / span, 50.0 / span, 60):
        F = np.column_stack([np.ones_like(tau), np.exp(-h * tau)])
        coef = solve(F, y, method="lstsq")
        rss = float(np.sum((F @ coef - y) ** 2))
        if best is None or rss < best[0]:
            best = (rss, h, coef)
    _, h, (ta, amp) = best
    return {"h": float(h), "T_ambient": float(ta), "T0": float(ta + amp)}


class Cooling(Preset):
    """Newton cooling ``dT/dt = -h (T - T_ambient)`` from ``T0`` at the first sample (deg C).

    Radiation and evaporation are integrated inside the equation; measured inputs add a drive.

    Examples
    --------
    >>> import numpy as np
    >>> pre = Cooling()
    >>> t = np.array([0.0, 10.0])
    >>> np.round(pre.build(())(t, {"h": 0.1, "T_ambient": 20.0, "T0": 90.0}), 3).tolist()
    [90.0, 45.752]
    >>> t = np.linspace(0, 50, 100)
    >>> g = pre.initial_guess(t, 20 + 70 * np.exp(-0.05 * t), {})   # a grid search over h
    >>> sorted(g), abs(g["T_ambient"] - 20) < 2, abs(g["T0"] - 90) < 2
    (['T0', 'T_ambient', 'h'], True, True)
    """

    name = "cooling"
    family = "cooling"
    description = "Newton cooling dT/dt = -h (T - T_ambient), T(t_start) = T0 (temperatures in deg C)"
    params = {"h": 0.05, "T_ambient": 20.0, "T0": 90.0}
    bounds = {"h": (0.0, INF)}
    native = frozenset({"radiation", "evaporation", "two_body_heat"})

    def build(self, effects):
        effects = frozenset(effects) & self.native
        ode = effects & {"radiation", "evaporation"}

        def predict(t, p):
            tau = t - t[0]
            ta = p["T_ambient"]
            drive = drive_function(self.inputs, p)
            if not ode and drive is None:
                out = ta + (p["T0"] - ta) * np.exp(-p["h"] * tau)
            elif not ode:
                with np.errstate(all="ignore"):
                    out = linear_response([[-p["h"]]], [1.0], [p["T0"]], t,
                                          p["h"] * ta + drive_on_grid(self.inputs, p, t))[:, 0]
            else:
                tak = ta + 273.15
                rad_norm = 4.0 * tak ** 3
                # d psat/dT at T_ambient: makes e_evap a linearised rate comparable with h
                evap_norm = _psat(ta) * 17.625 * 243.04 / (ta + 243.04) ** 2

                def rhs(tt, s):
                    T = s[0]
                    d = -p["h"] * (T - ta)
                    if "radiation" in ode:
                        d -= p["r_rad"] * ((T + 273.15) ** 4 - tak ** 4) / rad_norm
                    if "evaporation" in ode:
                        d -= p["e_evap"] * (_psat(T) - _psat(ta)) / evap_norm
                    if drive is not None:
                        d += drive(tt)
                    return [d]

                out = integrate_ode(self.name, rhs, [p["T0"]], t, p)[:, 0]
            if "two_body_heat" in effects:
                out = out + p["B_2"] * (np.exp(-p["lam_2"] * tau) - np.exp(-p["h"] * tau))
            return out

        return predict

    def canonical(self, effects, p):
        """Two-exponential cooling is the same curve with h and lam_2 swapped; the second body is the
        fast one (lam_2 > h), so B_2 and lam_2 always mean the same thing (and their intervals too).

        Without radiation, evaporation or inputs, ``Ta + (T0-Ta-B) e^(-h t) + B e^(-lam t)`` is
        unchanged by h <-> lam_2, B_2 -> T0 - Ta - B_2.
        """
        if ("two_body_heat" not in effects or set(effects) & {"radiation", "evaporation"} or self.inputs
                or not p["lam_2"] < p["h"]):
            return None
        return {**p, "h": p["lam_2"], "lam_2": p["h"], "B_2": p["T0"] - p["T_ambient"] - p["B_2"]}

    def initial_guess(self, t, y, p):
        if self.inputs:
            # regress T' on T, 1 and the inputs: h, h T_ambient and the gains
            coef = regression_start(t, y, self.inputs, order=1)
            h = float(max(coef[0], 1e-9))
            out = {"h": h, "T_ambient": float(-coef[1] / h), "T0": float(y[0])}
            out.update({g: float(c) for g, c in zip(gain_names(self.inputs), coef[2:], strict=True)})
            return out
        return _newton_fit(t, y)


# the two mains frequencies, each with the other; a start at one also tries the other (Hum.initial_guess)
NOMINAL_MAINS = {50.0: 60.0, 60.0: 50.0}
# the other mains is taken when its lines leave under this share of the given one's residual sum of squares
OTHER_MAINS_RSS = 0.5


def _refine_f0(t, y, f0, harmonics):
    """(rss, f, coef) of the best hum fit over a fine grid around ``f0`` (the grid frequency is never
    exactly nominal).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(4000) / 4000.0
    >>> round(float(_refine_f0(t, np.cos(2 * np.pi * 60.2 * t), 60.0, 1)[1]), 1)
    60.2
    """
    span = t[-1] - t[0]
    best = None
    for f in f0 + np.linspace(-0.5, 0.5, 201) / max(span, 1e-9) * 4:
        F = hum_columns(t, f, harmonics)
        coef = solve(F, y, method="lstsq")
        rss = float(np.sum((F @ coef - y) ** 2))
        if best is None or rss < best[0]:
            best = (rss, f, coef)
    return best


class Hum(Preset):
    """Mains hum: ``sum_h a_h cos(2 pi h f0 t) + b_h sin(2 pi h f0 t)`` over ``harmonics`` terms.

    Examples
    --------
    >>> import numpy as np
    >>> pre = Hum()
    >>> pre.amplitude_names(2)
    ['a1', 'b1', 'a2', 'b2']
    >>> p = {"f0": 50.0, "harmonics": 1, "a1": 1.0, "b1": 0.0}
    >>> np.round(pre.build(())(np.array([0.0, 0.01]), p), 6).tolist()
    [1.0, -1.0]
    """

    name = "hum"
    family = "hum"
    description = "mains hum: sum over harmonics h=1..H of a_h cos(2 pi h f0 t) + b_h sin(2 pi h f0 t)"
    params = {"f0": 50.0, "harmonics": 1}
    bounds = {"f0": (0.0, INF)}
    fixed = frozenset({"harmonics"})
    native = frozenset({"missing_harmonic", "frequency_drift"})
    # the wander is seen on the slow phase of every harmonic: long records on the audio engine only
    not_offered = frozenset({"frequency_wander"})

    def amplitude_names(self, harmonics):
        """Amplitude parameters ``a1, b1, a2, b2, ...`` of ``harmonics`` harmonics (see the class example)."""
        return [f"{ab}{h}" for h in range(1, int(harmonics) + 1) for ab in ("a", "b")]

    def build(self, effects):
        effects = frozenset(effects) & self.native

        def predict(t, p):
            tm = 0.5 * (t[0] + t[-1])
            phase = p["f0"] * t
            if "frequency_drift" in effects:
                phase = phase + 0.5 * p["f1"] * ((t - tm) ** 2 - (t[0] - tm) ** 2)
            out = np.zeros_like(t)
            for h in range(1, int(p["harmonics"]) + 1):
                w = 2 * np.pi * h * phase
                out += p[f"a{h}"] * np.cos(w) + p[f"b{h}"] * np.sin(w)
            if "missing_harmonic" in effects:
                w = 2 * np.pi * p["k_h"] * phase
                out += p["a_h"] * np.cos(w) + p["b_h"] * np.sin(w)
            return out

        return predict

    def initial_guess(self, t, y, p):
        f0 = float(p.get("f0", 50.0))
        H = int(p.get("harmonics", 1))
        best = _refine_f0(t, y, f0, H)
        if f0 in NOMINAL_MAINS:
            # f0 is only a starting value and defaults to 50: a 60 Hz record (the Americas) calibrated near
            # 50 Hz, its own line then absorbed as a "pickup" and the verdict read "the record does not
            # show the model". The other mains is taken only when it explains far more of the record.
            other = _refine_f0(t, y, NOMINAL_MAINS[f0], H)
            if other[0] < OTHER_MAINS_RSS * best[0]:
                best = other
        _, f, coef = best
        out = {"f0": float(f)}
        out.update({n: float(c) for n, c in zip(self.amplitude_names(H), coef, strict=True)})
        return out


def hum_columns(t, f0, H):
    """Design matrix of the hum: cos and sin columns of the harmonics 1..H of ``f0``.

    Parameters
    ----------
    t : ndarray
        Sample times (s).
    f0 : float
        Fundamental frequency (Hz).
    H : int
        Number of harmonics.

    Returns
    -------
    ndarray, shape (len(t), 2 H)
        Columns ``cos(2 pi h f0 t), sin(2 pi h f0 t)`` for h = 1..H.

    Examples
    --------
    >>> import numpy as np
    >>> hum_columns(np.array([0.0, 0.005]), 50.0, 2).round(6).tolist()
    [[1.0, 0.0, 1.0, 0.0], [0.0, 1.0, -1.0, 0.0]]
    """
    cols = []
    for h in range(1, H + 1):
        cols += [np.cos(2 * np.pi * h * f0 * t), np.sin(2 * np.pi * h * f0 * t)]
    return np.column_stack(cols)
