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


def test_two_pickups_on_a_free_fall_null_are_both_absorbed():
    # before: one pickup was absorbed and the other (1.2 Hz, about one cycle in the record) named linear_damping
    t = np.linspace(0, 0.7, 400)
    y = (4.6 - 0.5 * 9.81 * t ** 2 + 0.015 * np.random.default_rng(0).normal(size=t.size)
         + 0.04 * np.cos(2 * np.pi * 1.2 * t + 0.3) + 0.03 * np.cos(2 * np.pi * 21.8 * t + 1.0))
    res = explain("freefall", t, y)
    assert res.effects == []
    found = sorted(d["effect"] for d in res.disturbances)
    assert found == ["periodic_pickup", "periodic_pickup_2"]
    hz = sorted(d["parameters"][k] / (2 * np.pi) for d in res.disturbances for k in d["parameters"]
                if k.startswith("omega_pk"))
    assert abs(hz[0] - 1.2) < 0.3 and abs(hz[1] - 21.8) < 0.2
    assert all("a periodic component at" in d["description"] for d in res.disturbances)


def test_samples_at_a_sensor_rail_are_left_out_not_named():
    # before: the flat start of a clipped cooling record was named two_body_heat (and radiation)
    t = np.linspace(0, 100, 48)
    clean = -8 + 30 * np.exp(-0.02 * t)
    y = np.minimum(clean + 0.2 * np.random.default_rng(0).normal(size=t.size), clean[4])
    res = explain("cooling", t, y, unit="degC")
    assert res.effects == []
    (d,) = [d for d in res.disturbances if d["effect"] == "clipping"]
    assert d["count"] >= 4 and abs(d["parameters"]["upper"] - clean[4]) < 1e-12
    assert "saturates" in d["description"] and "saturates" in summary_text(res)
    assert len(res.y) == t.size - d["count"]


def test_a_coarse_adc_without_clipping_keeps_every_sample():
    t = np.linspace(0, 100, 200)
    y = np.round(-8 + 30 * np.exp(-0.02 * t) + 0.05 * np.random.default_rng(1).normal(size=t.size), 1)
    res = explain("cooling", t, y)
    assert len(res.y) == t.size and not [d for d in res.disturbances if d["effect"] == "clipping"]


def test_the_lowest_level_of_a_coarse_adc_near_a_flat_tail_is_not_a_rail():
    # a level visited less often than the one next to it is the tail of the noise, not a pile-up
    from odnn_sep.mismatch.saturation import find_saturation
    for seed in range(5):
        tail = 1.2 + 0.5 * np.random.default_rng(seed).normal(size=100)
        assert find_saturation(np.round(np.r_[np.linspace(30.0, 1.5, 40), tail])) is None
    clipped = np.maximum(np.r_[np.linspace(30.0, 1.5, 40), tail], 2.0)
    assert find_saturation(clipped).rails[0][:2] == ("lower", 2.0)


def test_a_step_of_the_level_is_a_disturbance_with_its_instant():
    # before: no disturbance could take a step; slow pickups and a drift absorbed it in part, or
    # physics did (linear damping for a free fall's quadratic drag)
    t = np.linspace(0, 0.9, 300)
    y = 4.0 - 0.5 * 9.81 * t ** 2 + 0.01 * np.random.default_rng(3).normal(size=t.size) + 0.05 * (t >= 0.41)
    res = explain("freefall", t, y)
    assert res.effects == []
    (d,) = [d for d in res.disturbances if d["effect"] == "step_offset"]
    assert abs(d["parameters"]["t_step"] - 0.41) < 0.01 and abs(d["parameters"]["h_step"] - 0.05) < 0.01
    assert "a step of" in d["description"]


def test_a_loss_term_that_ends_as_a_heat_gain_in_the_final_model_is_dropped(monkeypatch):
    # radiation chosen with r > 0 can end at r < 0 once later disturbances are refitted on top of it
    # (a cooling null with two pickups ended at r = -0.19, named); the final model's sign is checked too
    from types import SimpleNamespace as NS

    import odnn_sep.mismatch.selection as S
    reduced = NS(params={"h": 0.04})
    check = NS(score=12.0, heldout_gain=30.0)
    monkeypatch.setattr(S, "_drop_check", lambda c, sel, base, setup: (check, reduced, np.ones(4)))
    rad, pk = NS(effect="radiation"), NS(effect="periodic_pickup")
    sel = NS(accepted=[rad, pk], fit=NS(params={"h": 0.04, "r_rad": -0.19}), dropped=[], heldout_rmse=None)
    S._drop_wrong_sign(sel, None, None)
    assert sel.accepted == [pk] and sel.fit is reduced and "heat gain" in sel.dropped[0]["reason"]
    sel = NS(accepted=[rad], fit=NS(params={"r_rad": 0.01}), dropped=[], heldout_rmse=None)
    S._drop_wrong_sign(sel, None, None)
    assert sel.accepted == [rad] and sel.dropped == []
