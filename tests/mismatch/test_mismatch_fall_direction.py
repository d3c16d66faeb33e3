"""A free fall measured downwards (distance fallen) is noted, not left as a silent misfit.

Before, such a record read "the model does not fit" with g fitted at 2e-19 and a drift absorbed,
and nothing said that the axis points the other way.
"""
import numpy as np

from odnn_sep.mismatch import explain, make_model


def _fall(t):
    return make_model("freefall", {"g": 9.81, "h0": 2.0}).with_effect("quadratic_drag", {"q_drag": 0.05}).predict(t)


def test_distance_fallen_is_noted_and_height_is_not():
    t = np.linspace(0, 0.6, 120)
    noise = 0.001 * np.random.default_rng(0).normal(size=t.size)
    h = _fall(t) + noise
    down = explain("freefall", t, 2.0 - h)
    assert any("distance fallen" in n for n in down.notes)
    up = explain("freefall", t, h)
    assert not any("distance fallen" in n for n in up.notes)
    assert [c.effect for c in up.named] == ["quadratic_drag"]
