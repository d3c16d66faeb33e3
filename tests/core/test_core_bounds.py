"""The Cramér–Rao bound matches the exact solver's Monte-Carlo spread and refuses cone classes."""
import numpy as np
import pytest

from odnn_sep.core import Basis, Convex, Even, Periodic, Separator
from odnn_sep.core.bounds import efficiency_bound, expected_mape
from odnn_sep.errors import InputError


def _spread(basis, disturbance, x, theta, g, sigma, draws=300):
    rng = np.random.default_rng(0)
    clean = basis.evaluate(x) @ theta + g
    est = [Separator(basis, disturbance=disturbance).fit(x, clean + sigma * rng.standard_normal(x.size)).result_.theta
           for _ in range(draws)]
    return np.std(est, axis=0)


@pytest.mark.parametrize("case", ["periodic", "even"])
def test_bound_matches_monte_carlo_spread(case):
    x = np.arange(240.0) if case == "periodic" else np.linspace(-1, 1, 201)
    if case == "periodic":
        basis = Basis([lambda t: t / 240, lambda t: np.exp(-t / 60)], names=["ramp", "decay"])
        disturbance, g = Periodic(24), np.sin(2 * np.pi * x / 24) + 0.3 * np.cos(6 * np.pi * x / 24)
    else:
        basis = Basis([lambda t: t ** 3, lambda t: np.sin(3 * t)], names=["cubic", "sine"])
        disturbance, g = Even(), np.cos(4 * x) + x ** 2
    theta, sigma = np.array([1.5, -0.7]), 0.05
    cov = efficiency_bound(basis, disturbance, x, theta, sigma=sigma)
    sd_bound = np.sqrt(np.diag(cov))
    sd_mc = _spread(basis, disturbance, x, theta, g, sigma)
    # 300 draws: the sample sd is within about 4 % of the truth (1 sigma); allow 15 %
    np.testing.assert_allclose(sd_mc, sd_bound, rtol=0.15)
    F = basis.evaluate(x)
    no_disturbance = np.sqrt(np.diag(sigma ** 2 * np.linalg.inv(F.T @ F)))
    if case == "periodic":  # the ramp and decay overlap the periodic class: that costs information
        assert np.all(sd_bound > no_disturbance * 1.01)
    else:  # odd columns on a symmetric grid are orthogonal to every even function: nothing is lost
        np.testing.assert_allclose(sd_bound, no_disturbance, rtol=1e-9)


def test_expected_mape_of_a_gaussian():
    assert expected_mape(np.diag([0.01, 0.04]), [1.0, 2.0]) == pytest.approx(100 * np.sqrt(2 / np.pi) * 0.1)


def test_bound_refuses_cone_classes_and_bad_sigma():
    b = Basis([np.sin], names=["s"])
    x = np.linspace(0, 1, 50)
    with pytest.raises(InputError, match="Convex only set-identifies theta"):
        efficiency_bound(b, Convex(), x, [1.0], sigma=0.1)
    with pytest.raises(InputError, match="sigma must be a positive finite noise standard deviation; got 0"):
        efficiency_bound(b, Periodic(0.5), x, [1.0], sigma=0)
