"""``separate`` on a CSV whose first column holds date-times, as loggers write them.

``mismatch`` reads ISO 8601 time stamps as seconds since the first row; ``separate`` refused the same
file with "x (first column) has 400 missing or non-numeric value(s) ... fix or remove those rows".
"""
import json
from datetime import datetime, timedelta

import numpy as np

from odnn_sep.cli import main


def _logger_csv(path, bad_line=None, index=False):
    t0 = datetime(2026, 1, 31, 14, 0, 0)
    rng = np.random.default_rng(0)
    lines = [(",time,T" if index else "time,T")]
    for k in range(200):
        s = 5.0 * k
        stamp = (t0 + timedelta(seconds=s)).isoformat()
        lines.append((f"{k}," if index else "") + f"{stamp},{20 + 60 * np.exp(-0.002 * s) + rng.normal(0, 0.05)}")
    if bad_line is not None:
        lines[bad_line - 1] = ("0," if index else "") + "soon,50"
    path.write_text("\n".join(lines) + "\n")


def _theta(report):
    return {k: v["value"] for k, v in json.loads(report.read_text())["parameters"].items()}


def test_iso_time_stamps_read_as_seconds(tmp_path, capsys):
    data, report, parts = tmp_path / "log.csv", tmp_path / "r.json", tmp_path / "parts.csv"
    _logger_csv(data)
    assert main(["separate", str(data), "--basis", "exp(-0.002*time)", "--basis", "1",
                 "--report", str(report), "-o", str(parts)]) == 0
    theta = _theta(report)
    assert abs(theta["exp(-0.002*time)"] - 60) < 0.2 and abs(theta["1"] - 20) < 0.2
    assert np.loadtxt(parts, delimiter=",", skiprows=1)[:3, 0].tolist() == [0.0, 5.0, 10.0]
    assert "seconds since 2026-01-31T14:00:00" in capsys.readouterr().err


def test_iso_time_stamps_behind_a_row_counter(tmp_path):
    data, report = tmp_path / "log.csv", tmp_path / "r.json"
    _logger_csv(data, index=True)
    assert main(["separate", str(data), "--basis", "exp(-0.002*time)", "--basis", "1", "--quiet",
                 "--report", str(report)]) == 0
    assert abs(_theta(report)["exp(-0.002*time)"] - 60) < 0.2


def test_bad_time_stamp_named_by_its_line(tmp_path, capsys):
    data = tmp_path / "log.csv"
    _logger_csv(data, bad_line=7)
    assert main(["separate", str(data), "--basis", "exp(-0.002*time)", "--quiet"]) == 1
    err = capsys.readouterr().err.strip()
    assert "line 7" in err and "'soon'" in err, err
