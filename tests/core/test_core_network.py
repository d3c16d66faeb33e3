"""The network solver (the paper's constrained DNN) agrees with the exact solver."""
import warnings

import numpy as np
import pytest

from odnn_sep.core import Basis, Convex, Even, Orthogonal, Periodic, Separator
from odnn_sep.errors import IdentifiabilityWarning


@pytest.mark.parametrize("dist", [Orthogonal(), Even()])
def test_network_matches_exact_on_linear_explicit_cases(dist):
    x = np.linspace(-2, 2, 201)
    y = 0.5 * x ** 2 * np.sin(5 * x) + np.cos(x) + 0.01 * np.random.default_rng(0).normal(size=x.size)
    b = Basis([lambda x: x ** 2 * np.sin(5 * x), lambda x: np.sin(3 * x)], names=["a", "b"])
    ex = Separator(b, disturbance=dist).fit(x, y).result_
    nw = Separator(b, disturbance=dist, solver="network", random_state=0, epochs=500).fit(x, y).result_
    np.testing.assert_allclose(nw.theta, ex.theta, rtol=1e-3, atol=1e-3 * np.abs(ex.theta).max())


def test_network_periodic_and_determinism():
    t = np.arange(0, 20, 0.04)
    y = np.sin(5 * t) + 0.7 * t * np.sin(5 * t)
    b = Basis([lambda t: t * np.sin(5 * t)], names=["a"])
    r1 = Separator(b, disturbance=Periodic(2 * np.pi / 5), solver="network", random_state=3, epochs=600).fit(t, y)
    r2 = Separator(b, disturbance=Periodic(2 * np.pi / 5), solver="network", random_state=3, epochs=600).fit(t, y)
    assert r1.theta_[0] == pytest.approx(0.7, rel=1e-3)
    assert r1.theta_[0] == r2.theta_[0]


def test_network_convex_lands_inside_identified_set():
    x = np.linspace(-2, 2, 201)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdentifiabilityWarning)
        r = Separator(Basis([lambda x: np.sin(5 * x)], names=["a"]), disturbance=Convex(), solver="network",
                      random_state=0, epochs=800).fit(x, x ** 2 + np.sin(5 * x)).result_
    lo, hi = r.interval[0]
    assert lo - 0.01 <= r.theta[0] <= hi + 0.01
    # the ICNN output is convex by construction
    assert np.diff(r.disturbance, 2).min() > -1e-6


def test_network_weighted_orthogonal_matches_weighted_exact():
    x = np.linspace(0, 1, 200)
    rng = np.random.default_rng(0)
    y = 2 * x + 1 + np.sin(40 * x) + 0.1 * rng.normal(size=x.size)
    w = rng.uniform(0.2, 3, x.size)
    b = Basis([np.ones_like, lambda x: x], names=["c", "m"])
    ex = Separator(b).fit(x, y, weights=w).result_
    nw = Separator(b, solver="network", epochs=300, random_state=0).fit(x, y, weights=w).result_
    np.testing.assert_allclose(nw.theta, ex.theta, rtol=1e-6)
