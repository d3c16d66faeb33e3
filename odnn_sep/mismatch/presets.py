"""Simulation presets: named parameters, defaults, and the ODE or closed form of each system.

Every preset returns ``predict(t, p)`` for a tuple of effects, folding the family-specific effects
into its equations (a Duffing term in the oscillator's force, radiation in the cooling law) so
that the effect is a change of physics, not a patch on the output. ODEs are integrated with
``scipy.integrate.odeint`` (LSODA, compiled): it is about ten times faster than ``solve_ivp`` for
these small systems, which matters because calibration and cross-validation integrate each model
hundreds of times. Where a closed form exists (linear oscillator, Newton cooling, free fall with
linear or quadratic drag) it is used instead.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.integrate import odeint

from odnn_sep.errors import InputError

INF = np.inf


class ModelIntegrationError(InputError):
    """The model could not be evaluated (the ODE failed to integrate or gave non-finite values)."""


def _integrate(name, rhs, state0, t, p):
    with np.errstate(all="ignore"), warnings.catch_warnings():
        # a failure is reported below as one clear error, not as solver chatter
        warnings.simplefilter("ignore")
        sol, info = odeint(rhs, state0, t, full_output=True, mxstep=20000, rtol=1e-7, atol=1e-9,
                           tfirst=True)
    if info.get("message", "").lower().find("successful") < 0 or not np.all(np.isfinite(sol)):
        shown = {k: round(float(v), 6) for k, v in p.items()}
        raise ModelIntegrationError(
            f"model {name!r} failed to integrate with parameters {shown} "
            f"({info.get('message', 'non-finite values')}); check the starting values (--param)")
    return sol


def _friction_scale(v_scale):
    # tanh(v/eps) replaces sign(v): LSODA cannot step through a discontinuous force.
    return 3e-2 * max(float(v_scale), 1e-9)


class Preset:
    """Base class: ``params`` (name -> default), ``bounds``, ``fixed`` (structural, never refit)."""

    name = ""
    family = ""
    description = ""
    params: dict = {}
    bounds: dict = {}
    fixed: frozenset = frozenset()
    native: frozenset = frozenset()   # effects implemented inside the preset's equations
    autonomous = True
    ndim = 1

    def build(self, effects):
        raise NotImplementedError

    def initial_guess(self, t, y, p):
        """Data-driven starting values for parameters the user did not give (dict, may be partial)."""
        return {}


def _dominant_omega(t, y):
    """Angular frequency of the largest periodogram peak (zero-padded, mean removed)."""
    n = len(t)
    dt = float(np.median(np.diff(t)))
    nfft = int(2 ** np.ceil(np.log2(8 * n)))
    spec = np.abs(np.fft.rfft((y - y.mean()) * np.hanning(n), nfft))
    freqs = np.fft.rfftfreq(nfft, dt)
    spec[0] = 0
    return 2 * np.pi * freqs[int(np.argmax(spec))]


def _sinusoid_start(t, y, omega):
    """Amplitudes (x0, v0) of a pure oscillation at omega matched to the data by least squares."""
    tau = t - t[0]
    F = np.column_stack([np.cos(omega * tau), np.sin(omega * tau), np.ones_like(tau)])
    coef = np.linalg.lstsq(F, y, rcond=None)[0]
    return float(coef[0]), float(coef[1] * omega)


def _linear_oscillator(tau, k, c, m, x0, v0, *, with_velocity=False):
    """Closed-form solution of m x'' + c x' + k x = 0 (complex roots cover every damping regime)."""
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
        r = _linear_oscillator(tau, p["k"], p["c"], p["m"], p["x0"], p["v0"], with_velocity=True)
        return r

    def _observe(self, t, x, v, p, effects, eps):
        return x

    def build(self, effects):
        effects = frozenset(effects) & self.native
        name = self.name

        def predict(t, p):
            t0 = t[0]
            if not effects:
                out = self._closed_form(t - t0, p)
                if out is not None and all(np.all(np.isfinite(o)) for o in out):
                    return self._observe(t, out[0], out[1], p, effects, 0.0)
            m = p.get("m", 1.0)
            eps = _friction_scale(max(abs(p.get("v0", p.get("omega0", 0.0))),
                                      np.sqrt(abs(self._stiffness(p))) * abs(self._amplitude(p))))

            rhs = self._make_rhs(p, effects, m, eps)
            sol = _integrate(name, rhs, self._initial_state(p), t, p)
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

        def rhs(tt, st):
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

        return rhs

    def _stiffness(self, p):
        return p["k"] / p.get("m", 1.0)

    def _amplitude(self, p):
        return p["x0"]

    def initial_guess(self, t, y, p):
        omega = _dominant_omega(t, y)
        x0, v0 = _sinusoid_start(t, y, omega)
        return {"k": p.get("m", 1.0) * omega ** 2, "c": 0.0, "x0": x0, "v0": v0}


class Pendulum(Oscillator):
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
        return _linear_oscillator(tau, p["w2"], p["c"], 1.0, p["theta0"], p["omega0"], with_velocity=True)

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
        return L * a

    def _stiffness(self, p):
        return p["w2"]

    def _amplitude(self, p):
        return p["theta0"]

    def initial_guess(self, t, y, p):
        omega = _dominant_omega(t, y)
        x0, v0 = _sinusoid_start(t, y, omega)
        L = float(p.get("L", 0.0))
        if L > 0:   # data are accelerations: -L w2 theta
            x0, v0 = -x0 / (L * omega ** 2), -v0 / (L * omega ** 2)
        return {"w2": omega ** 2, "c": 0.0, "theta0": x0, "omega0": v0}


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
        coef, *_ = np.linalg.lstsq(F, y, rcond=None)
        rss = float(np.sum((F @ coef - y) ** 2))
        if best is None or rss < best[0]:
            best = (rss, h, coef)
    _, h, (ta, amp) = best
    return {"h": float(h), "T_ambient": float(ta), "T0": float(ta + amp)}


class Cooling(Preset):
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
            if not ode:
                out = ta + (p["T0"] - ta) * np.exp(-p["h"] * tau)
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
                    return [d]

                out = _integrate(self.name, rhs, [p["T0"]], t, p)[:, 0]
            if "two_body_heat" in effects:
                out = out + p["B_2"] * (np.exp(-p["lam_2"] * tau) - np.exp(-p["h"] * tau))
            return out

        return predict

    def initial_guess(self, t, y, p):
        return _newton_fit(t, y)


class Freefall(Preset):
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
        h0, g = np.linalg.lstsq(F, y, rcond=None)[0]
        return {"h0": float(h0), "g": float(max(g, 1e-6))}


class Hum(Preset):
    name = "hum"
    family = "hum"
    description = "mains hum: sum over harmonics h=1..H of a_h cos(2 pi h f0 t) + b_h sin(2 pi h f0 t)"
    params = {"f0": 50.0, "harmonics": 1}
    bounds = {"f0": (0.0, INF)}
    fixed = frozenset({"harmonics"})
    native = frozenset({"missing_harmonic", "frequency_drift"})

    def amplitude_names(self, harmonics):
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
        # refine f0 around the given value (the grid frequency is never exactly nominal)
        span = t[-1] - t[0]
        best = None
        for f in f0 + np.linspace(-0.5, 0.5, 201) / max(span, 1e-9) * 4:
            F = _hum_columns(t, f, H)
            coef, *_ = np.linalg.lstsq(F, y, rcond=None)
            rss = float(np.sum((F @ coef - y) ** 2))
            if best is None or rss < best[0]:
                best = (rss, f, coef)
        _, f, coef = best
        out = {"f0": float(f)}
        out.update({n: float(c) for n, c in zip(self.amplitude_names(H), coef, strict=True)})
        return out


def _hum_columns(t, f0, H):
    cols = []
    for h in range(1, H + 1):
        cols += [np.cos(2 * np.pi * h * f0 * t), np.sin(2 * np.pi * h * f0 * t)]
    return np.column_stack(cols)


class Heat2D(Preset):
    name = "heat2d"
    family = "heat2d"
    description = ("2D heat field at time t from point sources: "
                   "sum_i S_i exp(-r_i^2 / (4 alpha t)) / (4 pi alpha t)")
    params = {"alpha": 0.01, "t": 1.0, "sources": "0.5:0.5"}
    bounds = {"alpha": (1e-12, INF)}
    fixed = frozenset({"t", "sources"})
    native = frozenset({"extra_source", "offset"})
    ndim = 2

    def build(self, effects):
        effects = frozenset(effects) & self.native

        def predict(xy, p):
            srcs = parse_sources(p["sources"])
            s2 = 4.0 * p["alpha"] * p["t"]
            out = np.zeros(len(xy))
            terms = [(sx, sy, p[f"S{i + 1}"]) for i, (sx, sy) in enumerate(srcs)]
            if "extra_source" in effects:
                terms.append((p["xs"], p["ys"], p["S_extra"]))
            for sx, sy, S in terms:
                r2 = (xy[:, 0] - sx) ** 2 + (xy[:, 1] - sy) ** 2
                out += S * np.exp(-r2 / s2) / (np.pi * s2)
            if "offset" in effects:
                out += p["offset"]
            return out

        return predict

    def initial_guess(self, xy, z, p):
        srcs = parse_sources(p.get("sources", self.params["sources"]))
        tt = float(p.get("t", 1.0))
        ext = max(np.ptp(xy[:, 0]), np.ptp(xy[:, 1]))
        best = None
        for a in np.geomspace(1e-4, 1.0, 40) * ext ** 2 / tt:
            s2 = 4 * a * tt
            F = np.column_stack([np.exp(-((xy[:, 0] - sx) ** 2 + (xy[:, 1] - sy) ** 2) / s2) / (np.pi * s2)
                                 for sx, sy in srcs])
            coef, *_ = np.linalg.lstsq(F, z, rcond=None)
            rss = float(np.sum((F @ coef - z) ** 2))
            if best is None or rss < best[0]:
                best = (rss, a, coef)
        out = {"alpha": float(best[1])}
        out.update({f"S{i + 1}": float(c) for i, c in enumerate(best[2])})
        return out


def parse_sources(spec):
    """Parse ``"x:y;x:y"`` into a list of (x, y) floats."""
    if isinstance(spec, (list, tuple)):
        return [(float(a), float(b)) for a, b in spec]
    out = []
    for part in str(spec).split(";"):
        part = part.strip()
        if not part:
            continue
        try:
            a, b = part.split(":")
            out.append((float(a), float(b)))
        except ValueError:
            raise InputError(f"sources must be x:y pairs separated by ';' (e.g. 0.3:0.4;0.6:0.5); "
                             f"got {spec!r}") from None
    if not out:
        raise InputError(f"sources must name at least one x:y pair; got {spec!r}")
    return out


PRESETS: dict[str, Preset] = {p.name: p for p in (Oscillator(), Pendulum(), Cooling(), Hum(), Heat2D(),
                                                    Freefall())}
