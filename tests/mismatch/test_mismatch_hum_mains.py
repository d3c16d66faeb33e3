"""A 60 Hz hum record analysed without --param f0 (its start defaults to 50 Hz) is calibrated at 60 Hz."""
import json

import numpy as np

from odnn_sep.cli import main


def _hum(tmp_path, f0):
    t = np.arange(0, 1.0, 1 / 4000)
    y = 0.3 * np.sin(2 * np.pi * f0 * t) + 0.1 * np.sin(2 * np.pi * 3 * f0 * t + 0.3) \
        + 0.01 * np.random.default_rng(0).normal(size=t.size)
    f = tmp_path / f"hum{f0}.csv"
    f.write_text("t,v\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t.tolist(), y.tolist())))
    return f


def test_a_60_hz_record_is_calibrated_at_60_hz_and_its_third_harmonic_named(tmp_path):
    report = tmp_path / "r.json"
    assert main(["mismatch", str(_hum(tmp_path, 60.0)), "--model", "hum", "--quiet", "--report", str(report)]) == 0
    d = json.loads(report.read_text())
    # f0 was calibrated at 51.5 Hz, the 60 Hz line taken as a "pickup" disturbance and the verdict read
    # "the record does not show the model"
    assert abs(d["calibration"]["parameters"]["f0"]["value"] - 60.0) < 0.05
    v = d["verdict"]
    assert [e["effect"] for e in v["effects"]] == ["missing_harmonic"]
    assert v["effects"][0]["parameters"]["k_h"] == 3
    assert not any(x["effect"].startswith("periodic_pickup") for x in v["disturbances"])


def test_a_50_hz_record_stays_at_50_hz(tmp_path):
    report = tmp_path / "r.json"
    assert main(["mismatch", str(_hum(tmp_path, 50.0)), "--model", "hum", "--quiet", "--report", str(report)]) == 0
    d = json.loads(report.read_text())
    assert abs(d["calibration"]["parameters"]["f0"]["value"] - 50.0) < 0.05
