"""Fits that reuse work give exactly what the full computation gives.

Two shortcuts of the finder's ODE fits: a prediction already made (the common start of every
cross-validation fold and its first Jacobian, the optimum as the last trial point) is served from a
memo instead of integrating the ODE again, and an effect refit from several starts computes the
spread and the identifiability profiles of the best start alone. Each is compared here, bit for bit,
with the path that does every integration and completes every start.
"""
import numpy as np
import pytest

import odnn_sep.mismatch.prediction_memo as prediction_memo
from odnn_sep.mismatch import make_model
from odnn_sep.mismatch.candidates import refit_robust
from odnn_sep.mismatch.fitting import PredictionMemo, cross_validate, cv_folds, fit
from odnn_sep.mismatch.starts import effect_starts


def _duffing_record(n=240, seed=3):
    t = np.linspace(0, 12, n)
    truth = make_model("oscillator", {"k": 4.0, "c": 0.05, "x0": 1.0, "v0": 0.0}).with_effect(
        "cubic_stiffness", {"beta": 0.3})
    return t, truth.predict(t) + 0.01 * np.random.default_rng(seed).normal(size=n)


def _same_fit(a, b):
    assert a.params == b.params
    assert a.stderr == b.stderr
    assert a.rss == b.rss and a.n_eff == b.n_eff and a.converged == b.converged
    assert np.array_equal(a.prediction, b.prediction) and np.array_equal(a.residual, b.residual)
    assert a.unidentified == b.unidentified


def _ode_fit_and_cv():
    t, y = _duffing_record()
    m = make_model("oscillator", {"k": 4.0, "c": 0.0, "x0": 1.0, "v0": 0.0}).with_effect("cubic_stiffness")
    f = fit(m, t, y, start={**m.start, "beta": 0.1}, max_nfev=60)
    blocks = cv_folds(len(t))
    mse = cross_validate(m, t, y, f.params, block_id=blocks, max_nfev=30)
    return f, mse


def test_memo_serves_repeated_predictions_bit_for_bit():
    t, _ = _duffing_record(80)
    m = make_model("oscillator").with_effect("cubic_stiffness")
    memo = PredictionMemo(m, t)
    p = {**m.start, "beta": 0.2}
    first = memo.predict(t, p)
    first[:] = 0.0                       # a caller changing its copy changes nothing kept
    again = memo.predict(t, dict(p))
    assert np.array_equal(again, m.predict(t, p)) and memo.hits == 1
    # an int and a float of the same value are different parameters to a model
    assert prediction_memo.exact_key({"a": 1}) != prediction_memo.exact_key({"a": 1.0})
    assert prediction_memo.exact_key({"a": np.array([1.0])}) is None
    # other times than the memo's: predicted, not served
    assert np.array_equal(memo.predict(t[:10], p), m.predict(t[:10], p)) and memo.hits == 1


def test_fit_and_cross_validation_equal_the_path_without_memo(monkeypatch):
    fast_fit, fast_mse = _ode_fit_and_cv()
    calls = []
    original = PredictionMemo.predict

    def counting(self, t, p):
        calls.append(1)
        return original(self, t, p)
    monkeypatch.setattr(PredictionMemo, "predict", counting)
    original_init = PredictionMemo.__init__
    monkeypatch.setattr(PredictionMemo, "__init__",
                        lambda self, model, t, max_bytes=0: original_init(self, model, t, max_bytes=0))
    ref_fit, ref_mse = _ode_fit_and_cv()
    assert calls, "the fits did not go through the memo"
    _same_fit(fast_fit, ref_fit)
    assert np.array_equal(fast_mse, ref_mse, equal_nan=True)


def test_cross_validation_shares_the_common_start():
    t, y = _duffing_record()
    m = make_model("oscillator", {"k": 4.0, "c": 0.05, "x0": 1.0, "v0": 0.0}).with_effect("cubic_stiffness")
    served = []
    original = PredictionMemo.predict

    def watch(self, tt, p):
        out = original(self, tt, p)
        served.append(self.hits)
        return out
    PredictionMemo.predict = watch
    try:
        cross_validate(m, t, y, {**m.start, "beta": 0.3}, block_id=cv_folds(len(t)), max_nfev=30)
    finally:
        PredictionMemo.predict = original
    # four folds from one start: at least the start and its first Jacobian (1 + 5 predictions) of
    # folds 2-4 are served, and each fold's first residual repeats its start's prediction
    assert max(served) >= 3 * 6


def _refit_every_start_in_full(model, starts, cur, t, y):
    """The reference: every start fitted in full (spread and identifiability), the best kept."""
    base_start = {**model.start, **{k: v for k, v in cur.params.items() if k in model.start}}
    best = None
    for s in list(starts) + [base_start]:
        f = fit(model, t, y, start={**model.start, **s}, max_nfev=150, warn=False)
        if best is None or f.rss < best.rss:
            best = f
    return best


@pytest.mark.parametrize("effect", ["periodic_forcing", "cubic_stiffness"])
def test_refit_over_starts_equals_fitting_every_start_in_full(effect, monkeypatch):
    t, y = _duffing_record()
    base = make_model("oscillator")
    cur = fit(base, t, y, start={**base.start, "k": 4.0, "c": 0.0, "x0": 1.0, "v0": 0.0})
    model = cur.model.with_effect(effect)
    starts = effect_starts(effect, cur, t, y, model)
    assert len(starts) >= 1
    got, why = refit_robust(effect, model, starts, cur, t, y, None)
    assert why is None
    original_init = PredictionMemo.__init__
    monkeypatch.setattr(PredictionMemo, "__init__",      # the reference integrates every prediction
                        lambda self, model, t, max_bytes=0: original_init(self, model, t, max_bytes=0))
    _same_fit(got, _refit_every_start_in_full(model, starts, cur, t, y))


def test_generic_effect_on_an_integrated_model_reuses_the_integration(monkeypatch):
    """A pickup on top of a Duffing oscillator: changing only the pickup reuses the integration,
    and the fit is the one that integrates every prediction."""
    t, y = _duffing_record()
    y = y + 0.05 * np.cos(7.0 * t)
    m = make_model("oscillator", {"k": 4.0, "c": 0.05, "x0": 1.0, "v0": 0.0}).with_effect(
        "cubic_stiffness", {"beta": 0.3}).with_effect("periodic_pickup", {"omega_pk": 7.01, "a_pk": 0.04})
    assert prediction_memo.generic_only_names(m) == {"a_pk", "b_pk", "omega_pk"}
    memo = PredictionMemo(m, t)
    p = dict(m.start)
    memo.predict(t, p)
    moved = memo.predict(t, {**p, "a_pk": 0.07})
    assert memo.inner_hits == 1
    assert np.array_equal(moved, m.predict(t, {**p, "a_pk": 0.07}))
    fast = fit(m, t, y, max_nfev=40)
    original_init = PredictionMemo.__init__
    monkeypatch.setattr(PredictionMemo, "__init__",
                        lambda self, model, t, max_bytes=0: original_init(self, model, t, max_bytes=0))
    _same_fit(fast, fit(m, t, y, max_nfev=40))


def test_no_reuse_where_the_model_may_read_every_parameter():
    from odnn_sep.mismatch import custom_model
    user = custom_model(lambda t, a: a * t, {"a": 1.0}).with_effect("periodic_pickup")
    assert prediction_memo.generic_only_names(user) is None
    delayed = make_model("freefall").with_effect("time_delay").with_effect("periodic_pickup")
    assert prediction_memo.generic_only_names(delayed) is None
    assert prediction_memo.generic_only_names(make_model("oscillator").with_effect("cubic_stiffness")) is None
