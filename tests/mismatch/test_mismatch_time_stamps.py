"""A time column of ISO 8601 date-times is read as seconds since its first row, by every mismatch reader."""
import datetime as dt
import json

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.errors import FormatError
from odnn_sep.io_read import time_values

T0 = dt.datetime(2026, 3, 1, 9, 30)


def _cooling(n=150, step=4.0, seed=0):
    t = np.arange(n) * step
    y = 20 + 60 * np.exp(-t / 250) + np.random.default_rng(seed).normal(0, 0.05, n)
    return t, y


def _write(path, stamps, y, header="time,T"):
    path.write_text(header + "\n" + "".join(f"{a},{float(b)!r}\n" for a, b in zip(stamps, y)))
    return path


def test_date_times_give_the_fit_of_seconds(tmp_path):
    t, y = _cooling()
    secs = _write(tmp_path / "secs.csv", [f"{v:g}" for v in t], y)
    stamps = _write(tmp_path / "stamps.csv", [(T0 + dt.timedelta(seconds=float(v))).isoformat(sep=" ") for v in t], y)
    reports = []
    for src in (secs, stamps):
        rep = tmp_path / (src.stem + ".json")
        assert main(["mismatch", str(src), "--model", "cooling", "--quiet", "--report", str(rep)]) == 0
        reports.append(json.loads(rep.read_text()))
    a, b = (r["calibration"]["parameters"] for r in reports)
    assert a.keys() == b.keys() and all(np.isclose(a[k]["value"], b[k]["value"], rtol=1e-9) for k in a)
    assert reports[1]["input"]["time_origin"] == "2026-03-01T09:30:00"
    assert "time_origin" not in reports[0]["input"]


def test_the_note_names_the_origin(tmp_path, capsys):
    t, y = _cooling()
    src = _write(tmp_path / "s.csv", [(T0 + dt.timedelta(seconds=float(v))).isoformat() for v in t], y)
    assert main(["mismatch", str(src), "--model", "cooling"]) == 0
    assert "time is in seconds since 2026-03-01T09:30:00" in capsys.readouterr().err


def test_series_csv_with_date_times_shares_one_origin(tmp_path):
    from odnn_sep.mismatch.series_io import read_series_csv

    p = tmp_path / "mugs.csv"
    p.write_text("t,mug,T\n2026-03-01T09:30:00,A,90\n2026-03-01T09:30:05,B,80\n2026-03-01T09:30:10,A,85\n")
    got = {k: t.tolist() for k, (t, _) in read_series_csv(p, "mug").items()}
    assert got == {"A": [0.0, 10.0], "B": [5.0]}


@pytest.mark.parametrize("cells, message", [
    (["2026-03-01T09:30:00", "soon"], r"line 3: the time column 't' holds 'soon', neither a number nor an ISO 8601"),
    (["0", "1", "later"], r"line 4: the time column 't' holds 'later', not a number"),
    (["2026-03-01T09:30:00", "2026-03-01T09:30:01+01:00"], r"mixes time stamps with and without a UTC offset"),
    (["0001-01-01T00:00:00", "2026-03-01T09:30:00"], r"span more than 200 years"),
])
def test_bad_time_cells_are_named(cells, message):
    with pytest.raises(FormatError, match=message):
        time_values(cells, path="rec.csv", name="t")


def test_bad_stamp_through_the_command_is_one_line(tmp_path, capsys):
    t, y = _cooling(40)
    stamps = [(T0 + dt.timedelta(seconds=float(v))).isoformat() for v in t]
    stamps[7] = "31/03/2026 09:30"
    src = _write(tmp_path / "bad.csv", stamps, y)
    assert main(["mismatch", str(src), "--model", "cooling", "--quiet"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "line 9" in err[0] and "ISO 8601" in err[0]
    assert not list(tmp_path.glob("*.json"))
