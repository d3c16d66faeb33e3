"""A step of the level sits inside the record, never at its neutral instant 0 before the first sample.

The step's instant is held during a fit; the model's own start put it at 0, where it covers every
sample: a constant offset. On a real cooling record (CoolingWater1) that offset shifted the
temperature scale under evaporation (T_ambient -2.7 degrees, T0 74 for a first reading of 98.3)
and was reported as "a step of 24.13 at t = 0".
"""
from pathlib import Path

import numpy as np
import pytest

from odnn_sep.mismatch import explain
from odnn_sep.mismatch.candidates import refit_robust
from odnn_sep.mismatch.fitting import fit
from odnn_sep.mismatch.io import load_data
from odnn_sep.mismatch.model import make_model

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"


def test_no_step_is_fitted_at_an_instant_that_covers_every_sample():
    t = np.linspace(0, 1, 60)
    y = 5.0 - 4.9 * t ** 2 + 0.3 + 0.001 * np.random.default_rng(0).normal(size=t.size)
    cur = fit(make_model("freefall"), t, y)
    f, why = refit_robust("step_offset", cur.model.with_effect("step_offset"), [], cur, t, y, None)
    assert f is None or 0 < np.count_nonzero(t >= f.params["t_step"]) < t.size, f.params
    assert why is not None and "inside the record" in why


def test_a_step_start_inside_the_record_is_kept():
    t = np.linspace(0, 1, 60)
    y = 5.0 - 4.9 * t ** 2 + 0.3 * (t >= 0.5)
    cur = fit(make_model("freefall"), t, y)
    starts = [{"t_step": 0.5, "h_step": 0.3}]
    f, why = refit_robust("step_offset", cur.model.with_effect("step_offset"), starts, cur, t, y, None)
    assert why is None and f.params["t_step"] == 0.5 and abs(f.params["h_step"] - 0.3) < 1e-3


def test_real_cooling_record_gets_no_step_at_its_start():
    p = DATA / "cooling_water_wagon" / "CoolingWater1_fastR2.csv"
    if not p.exists():
        pytest.skip("shared data cooling_water_wagon absent")
    t, y, _ = load_data(p)
    res = explain("cooling", t, y)
    steps = [d for d in res.disturbances if d["effect"] == "step_offset"]
    assert all(0 < np.count_nonzero(t >= d["parameters"]["t_step"]) < t.size for d in steps), steps
    assert 10 < res.final_fit.params["T_ambient"] < 35 and abs(res.final_fit.params["T0"] - y[0]) < 3
