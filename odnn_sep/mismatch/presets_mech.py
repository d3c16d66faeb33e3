"""Mechanical presets: oscillator, pendulum, free fall (closed forms where they exist, else LSODA)."""
from __future__ import annotations

import math

import numpy as np

from odnn_sep.core.linalg import solve
from odnn_sep.errors import InputError
from odnn_sep.mismatch.inputs import (
    drive_function,
    drive_on_grid,
    gain_names,
    linear_response,
    regression_start,
)
from odnn_sep.mismatch.presets_base import (
    INF,
    Preset,
    dominant_omega,
    friction_scale,
    integrate_ode,
    sinusoid_start,
)


def linear_oscillator(tau, k, c, m, x0, v0, *, with_velocity=False):
    """Closed-form solution of m x'' + c x' + k x = 0 (complex roots cover every damping regime).

    Parameters
    ----------
    tau : ndarray
        Time since the start.
    k, c, m : float
        Stiffness, damping and mass.
    x0, v0 : float
        Initial position and velocity.
    with_velocity : bool, optional
        Also return the velocity.

    Returns
    -------
    ndarray or tuple of ndarray or None
        The position (and velocity); None at critical damping (repeated root), where the caller
        integrates numerically instead.

    Examples
    --------
    >>> import numpy as np
    >>> x = linear_oscillator(np.array([0.0, np.pi / 2]), 1.0, 0.0, 1.0, 1.0, 0.0)
    >>> np.round(x, 6).tolist()
    [1.0, 0.0]
    >>> linear_oscillator(np.array([0.0]), 1.0, 2.0, 1.0, 1.0, 0.0) is None   # critical damping
    True
    """
    disc = complex(c * c - 4 * m * k)
    r = np.sqrt(disc)
    l1, l2 = (-c + r) / (2 * m), (-c - r) / (2 * m)
    if abs(l1 - l2) < 1e-9 * max(1.0, abs(l1)):
        return None
    a = (v0 - l2 * x0) / (l1 - l2)
    b = x0 - a
    with np.errstate(all="ignore"):
        e1, e2 = np.exp(l1 * tau), np.exp(l2 * tau)
        x = np.real(a * e1 + b * e2)
        if with_velocity:
            return x, np.real(a * l1 * e1 + b * l2 * e2)
        return x


class Oscillator(Preset):
    """Mass-spring oscillator ``m x'' + c x' + k x = 0``, observed as the position ``x``.

    Closed form when no effect is added; the effects quadratic drag, Coulomb friction, cubic
    stiffness and periodic forcing are integrated inside the equation of motion.

    Examples
    --------
    >>> import numpy as np
    >>> pre = Oscillator()
    >>> f = pre.build(())
    >>> np.round(f(np.array([0.0, np.pi / 2]), dict(pre.params, k=1.0)), 6).tolist()
    [1.0, 0.0]
    >>> t = np.linspace(0, 20, 400)
    >>> round(float(pre.initial_guess(t, np.cos(2.0 * t), pre.params)["k"]), 1)
    4.0
    """

    name = "oscillator"
    family = "oscillator"
    description = "mass-spring oscillator m x'' + c x' + k x = 0 (free, damped; driven via periodic_forcing)"
    params = {"k": 1.0, "c": 0.0, "m": 1.0, "x0": 1.0, "v0": 0.0}
    bounds = {"k": (0.0, INF), "c": (-INF, INF)}
    fixed = frozenset({"m"})
    native = frozenset({"quadratic_drag", "coulomb_friction", "cubic_stiffness", "periodic_forcing"})

    def _restoring(self, x, p, effects):
        f = p["k"] * x
        if "cubic_stiffness" in effects:
            f = f + p["beta"] * x ** 3
        return f

    def _initial_state(self, p):
        return [p["x0"], p["v0"]]

    def _closed_form(self, tau, p):
        r = linear_oscillator(tau, p["k"], p["c"], p["m"], p["x0"], p["v0"], with_velocity=True)
        return r

    def _observe(self, t, x, v, p, effects, eps):
        return x

    def build(self, effects):
        effects = frozenset(effects) & self.native
        name = self.name

        def predict(t, p):
            t0 = t[0]
            if not effects and not self.inputs:
                out = self._closed_form(t - t0, p)
                if out is not None and all(np.all(np.isfinite(o)) for o in out):
                    return self._observe(t, out[0], out[1], p, effects, 0.0)
            if not effects and self.inputs:
                m = p.get("m", 1.0)
                A = [[0.0, 1.0], [-self._stiffness(p), -float(p["c"]) / m]]
                with np.errstate(all="ignore"):
                    x = linear_response(A, [0.0, 1.0 / m], self._initial_state(p), t,
                                        drive_on_grid(self.inputs, p, t))
                if np.all(np.isfinite(x)):
                    return self._observe(t, x[:, 0], x[:, 1], p, effects, 0.0)
            m = p.get("m", 1.0)
            eps = friction_scale(max(abs(p.get("v0", p.get("omega0", 0.0))),
                                      np.sqrt(abs(self._stiffness(p))) * abs(self._amplitude(p))))

            rhs = self._make_rhs(p, effects, m, eps)
            sol = integrate_ode(name, rhs, self._initial_state(p), t, p)
            return self._observe(t, sol[:, 0], sol[:, 1], p, effects, eps)

        return predict

    def _make_rhs(self, p, effects, m, eps):
        # Specialised closure with plain floats and math functions: LSODA calls it thousands of
        # times per integration, so dict lookups and numpy scalar calls would dominate the cost.
        c = float(p["c"]) / m
        k = float(p.get("k", p.get("w2", 0.0))) / m
        beta = float(p.get("beta", 0.0)) / m if "cubic_stiffness" in effects else 0.0
        s_ang = float(p.get("s_angle", 0.0)) if "large_angle" in effects else 0.0
        q = float(p.get("q_drag", 0.0)) / m if "quadratic_drag" in effects else 0.0
        mu = float(p.get("mu", 0.0)) / m if "coulomb_friction" in effects else 0.0
        forced = "periodic_forcing" in effects
        F = float(p.get("F", 0.0)) / m
        wf = float(p.get("omega_f", 0.0))
        ph = float(p.get("phase_f", 0.0))
        sin, cos, tanh = math.sin, math.cos, math.tanh
        drive = drive_function(self.inputs, p)
        if drive is not None:
            def driven(tt, st):
                v, a = free(tt, st)
                return (v, a + drive(tt) / m)

        def free(tt, st):
            x, v = st
            if s_ang:
                a = -k * ((1.0 - s_ang) * x + s_ang * sin(x))
            else:
                a = -k * x - beta * x * x * x
            a -= c * v + q * v * abs(v)
            if mu:
                a -= mu * tanh(v / eps)
            if forced:
                a += F * cos(wf * tt + ph)
            return (v, a)

        return free if drive is None else driven

    def _stiffness(self, p):
        return p["k"] / p.get("m", 1.0)

    def _amplitude(self, p):
        return p["x0"]

    def initial_guess(self, t, y, p):
        if self.inputs:
            return self._driven_guess(t, y, p, "k", "x0", "v0")
        omega = dominant_omega(t, y)
        x0, v0 = sinusoid_start(t, y, omega)
        return {"k": p.get("m", 1.0) * omega ** 2, "c": 0.0, "x0": x0, "v0": v0}

    def _driven_guess(self, t, y, p, kname, xname, vname):
        """Driven: the dominant frequency is the drive's, not the system's; regress y'' on y, y', u."""
        m = p.get("m", 1.0)
        coef = regression_start(t, y, self.inputs, order=2)
        out = {kname: float(max(coef[0], 1e-9)) * m, "c": float(coef[1]) * m, xname: float(y[0]),
               vname: float((y[1] - y[0]) / (t[1] - t[0]))}
        out.update({g: float(c) * m for g, c in zip(gain_names(self.inputs), coef[2:], strict=True)})
        return out


class Pendulum(Oscillator):
    """Linear small-angle pendulum ``theta'' + c theta' + w2 theta = 0`` (``w2 = g / L``).

    Observed as the angle, or as the tangential acceleration ``L theta''`` when ``L > 0``.

    Examples
    --------
    >>> import numpy as np
    >>> pre = Pendulum()
    >>> p = dict(pre.params, w2=4.0, theta0=0.1)
    >>> np.round(pre.build(())(np.array([0.0, np.pi / 2]), p), 6).tolist()
    [0.1, -0.1]
    >>> np.round(pre.build(())(np.array([0.0]), dict(p, L=2.0)), 6).tolist()   # L theta''
    [-0.8]
    """

    name = "pendulum"
    family = "pendulum"
    description = ("pendulum, linear small-angle model theta'' + c theta' + w2 theta = 0 (w2 = g/L); "
                   "observed as the angle (rad), or as the tangential acceleration L theta'' when L > 0")
    params = {"w2": 1.0, "c": 0.0, "theta0": 0.1, "omega0": 0.0, "L": 0.0}
    bounds = {"w2": (0.0, INF), "c": (-INF, INF)}
    fixed = frozenset({"L"})
    native = frozenset({"quadratic_drag", "coulomb_friction", "large_angle", "periodic_forcing"})

    def _restoring(self, x, p, effects):
        if "large_angle" in effects:
            s = p["s_angle"]
            return p["w2"] * ((1.0 - s) * x + s * np.sin(x))
        return p["w2"] * x

    def _initial_state(self, p):
        return [p["theta0"], p["omega0"]]

    def _closed_form(self, tau, p):
        return linear_oscillator(tau, p["w2"], p["c"], 1.0, p["theta0"], p["omega0"], with_velocity=True)

    def _observe(self, t, x, v, p, effects, eps):
        L = float(p.get("L", 0.0))
        if L <= 0:
            return x
        # a phone or accelerometer on the bob measures the tangential acceleration L theta''
        k = p["w2"]
        s_ang = p.get("s_angle", 0.0) if "large_angle" in effects else 0.0
        a = -k * ((1.0 - s_ang) * x + s_ang * np.sin(x)) - p["c"] * v
        if "quadratic_drag" in effects:
            a = a - p["q_drag"] * v * np.abs(v)
        if "coulomb_friction" in effects:
            a = a - p["mu"] * np.tanh(v / eps)
        if "periodic_forcing" in effects:
            a = a + p["F"] * np.cos(p["omega_f"] * t + p["phase_f"])
        if self.inputs:
            a = a + drive_on_grid(self.inputs, p, t)
        return L * a

    def _stiffness(self, p):
        return p["w2"]

    def _amplitude(self, p):
        return p["theta0"]

    def _free_guess(self, t, y, p):
        omega = dominant_omega(t, y)
        x0, v0 = sinusoid_start(t, y, omega)
        L = float(p.get("L", 0.0))
        if L > 0:   # data are accelerations: -L w2 theta
            x0, v0 = -x0 / (L * omega ** 2), -v0 / (L * omega ** 2)
        return {"w2": omega ** 2, "c": 0.0, "theta0": x0, "omega0": v0}

    def initial_guess(self, t, y, p):
        if self.inputs and float(p.get("L", 0.0)) <= 0:
            return self._driven_guess(t, y, p, "w2", "theta0", "omega0")
        return self._free_guess(t, y, p)


class Freefall(Preset):
    """Free fall from rest at ``t = 0``: ``h(t) = h0 - g t^2 / 2`` (held at ``h0`` before).

    Linear damping or quadratic drag (one at a time) are solved in closed form.

    Examples
    --------
    >>> import numpy as np
    >>> pre = Freefall()
    >>> pre.build(())(np.array([-1.0, 0.0, 1.0]), {"g": 10.0, "h0": 5.0}).tolist()
    [5.0, 5.0, 0.0]
    >>> t = np.linspace(0, 1, 50)
    >>> {k: round(v, 6) for k, v in pre.initial_guess(t, 2.0 - 4.9 * t ** 2, {}).items()}
    {'h0': 2.0, 'g': 9.8}
    """

    name = "freefall"
    family = "freefall"
    description = "free fall from rest at t = 0: height h(t) = h0 - g t^2 / 2"
    params = {"g": 9.81, "h0": 1.0}
    bounds = {"g": (0.0, INF)}
    native = frozenset({"linear_damping", "quadratic_drag"})
    autonomous = False

    def build(self, effects):
        effects = frozenset(effects) & self.native

        def predict(t, p):
            tt = np.maximum(t, 0.0)   # held at h0 before the release
            g = p["g"]
            with np.errstate(all="ignore"):
                if "quadratic_drag" in effects and "linear_damping" in effects:
                    raise InputError("freefall supports one drag law at a time; "
                                     "use linear_damping or quadratic_drag, not both")
                if "quadratic_drag" in effects and p["q_drag"] > 1e-12:
                    a = np.sqrt(g * p["q_drag"])
                    x = a * tt
                    # log(cosh(x)) written to avoid overflow for large x
                    lc = x + np.log1p(np.exp(-2 * x)) - np.log(2.0)
                    return p["h0"] - lc / p["q_drag"]
                if "linear_damping" in effects and p["b_lin"] > 1e-12:
                    b = p["b_lin"]
                    return p["h0"] - g / b * tt + g / b ** 2 * (-np.expm1(-b * tt))
            return p["h0"] - 0.5 * g * tt ** 2

        return predict

    def initial_guess(self, t, y, p):
        F = np.column_stack([np.ones_like(t), -0.5 * np.maximum(t, 0) ** 2])
        h0, g = solve(F, y, method="lstsq")
        return {"h0": float(h0), "g": float(max(g, 1e-6))}
