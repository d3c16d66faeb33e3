"""Rules found with recipes/bench_mismatch_probe.py: disturbances first when tied, loss terms never gains."""
import numpy as np

from odnn_sep.mismatch import explain
from odnn_sep.mismatch.report import summary_text

T = np.linspace(0, 900, 76)


def _slow_pickup_null(seed):
    """A cooling curve with a pickup slower than the record (0.8 cycles): no effect in it."""
    rng = np.random.default_rng(seed)
    return 35 + 73 * np.exp(-0.0039 * T) + 0.15 * rng.normal(size=T.size) + 0.5 * np.cos(2 * np.pi * 0.00087 * T + 1.0)


def test_slow_pickup_on_a_cooling_null_is_not_named_as_physics():
    # before: radiation fitted as a heat gain (seed 2) and a second body (seed 4) were named
    for seed in (2, 4):
        res = explain("cooling", T, _slow_pickup_null(seed))
        assert res.effects == [], (seed, res.effects)
        assert res.disturbances, seed


def test_loss_term_fitted_as_a_gain_is_set_aside_with_its_reason():
    res = explain("cooling", T, _slow_pickup_null(2))
    notes = {c.effect: c.note for c in res.candidates}
    assert "heat gain" in (notes["radiation"] or "") or "absorbed first" in (notes["radiation"] or "")
    assert "radiation" not in res.effects
    assert "nothing missing" in summary_text(res)
