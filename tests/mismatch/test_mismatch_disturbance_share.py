"""A record the disturbances hold is not "nothing missing" (odnn_sep.mismatch.shares).

A 50 Hz hum analysed with the cooling preset: the periodic pickup took the whole signal, the
cooling curve stayed flat (h = 180 +- 530, not identified) and the verdict read "nothing missing".
"""
import json

import numpy as np

from odnn_sep.cli import main
from odnn_sep.mismatch import explain


def _hum_csv(path):
    t = np.arange(1000) / 1000.0
    y = 0.3 * np.sin(2 * np.pi * 50 * t) + 0.01 * np.random.default_rng(0).normal(size=t.size)
    np.savetxt(path, np.c_[t, y], delimiter=",", header="t,y", comments="")


def test_hum_under_the_cooling_model_is_not_nothing_missing(tmp_path, capsys):
    data, report = tmp_path / "hum.csv", tmp_path / "r.json"
    _hum_csv(data)
    assert main(["mismatch", str(data), "--model", "cooling", "--report", str(report)]) == 0
    v = json.loads(report.read_text())["verdict"]
    assert v["status"] == "disturbance_dominates", v["status"]
    assert v["variance_shares"]["disturbances"] > 0.99 and v["variance_shares"]["physics"] < 0.01
    line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("Verdict:"))
    assert line.startswith("Verdict: the model does not fit: the disturbances hold"), line


def test_a_pickup_beside_the_cooling_curve_keeps_its_verdict():
    # a pickup well above the noise, but a small part of a record the physics explains
    t = np.linspace(0, 100, 300)
    y = (20 + 70 * np.exp(-0.03 * t) + 0.5 * np.sin(2 * np.pi * 0.37 * t)
         + 0.05 * np.random.default_rng(1).normal(size=t.size))
    v = explain("cooling", t, y).as_dict()["verdict"]
    assert [d["effect"] for d in v["disturbances"]] == ["periodic_pickup"]
    assert v["status"] == "nothing_missing" and v["variance_shares"]["physics"] > 0.99


def test_a_record_of_noise_alone_is_no_evidence_for_the_hum_model():
    # no hum at all: the hum's amplitude is not identified and "nothing missing" said nothing about the model
    t = np.arange(2000) / 2000.0
    y = 0.1 * np.random.default_rng(0).normal(size=t.size)
    v = explain("hum", t, y, params={"f0": 50.0}).as_dict()["verdict"]
    assert v["status"] == "nothing_missing" and v["variance_shares"]["physics_p_value"] > 0.05
    assert "the record does not show the model" in v["description"], v["description"]


def test_a_clear_cooling_curve_keeps_the_plain_sentence():
    t = np.linspace(0, 100, 300)
    y = 20 + 70 * np.exp(-0.03 * t) + 0.05 * np.random.default_rng(1).normal(size=300)
    v = explain("cooling", t, y).as_dict()["verdict"]
    assert v["description"].startswith("nothing missing that the data can show: no effect improved")
    assert v["variance_shares"]["physics_p_value"] < 1e-12
