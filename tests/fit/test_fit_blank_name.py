"""``separate --name ''`` (or blank) printed an unlabelled line and keyed the report's parameter by ''."""
import numpy as np
import pytest

from odnn_sep.cli import main


@pytest.mark.parametrize("names", [[""], [" "], ["a", ""]])
def test_blank_name_refused(tmp_path, capsys, names):
    x = np.linspace(0, 3, 100)
    data = tmp_path / "s.csv"
    np.savetxt(data, np.c_[x, 2 * np.sin(5 * x) + x], delimiter=",", header="x,y", comments="")
    basis = ["sin(5*x)", "x"][:len(names)]
    argv = ["separate", str(data), "--quiet", "--report", str(tmp_path / "r.json")]
    for b in basis:
        argv += ["--basis", b]
    for n in names:
        argv += ["--name", n]
    assert main(argv) == 1
    assert "is blank" in capsys.readouterr().err
    assert not (tmp_path / "r.json").exists()
