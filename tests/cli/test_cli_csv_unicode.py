"""CSV files in UTF-16 or UTF-32 behind a byte-order mark (Excel's "Unicode text" export: UTF-16, tabs).

Their NUL bytes (halves of characters) made ``mismatch`` and ``separate`` refuse them as "binary data".
"""
import json

import numpy as np
import pytest

from odnn_sep.cli import main


def _cooling_text(sep):
    t = np.arange(0, 300, 1.0)
    T = 20 + 60 * np.exp(-0.01 * t) + np.random.default_rng(0).normal(0, 0.05, t.size)
    return f"t{sep}T\r\n" + "".join(f"{a}{sep}{b:.4f}\r\n" for a, b in zip(t, T, strict=True))


ENCODINGS = [("utf-16", "\t"), ("utf-16", ","), ("utf-32", "\t")]


def _write(path, encoding, sep):
    path.write_bytes(_cooling_text(sep).encode(encoding))     # Python's utf-16/utf-32 write the mark


@pytest.mark.parametrize(("encoding", "sep"), ENCODINGS)
def test_mismatch_reads_unicode_text(tmp_path, encoding, sep):
    data, report = tmp_path / "mug.csv", tmp_path / "r.json"
    _write(data, encoding, sep)
    assert main(["mismatch", str(data), "--model", "cooling", "--effects", "radiation", "--quiet",
                 "--report", str(report)]) == 0
    rep = json.loads(report.read_text())
    assert rep["input"]["time"] == "t" and rep["input"]["column"] == "T"
    h = rep["calibration"]["parameters"]["h"]
    assert abs((h["value"] if isinstance(h, dict) else h) - 0.01) < 1e-3


@pytest.mark.parametrize(("encoding", "sep"), ENCODINGS + [("utf-16-be-marked", "\t")])
def test_separate_reads_unicode_text(tmp_path, encoding, sep):
    data, report = tmp_path / "mug.csv", tmp_path / "r.json"
    if encoding == "utf-16-be-marked":
        data.write_bytes(b"\xfe\xff" + _cooling_text(sep).encode("utf-16-be"))
    else:
        _write(data, encoding, sep)
    assert main(["separate", str(data), "--basis", "exp(-0.01*t)", "--basis", "1", "--quiet",
                 "--report", str(report)]) == 0
    theta = {k: v["value"] for k, v in json.loads(report.read_text())["parameters"].items()}
    assert abs(theta["exp(-0.01*t)"] - 60) < 1 and abs(theta["1"] - 20) < 1, theta


def test_binary_behind_a_utf16_mark_is_still_refused(tmp_path, capsys):
    data = tmp_path / "blob.csv"
    data.write_bytes(b"\xff\xfe" + bytes(64))
    assert main(["mismatch", str(data), "--model", "cooling"]) != 0
    assert "binary data" in capsys.readouterr().err
