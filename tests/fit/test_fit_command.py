"""`odnn-sep separate`: expressions, disturbance specs, files, errors."""
import json

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.errors import InputError
from odnn_sep.fit import basis_from_expressions, parse_disturbance


@pytest.fixture
def csv(tmp_path):
    x = np.linspace(-2, 2, 201)
    y = 0.5 * x ** 2 * np.sin(5 * x) + np.cos(x)
    p = tmp_path / "sig.csv"
    np.savetxt(p, np.c_[x, y, -y], delimiter=",", header="x,F,G", comments="")
    return p


def test_separate_recovers_theta_and_writes_outputs(csv, tmp_path, capsys):
    rep, comp, fig = tmp_path / "r.json", tmp_path / "c.csv", tmp_path / "f.png"
    code = main(["separate", str(csv), "--basis", "x**2*sin(5*x)", "--name", "a", "--disturbance", "even",
                 "--report", str(rep), "-o", str(comp), "--plot", str(fig)])
    assert code == 0
    r = json.loads(rep.read_text())
    assert r["parameters"]["a"]["value"] == pytest.approx(0.5, rel=1e-9)
    data = np.loadtxt(comp, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 2] + data[:, 3] + data[:, 4], data[:, 1], atol=1e-8)
    assert fig.stat().st_size > 1000


def test_column_by_name(csv, tmp_path):
    rep = tmp_path / "r.json"
    assert main(["separate", str(csv), "--column", "G", "--basis", "x**2*sin(5*x)", "--name", "a",
                 "--disturbance", "even", "--report", str(rep)]) == 0
    assert json.loads(rep.read_text())["parameters"]["a"]["value"] == pytest.approx(-0.5, rel=1e-9)


def test_2d_npz_field(tmp_path):
    g = np.linspace(-1, 1, 31)
    X, Y = np.meshgrid(g, g)
    z = 1.5 * np.exp(-((X + 1) ** 2 + (Y - 1) ** 2) / 0.3) + np.cos(X) * np.cos(2 * Y)
    np.savez(tmp_path / "f.npz", x=g, y=g, z=z)
    rep = tmp_path / "r.json"
    assert main(["separate", str(tmp_path / "f.npz"), "--basis", "exp(-((x+1)**2+(y-1)**2)/0.3)", "--name", "q",
                 "--disturbance", "even:0,0", "--report", str(rep)]) == 0
    assert json.loads(rep.read_text())["parameters"]["q"]["value"] == pytest.approx(1.5, rel=1e-9)


def test_expression_errors():
    with pytest.raises(InputError, match=r"calls unknown function 'sni' \(did you mean 'sin'\?\)"):
        basis_from_expressions(["sni(x)"])
    with pytest.raises(InputError, match="uses Attribute, which is not allowed"):
        basis_from_expressions(["x.__class__"])
    with pytest.raises(InputError, match=r"uses unknown name 't' \(did you mean"):
        basis_from_expressions(["t"], coords=("s", "tt"))
    with pytest.raises(InputError, match=r"disturbance spec 'evn' is not understood \(did you mean 'even'\?\)"):
        parse_disturbance("evn")


def test_cli_errors_exit_1(csv, tmp_path, capsys):
    assert main(["separate", str(tmp_path / "missing.csv"), "--basis", "x"]) == 1
    assert "does not exist" in capsys.readouterr().err
    assert main(["separate", str(csv), "--basis", "x", "-o", str(csv)]) == 1
    assert "is the input file" in capsys.readouterr().err
    assert main(["separate", str(csv), "--basis", "x", "--column", "Q"]) == 1
    assert "--column 'Q' is not a column of the CSV" in capsys.readouterr().err
