"""``--disturbance even:C`` with a centre of the wrong dimension, or not finite.

``even:1,2`` on a 1-D signal (or three numbers on a field) ended in a NumPy broadcasting traceback;
``even:nan`` was refused as "no sample has a mirror image".
"""
import numpy as np
import pytest

from odnn_sep.errors import InputError
from odnn_sep.fit.expr import parse_disturbance


@pytest.mark.parametrize("spec, ndim", [("even:1,2", 1), ("even:nan", 1), ("even:inf", 1), ("even:1,2,3", 2),
                                        ("even:0,nan", 2)])
def test_bad_centre_refused(spec, ndim):
    with pytest.raises(InputError, match="the centre of symmetry must be"):
        parse_disturbance(spec, ndim=ndim)


def test_good_centres_kept():
    assert parse_disturbance("even:1.5").center == 1.5
    assert parse_disturbance("even:0.5,0.25", ndim=2).center == (0.5, 0.25)
    assert parse_disturbance("even:0.5", ndim=2).center == 0.5


def test_cli_one_line(tmp_path, capsys):
    from odnn_sep.cli import main
    x = np.linspace(-1, 1, 41)
    data = tmp_path / "s.csv"
    np.savetxt(data, np.c_[x, np.sin(5 * x) + x**2], delimiter=",", header="x,y", comments="")
    assert main(["separate", str(data), "--basis", "sin(5*x)", "--disturbance", "even:1,2", "--quiet"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("Error: --disturbance 'even:1,2'") and "\n" not in err
