"""A 1-D record's coordinate is reachable as ``x`` whatever its header calls it.

The help and every example write the basis in x; a lab table headed ``length,period`` refused
``--basis 'sqrt(x)'`` (only ``length`` was known), so a first try failed on a name.
"""
import json

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.errors import InputError
from odnn_sep.fit.expr import basis_from_expressions


def _pendulum(path):
    L = np.linspace(0.1, 2.0, 25)
    T = 2 * np.pi / np.sqrt(9.81) * np.sqrt(L) + 0.01 * np.random.default_rng(0).normal(size=L.size)
    np.savetxt(path, np.c_[L, T], delimiter=",", header="length,period", comments="")


def test_x_and_the_header_name_give_the_same_fit(tmp_path):
    f = tmp_path / "pendulum.csv"
    _pendulum(f)
    reps = []
    for expr in ("sqrt(x)", "sqrt(length)"):
        rep = tmp_path / f"{expr[5]}.json"
        assert main(["separate", str(f), "--basis", expr, "--name", "a", "--quiet", "--report", str(rep)]) == 0
        reps.append(json.loads(rep.read_text())["parameters"]["a"])
    assert reps[0] == reps[1]
    assert reps[0]["interval"][0] < 2 * np.pi / np.sqrt(9.81) < reps[0]["interval"][1]


def test_an_unknown_name_lists_both():
    with pytest.raises(InputError, match=r"coordinates \['length', 'x'\]"):
        basis_from_expressions(["sqrt(len)"], ("length",))


def test_a_field_keeps_x_and_y_only():
    b = basis_from_expressions(["x*y"], ("x", "y"))
    assert b.evaluate(np.array([[2.0, 3.0]])).tolist() == [[6.0]]
    with pytest.raises(InputError, match="unknown name 'z'"):
        basis_from_expressions(["z"], ("x", "y"))
