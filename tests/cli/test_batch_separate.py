"""``odnn-sep batch separate``: one JSON report per series, parts CSVs and figures beside it.

A folder of measurements fitted with the same basis is the common case of ``separate`` (one series
per sensor, per run); batch had no ``separate`` target, so users looped in the shell and lost the
summary, the per-file failure list and the input-safety checks.
"""
import hashlib
import json

import numpy as np
import pytest

from odnn_sep.cli import main


def _series(folder, amplitudes):
    folder.mkdir()
    x = np.linspace(-1, 1, 101)
    for k, a in enumerate(amplitudes):
        noise = 0.01 * np.random.default_rng(k).normal(size=x.size)
        np.savetxt(folder / f"s{k}.csv", np.c_[x, a * np.sin(5 * x) + x**2 + noise], delimiter=",",
                   header="x,y", comments="")


def _digest(folder):
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir())}


def test_each_series_gets_its_report_parts_and_figure(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _series(tmp_path / "in", [1.0, 2.0, 3.0])
    before = _digest(tmp_path / "in")
    assert main(["batch", "separate", "in", "-o", "out", "--jobs", "1", "--quiet", "--",
                 "--basis", "sin(5*x)", "--disturbance", "even", "-o", "parts.csv", "--plot", "fig.png"]) == 0
    assert _digest(tmp_path / "in") == before
    assert not (tmp_path / "parts.csv").exists() and not (tmp_path / "fig.png").exists()
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert names == ["batch_summary.json"] + [f"s{k}.{e}" for k in range(3) for e in ("json", "parts.csv", "plot.png")]
    for k, a in enumerate([1.0, 2.0, 3.0]):
        rep = json.loads((tmp_path / "out" / f"s{k}.json").read_text())
        lo, hi = rep["parameters"]["sin(5*x)"]["interval"]
        assert lo < a < hi and hi - lo < 0.02
        parts = np.genfromtxt(tmp_path / "out" / f"s{k}.parts.csv", delimiter=",", names=True)
        assert len(parts) == 101 and "physics" in parts.dtype.names
    summary = json.loads((tmp_path / "out" / "batch_summary.json").read_text())
    assert summary["command"] == "separate" and summary["failed"] == 0
    assert summary["results"][1]["outcome"].startswith("fitted: sin(5*x) = 2")


def test_a_series_that_cannot_be_fitted_is_listed_and_the_rest_go_on(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    _series(tmp_path / "in", [1.0, 2.0])
    (tmp_path / "in" / "s9.csv").write_text("x,y\n0,1\n")     # one point: nothing to fit
    assert main(["batch", "separate", "in", "-o", "out", "--jobs", "1", "--quiet", "--",
                 "--basis", "sin(5*x)", "--disturbance", "even"]) == 1
    summary = json.loads((tmp_path / "out" / "batch_summary.json").read_text())
    codes = {r["input"]: r["exit_code"] for r in summary["results"]}
    assert codes == {"in/s0.csv": 0, "in/s1.csv": 0, "in/s9.csv": codes["in/s9.csv"]} and codes["in/s9.csv"] != 0
    assert not (tmp_path / "out" / "s9.json").exists()
    assert "failed: in/s9.csv" in capsys.readouterr().err


def test_the_report_named_after_dashes_is_refused(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    _series(tmp_path / "in", [1.0])
    assert main(["batch", "separate", "in", "-o", "out", "--", "--basis", "x", "--report", "r.json"]) == 1
    assert "would send every file's output to one path" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("target", ["denoise", "unwatermark"])
def test_dash_o_still_refused_where_it_is_the_batch_output(tmp_path, monkeypatch, capsys, target):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "in").mkdir()
    (tmp_path / "in" / ("a.wav" if target == "denoise" else "a.png")).write_bytes(b"x")
    assert main(["batch", target, "in", "-o", "out", "--", "-o", "x.out"]) == 1
    assert "would send every file's output to one path" in capsys.readouterr().err
