"""Simulation presets: named parameters, defaults, and the ODE or closed form of each system.

Every preset returns ``predict(t, p)`` for a tuple of effects, folding the family-specific effects
into its equations (a Duffing term in the oscillator's force, radiation in the cooling law) so
that the effect is a change of physics, not a patch on the output. ODEs are integrated with
``scipy.integrate.odeint`` (LSODA, compiled): it is about ten times faster than ``solve_ivp`` for
these small systems, which matters because calibration and cross-validation integrate each model
hundreds of times. Where a closed form exists (linear oscillator, Newton cooling, free fall with
linear or quadratic drag) it is used instead.
"""
from odnn_sep.mismatch.presets_base import (  # noqa: F401  (re-exported)
    INF,
    ModelIntegrationError,
    Preset,
    dominant_omega,
    integrate_ode,
    sinusoid_start,
)
from odnn_sep.mismatch.presets_fields import Cooling, Heat2D, Hum, parse_sources  # noqa: F401
from odnn_sep.mismatch.presets_mech import Freefall, Oscillator, Pendulum, linear_oscillator  # noqa: F401

PRESETS: dict[str, Preset] = {p.name: p for p in (Oscillator(), Pendulum(), Cooling(), Hum(), Heat2D(),
                                                    Freefall())}
