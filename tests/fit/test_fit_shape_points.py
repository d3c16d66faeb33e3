"""A convex or monotone class on more points than it can be fitted on in minutes is refused at once.

1,000,000 points with ``--disturbance convex`` ran past 5 minutes with 12.8 GB of memory and did not
stop on SIGTERM; 30,000 points ran past 250 s. Now the size is checked before the fit
(``ODNN_SEP_MAX_SHAPE_POINTS``, default 20,000).
"""
import time

import numpy as np
import pytest

from odnn_sep.cli import main


def _signal(path, n):
    x = np.linspace(0, 3, n)
    y = 2 * np.sin(5 * x) + 0.5 * x**2 + 0.05 * np.random.default_rng(0).normal(size=n)
    np.savetxt(path, np.c_[x, y], delimiter=",", header="x,y", comments="", fmt="%.10g")


@pytest.mark.parametrize("kind", ["convex", "monotone", "monotone:dec"])
def test_shape_class_over_the_bound_refused(tmp_path, monkeypatch, capsys, kind):
    monkeypatch.setenv("ODNN_SEP_MAX_SHAPE_POINTS", "100")
    data = tmp_path / "s.csv"
    _signal(data, 200)
    assert main(["separate", str(data), "--basis", "sin(5*x)", "--disturbance", kind, "--quiet",
                 "-o", str(tmp_path / "parts.csv")]) == 1
    err = capsys.readouterr().err
    assert f"--disturbance {kind} on 200 points" in err and "ODNN_SEP_MAX_SHAPE_POINTS" in err
    assert not (tmp_path / "parts.csv").exists()


def test_default_bound_refuses_a_long_record_at_once(tmp_path, monkeypatch, capsys):
    monkeypatch.delenv("ODNN_SEP_MAX_SHAPE_POINTS", raising=False)
    data = tmp_path / "s.csv"
    _signal(data, 20_001)
    t0 = time.perf_counter()
    assert main(["separate", str(data), "--basis", "sin(5*x)", "--disturbance", "convex", "--quiet"]) == 1
    assert time.perf_counter() - t0 < 30
    assert "at most 20,000 points" in capsys.readouterr().err


def test_other_classes_and_short_records_unchanged(tmp_path, monkeypatch):
    monkeypatch.setenv("ODNN_SEP_MAX_SHAPE_POINTS", "100")
    data = tmp_path / "s.csv"
    _signal(data, 200)
    assert main(["separate", str(data), "--basis", "sin(5*x)", "--disturbance", "even:1.5", "--quiet"]) == 0
    monkeypatch.setenv("ODNN_SEP_MAX_SHAPE_POINTS", "200")
    assert main(["separate", str(data), "--basis", "sin(5*x)", "--disturbance", "convex", "--quiet"]) == 0
