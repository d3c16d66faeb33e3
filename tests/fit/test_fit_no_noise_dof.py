"""A fit that leaves no point to estimate the noise says so, instead of printing an interval of NaN."""
import json

import numpy as np

from odnn_sep.cli import main
from odnn_sep.core import Basis, Even, Separator


def _three_points(tmp_path):
    x = np.array([-1.0, 0.0, 1.0])
    f = tmp_path / "s.csv"
    np.savetxt(f, np.c_[x, 2 * np.sin(5 * x) + np.cos(2 * x) + [0.01, 0.0, -0.02]], delimiter=",",
               header="x,y", comments="")
    return f


def test_separate_warns_when_no_point_is_left_for_the_noise(tmp_path, capsys):
    report = tmp_path / "r.json"
    assert main(["separate", str(_three_points(tmp_path)), "--basis", "sin(5*x)", "--disturbance", "even",
                 "--report", str(report)]) == 0
    out, err = capsys.readouterr()
    assert "nan" not in out and "no interval" in out
    assert "no point is left to estimate the noise" in err
    assert any("no point is left" in w for w in json.loads(report.read_text())["warnings"])


def test_result_as_dict_is_strict_json_without_a_noise_estimate():
    x = np.array([-1.0, 0.0, 1.0])
    r = Separator(Basis([lambda x: x], names=["a"]), disturbance=Even()).fit(x, 2 * x + np.cos(x)).result_
    d = json.loads(json.dumps(r.as_dict(), allow_nan=False))
    assert d["parameters"]["a"]["stderr"] is None and d["parameters"]["a"]["interval"] == [None, None]
    assert "nan" not in r.summary()
