"""CSV files that start with a byte-order mark (a spreadsheet's "CSV UTF-8", pandas' ``encoding="utf-8-sig"``).

The mark stayed in the first header cell: pandas' unnamed index column was then not seen as a row
counter, so ``mismatch`` read the index as time and the time column as the temperatures (exit 0,
T_ambient 5e4), and ``separate`` named the coordinate 'x' instead of the header's 't'.
"""
import json

import numpy as np

from odnn_sep.cli import main


def _write(path, text):
    with open(path, "w", encoding="utf-8-sig", newline="") as fh:
        fh.write(text)


def _cooling_rows(index):
    t = np.arange(0, 300, 1.0)
    T = 20 + 60 * np.exp(-0.01 * t) + np.random.default_rng(0).normal(0, 0.05, t.size)
    head = ",t,T\n" if index else "t,T\n"
    return head + "".join((f"{k}," if index else "") + f"{a},{b}\n" for k, (a, b) in enumerate(zip(t, T, strict=True)))


def test_mismatch_pandas_index_behind_a_bom(tmp_path):
    data, report = tmp_path / "mug.csv", tmp_path / "r.json"
    _write(data, _cooling_rows(index=True))
    assert main(["mismatch", str(data), "--model", "cooling", "--effects", "radiation", "--quiet",
                 "--report", str(report)]) == 0
    rep = json.loads(report.read_text())
    assert rep["input"]["time"] == "t" and rep["input"]["column"] == "T"
    assert rep["input"]["row_index_column"] == ""
    params = {k: v["value"] if isinstance(v, dict) else v for k, v in rep["calibration"]["parameters"].items()}
    assert abs(params["h"] - 0.01) < 1e-3 and abs(params["T_ambient"] - 20) < 0.5


def test_separate_coordinate_named_behind_a_bom(tmp_path, capsys):
    data = tmp_path / "mug.csv"
    _write(data, _cooling_rows(index=False))
    assert main(["separate", str(data), "--basis", "exp(-0.01*t)", "--quiet"]) == 0
    assert capsys.readouterr().err == ""


def test_separate_pandas_index_behind_a_bom(tmp_path):
    data, report = tmp_path / "mug.csv", tmp_path / "r.json"
    _write(data, _cooling_rows(index=True))
    assert main(["separate", str(data), "--basis", "exp(-0.01*t)", "--basis", "1", "--quiet",
                 "--report", str(report)]) == 0
    theta = {k: v["value"] for k, v in json.loads(report.read_text())["parameters"].items()}
    assert abs(theta["exp(-0.01*t)"] - 60) < 1 and abs(theta["1"] - 20) < 1, theta
