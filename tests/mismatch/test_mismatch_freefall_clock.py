"""A free fall timed by a logger's clock or Unix time is analysed from its first sample."""
import json
import warnings

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.mismatch import explain, make_model


def _fall(drag):
    t = np.linspace(0, 0.6, 120)
    m = make_model("freefall", {"g": 9.81, "h0": 2.0})
    if drag:
        m = m.with_effect("quadratic_drag", {"q_drag": drag})
    return t, m.predict(t) + 0.001 * np.random.default_rng(4).normal(size=t.size)


@pytest.mark.parametrize("clock", [1000.0, 1.7e9])
def test_a_far_clock_gives_the_fall_of_the_record_from_zero(clock):
    t, y = _fall(0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain("freefall", t + clock, y)
    # it gave g = 9.807 beside h0 = 4.9e6 and a 'drift' of 9807 (clock 1000), or g = 0 (Unix time)
    lo, hi = res.final_fit.intervals()["g"]
    assert lo < 9.81 < hi and abs(res.final_fit.params["h0"] - 2.0) < 0.01
    assert res.effects == [] and res.disturbances == []
    assert res.t[0] == t[0] + clock and any("first sample" in n for n in res.notes)


def test_drag_is_named_through_the_cli_with_unix_time(tmp_path):
    t, y = _fall(0.05)
    f = tmp_path / "fall.csv"
    f.write_text("t,h\n" + "".join(f"{a + 1.7e9:.6f},{b!r}\n" for a, b in zip(t.tolist(), y.tolist())))
    report = tmp_path / "r.json"
    # it stopped with a traceback (ValueError: array must not contain infs or NaNs)
    assert main(["mismatch", str(f), "--model", "freefall", "--quiet", "--report", str(report)]) == 0
    v = json.loads(report.read_text())["verdict"]
    assert [e["effect"] for e in v["effects"]] == ["quadratic_drag"]
    lo, hi = v["effects"][0]["intervals"]["q_drag"]
    assert lo < 0.05 < hi


def test_a_record_starting_near_the_release_is_left_on_its_clock():
    t, y = _fall(0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain("freefall", t + 0.1, y)
    assert not any("first sample" in n for n in res.notes)
