"""Model-error-aware spread (block sandwich from the core) and equivalence reporting."""
import numpy as np

from odnn_sep.core.uncertainty import block_length, sandwich_standard_errors
from odnn_sep.mismatch.candidates import Candidate
from odnn_sep.mismatch.fitting import t_over_normal
from odnn_sep.mismatch.selection import EQUIVALENCE_GAP, attach_equivalents, variance_inflation


def _ar1(rng, n, phi):
    e = rng.normal(size=n) * np.sqrt(1 - phi ** 2)
    out = np.empty(n)
    out[0] = rng.normal()
    for i in range(1, n):
        out[i] = phi * out[i - 1] + e[i]
    return out


def test_sandwich_covers_under_ar1_noise_where_classical_does_not():
    rng = np.random.default_rng(0)
    n, phi, reps = 400, 0.7, 150
    t = np.linspace(0, 1, n)
    J = np.c_[np.ones(n), t]
    hit_s, hit_c = [], []
    for _ in range(reps):
        y = 1.0 + 2.0 * t + _ar1(rng, n, phi)
        coef, *_ = np.linalg.lstsq(J, y, rcond=None)
        out = sandwich_standard_errors(J, y - J @ coef, n - 2)
        widen = t_over_normal(out.n_blocks - 1)
        hit_s.append(abs(coef[1] - 2.0) <= 1.96 * widen * out.stderr[1])
        hit_c.append(abs(coef[1] - 2.0) <= 1.96 * out.classical[1])
    assert np.mean(hit_c) < 0.75          # white-noise errors are overconfident here
    assert np.mean(hit_s) >= 0.85         # the block sandwich is (nominal 0.95)


def test_block_length_grows_with_correlation():
    rng = np.random.default_rng(1)
    assert block_length(rng.normal(size=500)) == round(2 * 500 ** (1 / 3))
    assert block_length(_ar1(rng, 500, 0.9)) > 2 * block_length(rng.normal(size=500))


def test_variance_inflation_of_ar1():
    rng = np.random.default_rng(2)
    vif = variance_inflation(_ar1(rng, 5000, 0.6), np.arange(5000.0))
    assert abs(vif - 1.6 / 0.4) < 0.4
    assert variance_inflation(rng.normal(size=5000), np.arange(5000.0)) < 1.1
    assert variance_inflation(np.ones(10), np.ones((10, 2))) == 1.0   # 2D fields: no time order


class _F:
    def __init__(self, r):
        self.residual = r


def test_equivalence_only_within_the_margin():
    rng = np.random.default_rng(3)
    t = np.arange(300.0)
    white = _F(rng.normal(size=300))
    best = Candidate("radiation", 40.0, white)
    close = Candidate("evaporation", 40.0 - 0.5 * EQUIVALENCE_GAP, white)
    far = Candidate("two_body_heat", 40.0 - 3 * EQUIVALENCE_GAP, white)
    weak = Candidate("drift", 39.0, white)   # a disturbance is never an equivalent physics effect
    attach_equivalents(best, [best, close, far, weak], 10.0, t)
    assert best.equivalent == ["evaporation"]
    # the same gap under strongly correlated residuals is within the margin
    red = Candidate("radiation", 40.0, _F(_ar1(rng, 300, 0.8)))
    attach_equivalents(red, [red, far], 10.0, t)
    assert red.equivalent == ["two_body_heat"]


def test_two_exponential_cooling_is_reported_in_one_labelling():
    from odnn_sep.mismatch import make_model
    from odnn_sep.mismatch.fitting import fit
    t = np.linspace(0, 200, 200)
    truth = make_model("cooling", {"h": 0.02, "T_ambient": 22.0, "T0": 95.0}).with_effect(
        "two_body_heat", {"B_2": 2.0, "lam_2": 0.2})
    y = truth.predict(t) + 0.05 * np.random.default_rng(4).normal(size=200)
    # start in the swapped labelling (the fast exponential as "h"): the same curve, B_2 = T0 - Ta - 2
    swapped = {**truth.start, "h": 0.2, "lam_2": 0.02, "B_2": 71.0}
    f = fit(truth, t, y, start=swapped)
    assert f.params["lam_2"] > f.params["h"]
    assert abs(f.params["h"] - 0.02) < 0.002 and abs(f.params["B_2"] - 2.0) < 0.5
    lo, hi = f.intervals()["B_2"]
    assert lo < 2.0 < hi


def test_a_parameter_near_zero_of_an_integrated_model_gets_its_own_spread():
    # parameters near 0 (an initial velocity, a cubic term): a finite-difference step of 1e-5 of
    # the value (SciPy's rule for a given diff_step) fell under the integration error, and their
    # standard errors came out orders of magnitude too small (beta: 5e-10). The spread must match
    # the profile of the fit (chi2 up by about 1 at one standard error), and a free extra
    # parameter can only widen the spread of v0 over the closed-form linear model's.
    from dataclasses import replace

    from odnn_sep.mismatch.fitting import fit
    from odnn_sep.mismatch.model import make_model

    t = np.linspace(0, 10, 300)
    truth = make_model("oscillator", {"k": 4.0, "c": 0.1, "x0": 1.0, "v0": 1e-4})
    y = truth.predict(t) + 0.01 * np.random.default_rng(3).normal(size=300)
    closed = fit(truth, t, y, start=truth.start)
    m = truth.with_effect("cubic_stiffness")
    f = fit(m, t, y, start={**closed.params, "beta": 0.0})
    assert f.stderr["v0"] >= 0.9 * closed.stderr["v0"]
    se = f.stderr["beta"]
    sigma2 = f.rss / (len(t) - len(f.free))
    for b in (f.params["beta"] - se, f.params["beta"] + se):
        g = fit(replace(m, bounds={**m.bounds, "beta": (b, b + 1e-12)}), t, y, start={**f.params, "beta": b})
        assert 0.3 < (g.rss - f.rss) / sigma2 < 3.0
