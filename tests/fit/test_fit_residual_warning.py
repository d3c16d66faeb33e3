"""``separate`` says when the residual is not like noise: the class cannot hold the disturbance, or the
noise is correlated, and the intervals are then too narrow.

With ``y = 2 sin 5x + x**2`` and ``--disturbance monotone`` (x**2 is not monotone on [-1, 1]) it
printed ``identified set [2.10, 2.20]`` and no warning; the truth 2 lies outside.
"""
import json

import numpy as np
import pytest

from odnn_sep.cli import main

X = np.linspace(-1, 1, 400)
NOISE = 0.02 * np.random.default_rng(5).normal(size=X.size)


def _run(tmp_path, y, spec, capsys):
    data, report = tmp_path / "s.csv", tmp_path / "r.json"
    np.savetxt(data, np.c_[X, y], delimiter=",", header="x,y", comments="")
    assert main(["separate", str(data), "--basis", "sin(5*x)", "--disturbance", spec, "--quiet",
                 "--report", str(report)]) == 0
    return capsys.readouterr().err, json.loads(report.read_text())


@pytest.mark.parametrize("g, spec", [(X**2, "monotone"), (np.exp(X), "even"), (0.3 * np.sin(3 * X), "convex"),
                                     (X**2, "periodic:0.5")])
def test_wrong_class_is_named(tmp_path, capsys, g, spec):
    err, rep = _run(tmp_path, 2 * np.sin(5 * X) + g + NOISE, spec, capsys)
    assert "Warning: the residual is not like noise (lag-1 correlation 0." in err
    assert any(w.startswith("the residual is not like noise") for w in rep["warnings"])


@pytest.mark.parametrize("g, spec", [(np.exp(X), "monotone"), (np.cos(2 * X), "even"), (np.exp(X), "convex"),
                                     (np.cos(4 * np.pi * X), "periodic:0.5"), (X, "orthogonal")])
def test_right_class_is_quiet(tmp_path, capsys, g, spec):
    err, rep = _run(tmp_path, 2 * np.sin(5 * X) + g + NOISE, spec, capsys)
    assert "not like noise" not in err
    assert not any("not like noise" in w for w in rep["warnings"])


def test_noise_free_data_is_quiet(tmp_path, capsys):
    err, _ = _run(tmp_path, 2 * np.sin(5 * X) + np.cos(2 * X), "even", capsys)
    assert "not like noise" not in err


def test_field(tmp_path, capsys):
    xa, ya = np.linspace(-1, 1, 30), np.linspace(-1, 1, 20)
    Xg, Yg = np.meshgrid(xa, ya)
    z = 2 * np.sin(3 * Xg) * np.cos(Yg) + np.exp(Xg + Yg) + 0.01 * np.random.default_rng(1).normal(size=Xg.shape)
    np.savez(tmp_path / "f.npz", x=xa, y=ya, z=z)
    assert main(["separate", str(tmp_path / "f.npz"), "--basis", "sin(3*x)*cos(y)", "--disturbance", "even",
                 "--quiet"]) == 0
    assert "not like noise" in capsys.readouterr().err
