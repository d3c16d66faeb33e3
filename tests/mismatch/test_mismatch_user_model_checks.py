"""A user model's misspelt or impossible options are one clear InputError at construction, never
ignored (a parameter believed fixed that was refitted) and never a crash inside the fit."""
import numpy as np
import pytest

from odnn_sep.errors import InputError
from odnn_sep.mismatch import custom_model, explain, ode_model


def _rhs(t, s, k):
    return [-k * s[0]]


@pytest.mark.parametrize("make, words", [
    (lambda: ode_model(_rhs, {"kk": 1.0, "T0": 2.0}, ["T0"]), ["'kk'", "did you mean 'k'"]),
    (lambda: ode_model(lambda t, s, k, c: [-k * s[0] - c], {"k": 1.0, "T0": 2.0}, ["T0"]), ["needs 'c'"]),
    (lambda: ode_model(_rhs, {"k": 1.0, "T0": 2.0}, ["T0"], fixed=["T00"]), ["fixed names 'T00'"]),
    (lambda: ode_model(_rhs, {"k": 1.0, "T0": 2.0}, ["T0"], bounds={"kk": (0, 1)}), ["bounds names 'kk'"]),
    (lambda: ode_model(_rhs, {"k": 1.0, "T0": 2.0}, ["T0"], output=1), ["output=1"]),
    (lambda: custom_model(lambda t, a, k: a * np.exp(-k * t), {"a": 1.0, "k": 1.0}, fixed=["kk"]),
     ["fixed names 'kk'"]),
    (lambda: custom_model(lambda t, a, k: a * np.exp(-k * t), {"a": 1.0, "k": 1.0}, bounds={"k": (2, 1)}),
     ["bounds['k']", "lo < hi"]),
])
def test_bad_user_model_options_are_refused_at_construction(make, words):
    with pytest.raises(InputError) as info:
        make()
    msg = str(info.value)
    assert all(w in msg for w in words) and "\n" not in msg


def test_an_rhs_with_more_derivatives_than_states_is_an_input_error():
    t = np.linspace(0, 10, 100)
    y = 2 * np.exp(-0.5 * t) + 0.01 * np.random.default_rng(0).normal(size=t.size)
    m = ode_model(lambda t, s, k: [-k * s[0], s[0]], {"k": 1.0, "T0": 2.0}, ["T0"])
    # it was a RuntimeError from the integrator
    with pytest.raises(InputError, match="returned 2 derivative"):
        explain(m, t, y)


def test_a_well_formed_user_ode_still_fits():
    t = np.linspace(0, 10, 100)
    y = 2 * np.exp(-0.5 * t) + 0.01 * np.random.default_rng(0).normal(size=t.size)
    res = explain(ode_model(_rhs, {"k": 1.0, "T0": 2.0}, ["T0"], bounds={"k": (0, 5)}, fixed=[]), t, y)
    assert res.effects == [] and abs(res.final_fit.params["k"] - 0.5) < 0.01
