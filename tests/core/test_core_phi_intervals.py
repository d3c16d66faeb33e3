"""Theta's intervals include the uncertainty of the fitted nonlinear parameters phi."""
import warnings

import numpy as np

from odnn_sep.core import Orthogonal, ParametricBasis, Separator
from odnn_sep.signals import make_dataset


def test_growth_amplitude_intervals_cover_at_the_nominal_rate():
    # N0 exp(mu t): N0 and mu are strongly correlated; with mu held at its estimate the N0 interval
    # held the truth in about 20 % of draws
    hits = []
    for seed in range(500, 520):
        ds = make_dataset("biology", random_state=seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y).result_
        lo, hi = r.interval[0]
        hits.append(lo <= ds.theta_true["N0"] <= hi)
    assert sum(hits) >= 16          # 95 % nominal: 17 or more of 20 expected, 12 % chance of 16 or fewer


def test_theta_error_matches_the_spread_over_noise_draws():
    t = np.linspace(0, 3, 200)
    basis = ParametricBasis(lambda t, xp=np, k=1.0: xp.exp(-k * t), {"k": 1.0}, names=["a"], bounds={"k": (0.1, 5)})
    rng = np.random.default_rng(0)
    est, err = [], []
    for _ in range(150):
        y = 2 * np.exp(-1.3 * t) + 0.05 * rng.standard_normal(t.size)
        r = Separator(basis, disturbance=Orthogonal()).fit(t, y).result_
        est.append(r.theta[0])
        err.append(r.stderr[0])
    # the reported error is the spread of the estimate (about 0.7 of it with k held fixed)
    assert 0.85 < np.median(err) / np.std(est) < 1.2
