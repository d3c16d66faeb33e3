"""``separate --x-column``: the coordinate need not be a CSV's first column.

A lab table (time, mass, height, velocity, drag force) holds the coordinate of interest in its
fourth column; the only way was to rewrite the file.
"""
import json

import numpy as np
import pytest

from odnn_sep.cli import main


def _table(path):
    rng = np.random.default_rng(3)
    v = rng.uniform(0.4, 2.0, 40)
    force = 0.8 * v**2 + 0.01 * rng.normal(size=v.size)
    t = 1.0 / v
    np.savetxt(path, np.c_[t, np.full(v.size, 0.2), np.ones(v.size), v, force], delimiter=",",
               header="time,mass,height,velocity,force", comments="")


@pytest.mark.parametrize("given", [["--x-column", "velocity", "--column", "force"], ["--x-column", "3", "--column", "4"]])
def test_coordinate_from_another_column(tmp_path, given):
    f, rep = tmp_path / "drag.csv", tmp_path / "r.json"
    _table(f)
    assert main(["separate", str(f), *given, "--basis", "velocity**2", "--name", "c", "--quiet",
                 "--report", str(rep)]) == 0
    lo, hi = json.loads(rep.read_text())["parameters"]["c"]["interval"]
    assert lo < 0.8 < hi and hi - lo < 0.02


def test_value_column_defaults_to_the_first_other_column(tmp_path):
    f = tmp_path / "two.csv"
    x = np.linspace(-1, 1, 51)
    np.savetxt(f, np.c_[2 * np.sin(5 * x) + x**2, x], delimiter=",", header="y,x", comments="")
    rep = tmp_path / "r.json"
    assert main(["separate", str(f), "--x-column", "x", "--basis", "sin(5*x)", "--disturbance", "even",
                 "--quiet", "--report", str(rep)]) == 0
    assert abs(json.loads(rep.read_text())["parameters"]["sin(5*x)"]["value"] - 2) < 1e-8


@pytest.mark.parametrize("given, words", [
    (["--x-column", "veloc"], "did you mean 'velocity'"),
    (["--x-column", "9"], "out of range"),
    (["--x-column", "velocity", "--column", "3"], "both name column 3"),
])
def test_bad_x_column_is_one_line(tmp_path, capsys, given, words):
    f, out = tmp_path / "drag.csv", tmp_path / "parts.csv"
    _table(f)
    assert main(["separate", str(f), *given, "--basis", "x", "-o", str(out)]) == 1
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_a_field_refuses_x_column(tmp_path, capsys):
    f = tmp_path / "field.npz"
    g = np.linspace(-1, 1, 20)
    np.savez(f, x=g, y=g, z=np.add.outer(g, g))
    assert main(["separate", str(f), "--x-column", "x", "--basis", "x"]) == 1
    assert "--x-column is for a CSV" in capsys.readouterr().err
