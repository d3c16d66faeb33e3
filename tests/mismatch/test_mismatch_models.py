import numpy as np
import pytest
from scipy.integrate import odeint

from odnn_sep.mismatch import EFFECTS, PRESETS, VOCABULARY, make_model
from odnn_sep.mismatch.effects import applicable


def test_vocabulary_is_the_documented_one():
    for name in ["linear_damping", "quadratic_drag", "coulomb_friction", "cubic_stiffness", "large_angle",
                 "periodic_forcing", "offset", "drift", "time_delay", "radiation", "evaporation",
                 "two_body_heat", "missing_harmonic", "frequency_drift", "amplitude_modulation",
                 "channel_coupling", "extra_source"]:
        assert name in VOCABULARY
    assert set(PRESETS) == {"oscillator", "pendulum", "cooling", "hum", "heat2d", "freefall"}
    # on a user model a periodic force is an additive sinusoid: offered as the periodic_pickup disturbance
    assert "periodic_pickup" in applicable("user") and "periodic_forcing" not in applicable("user")
    assert "cubic_stiffness" not in applicable("user")


def test_oscillator_closed_form_matches_ode():
    t = np.linspace(0, 10, 200)
    m = make_model("oscillator", {"k": 3.0, "c": 0.3, "x0": 0.5, "v0": 0.2})
    closed = m.predict(t)
    ode = m.with_effect("cubic_stiffness", {"beta": 0.0}).predict(t)   # same physics through LSODA
    assert np.max(np.abs(closed - ode)) < 1e-5
    # overdamped regime also uses the closed form
    over = make_model("oscillator", {"k": 1.0, "c": 5.0, "x0": 1.0, "v0": 0.0})
    ref = odeint(lambda s, tt: [s[1], -s[0] - 5.0 * s[1]], [1.0, 0.0], t)[:, 0]
    assert np.max(np.abs(over.predict(t) - ref)) < 1e-5


def test_freefall_drag_closed_forms_match_ode():
    t = np.linspace(0, 1.0, 50)
    for eff, key, force in [("quadratic_drag", "q_drag", lambda v, q: -q * v * abs(v)),
                            ("linear_damping", "b_lin", lambda v, q: -q * v)]:
        m = make_model("freefall", {"g": 9.81, "h0": 3.0}).with_effect(eff, {key: 0.3})
        ref = odeint(lambda s, tt, f=force: [s[1], -9.81 + f(s[1], 0.3)], [3.0, 0.0], t, rtol=1e-10)[:, 0]
        assert np.max(np.abs(m.predict(t) - ref)) < 1e-6


def test_cooling_effects_vanish_at_neutral_values_and_add_heat_loss():
    t = np.linspace(0, 100, 101)
    base = make_model("cooling", {"h": 0.03, "T_ambient": 20.0, "T0": 90.0})
    for e in ("radiation", "evaporation", "two_body_heat"):
        assert np.max(np.abs(base.with_effect(e).predict(t) - base.predict(t))) < 1e-4
    rad = base.with_effect("radiation", {"r_rad": 0.01}).predict(t)
    assert np.all(rad[1:] < base.predict(t)[1:])   # extra loss cools faster


def test_hum_and_heat2d_predict():
    t = np.arange(400) / 400.0
    m = make_model("hum", {"f0": 50.0, "harmonics": 2, "a1": 1.0, "b2": 0.5})
    y = m.predict(t)
    assert abs(np.sqrt(np.mean(y ** 2)) - np.sqrt(0.5 + 0.125)) < 1e-3
    g = np.linspace(0, 1, 10)
    X, Y = np.meshgrid(g, g)
    xy = np.column_stack([X.ravel(), Y.ravel()])
    h = make_model("heat2d", {"sources": "0.2:0.2;0.8:0.8", "S1": 1.0, "S2": 2.0, "alpha": 0.01})
    z = h.predict(xy)
    assert z.shape == (100,) and np.argmax(z) == 77   # nearest grid point to the stronger source (0.78, 0.78)


def test_predict_does_not_mutate_inputs():
    t = np.linspace(0, 5, 50)
    t0 = t.copy()
    p = dict(make_model("pendulum").start)
    p0 = dict(p)
    make_model("pendulum").with_effect("large_angle", {"s_angle": 1.0}).predict(t)
    assert np.array_equal(t, t0) and p == p0


def test_every_effect_has_consistent_bounds():
    for e in EFFECTS.values():
        assert set(e.bounds) <= set(e.params)


def test_an_integration_over_its_call_budget_is_a_clear_error(monkeypatch):
    # a stiff or slowly diverging trial point must fail fast (mxstep bounds one output interval
    # only: such a point of an optimiser ran for many minutes)
    import odnn_sep.mismatch.presets_base as pb
    from odnn_sep.mismatch.presets import ModelIntegrationError

    monkeypatch.setattr(pb, "ODE_CALL_BUDGET", 50)
    monkeypatch.setattr(pb, "ODE_CALLS_PER_SAMPLE", 0)
    with pytest.raises(ModelIntegrationError, match="more than 50 evaluations"):
        pb.integrate_ode("stiff", lambda t, s: [-1e4 * (s[0] - np.cos(t))], [0.0], np.linspace(0, 10, 20), {})
    monkeypatch.setattr(pb, "ODE_CALL_BUDGET", 100_000)
    assert pb.integrate_ode("decay", lambda t, s: [-s[0]], [1.0], np.linspace(0, 1, 20), {}).shape == (20, 1)
