"""Prewhitened scores and the final check of a named effect against its rivals."""
import numpy as np

from odnn_sep.core.whitening import ar_fit, prewhiten
from odnn_sep.mismatch import explain, make_model
from odnn_sep.mismatch.fitting import fit
from odnn_sep.mismatch.rivals import noise_filter, outlier_mask, prewhitened_score, step_score


def _ar1(n, phi, seed):
    e = np.random.default_rng(seed).normal(size=n)
    x = np.zeros(n)
    for i in range(1, n):
        x[i] = phi * x[i - 1] + e[i]
    return x


def test_ar_fit_recovers_ar1_and_white_noise_gets_no_filter():
    a = ar_fit(_ar1(3000, 0.8, 0))
    assert len(a) >= 1 and abs(a[0] - 0.8) < 0.05
    assert len(noise_filter(np.random.default_rng(1).normal(size=400))) == 0
    e = prewhiten(_ar1(3000, 0.8, 0), a)
    assert abs(np.corrcoef(e[1:], e[:-1])[0, 1]) < 0.05


def test_step_score_is_the_bic_drop_on_white_noise_and_smaller_on_coloured_noise():
    t = np.linspace(0, 1, 300)
    clean = 5.0 - 4.9 * t ** 2
    white = clean + 0.01 * np.random.default_rng(2).normal(size=300)
    cur = fit(make_model("freefall"), t, white)
    f = fit(cur.model.with_effect("drift"), t, white)
    assert abs(step_score(cur, f.residual, f.n_params, t) - (cur.bic - f.bic)) < 1e-9
    # AR(1) noise: a drift follows its slow part; the prewhitened evidence is far smaller
    col = clean + 0.004 * _ar1(300, 0.9, 3)
    cur = fit(make_model("freefall"), t, col)
    f = fit(cur.model.with_effect("drift"), t, col)
    assert step_score(cur, f.residual, f.n_params, t) < 0.5 * (cur.bic - f.bic)


def test_outliers_keep_only_the_model_difference():
    r = 0.1 * np.random.default_rng(4).normal(size=200)
    r[[20, 120]] = 5.0
    mask = outlier_mask(r)
    assert np.flatnonzero(mask).tolist() == [20, 120]
    other = r + 0.01
    # the spike sits in both residuals: only the models' difference (0.01) counts there
    s0 = prewhitened_score(r, r, 2, [], mask)
    s1 = prewhitened_score(other, r, 2, [], mask)
    assert 0 < s1 - s0 < 5


def test_clear_drag_law_is_named_without_an_equivalence():
    t = np.linspace(0, 0.6, 120)
    truth = make_model("freefall", {"g": 9.81, "h0": 2.0}).with_effect("quadratic_drag", {"q_drag": 0.1})
    y = truth.predict(t) + 0.001 * np.random.default_rng(0).normal(size=120)
    res = explain("freefall", t, y)
    assert res.effects == ["quadratic_drag"]
    named = res.named[0]
    assert named.equivalent == []
    # the rival's gap: on the final model, or at its step when it was too far behind to be refitted
    gaps = {r["effect"]: r.get("prewhitened_gap", r.get("bic_gap")) for r in named.rivals}
    assert gaps.get("linear_damping", np.inf) > 6
