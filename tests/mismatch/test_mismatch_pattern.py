"""A stripe across a 2D field is a disturbance (periodic_pattern), never an extra source."""
import numpy as np

from odnn_sep.mismatch import explain
from odnn_sep.mismatch.disturbances import describe
from odnn_sep.mismatch.model import make_model

SRC = "0.3:0.4;0.7:0.6"
BASE = {"alpha": 0.01, "t": 1.0, "sources": SRC, "S1": 1.0, "S2": 0.7}


def _grid(n=24):
    g = np.linspace(0, 1, n)
    X, Y = np.meshgrid(g, g)
    return np.column_stack([X.ravel(), Y.ravel()])


def _stripe(xy, amp=0.12, k=(2.0 * np.pi * 3.2, 2.0 * np.pi * 1.1), phase=0.7):
    return amp * np.cos(xy @ np.asarray(k) + phase)


def test_stripe_on_a_null_is_absorbed_and_described():
    xy = _grid()
    y = make_model("heat2d", BASE).predict(xy) + _stripe(xy) + 0.05 * np.random.default_rng(3).normal(size=len(xy))
    res = explain("heat2d", xy, y, params={"sources": SRC})
    assert res.effects == []
    assert [d["effect"] for d in res.disturbances] == ["periodic_pattern"]
    p = res.final_fit.params
    assert abs(np.hypot(p["a_pp"], p["b_pp"]) - 0.12) < 0.02
    assert abs(np.hypot(p["kx_pp"], p["ky_pp"]) - 2 * np.pi * np.hypot(3.2, 1.1)) < 0.5


def test_extra_source_is_still_named_beside_a_stripe():
    xy = _grid()
    truth = make_model("heat2d", BASE).with_effect("extra_source", {"xs": 0.5, "ys": 0.85, "S_extra": 0.4})
    y = truth.predict(xy) + _stripe(xy) + 0.05 * np.random.default_rng(4).normal(size=len(xy))
    res = explain("heat2d", xy, y, params={"sources": SRC})
    assert res.effects == ["extra_source"]
    assert "periodic_pattern" in [d["effect"] for d in res.disturbances]


def test_description_names_wavelength_and_direction():
    text = describe("periodic_pattern", {"a_pp": 0.3, "b_pp": 0.4, "kx_pp": 0.0, "ky_pp": 2 * np.pi / 0.25},
                    model_family="heat2d", linear=True)
    assert text.startswith("a periodic pattern (stripes) of wavelength 0.25, wave vector at 90 deg, 0.5")
