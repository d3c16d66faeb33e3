"""`odnn-sep simulate`: writes data + truth, round-trips through `odnn-sep separate`."""
import json
import re
import subprocess
import sys

import numpy as np
import pytest

from odnn_sep.cli import main


def test_simulate_csv_and_truth(tmp_path, capsys):
    out, truth = tmp_path / "fig2.csv", tmp_path / "truth.json"
    assert main(["simulate", "figure2", "-o", str(out), "--truth", str(truth), "--seed", "3"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert out.read_text().splitlines()[0] == "x,y,physics,disturbance,noise"
    np.testing.assert_allclose(data[:, 1], data[:, 2:].sum(1), atol=1e-12)
    t = json.loads(truth.read_text())
    assert t["dataset"] == "figure2" and set(t["theta_true"]) == {"theta"}
    printed = capsys.readouterr().out
    assert "true parameters: theta = " in printed
    assert "try: odnn-sep separate" in printed


def test_simulate_then_separate_recovers_theta(tmp_path, capsys):
    out = tmp_path / "per.csv"
    assert main(["simulate", "implicit_periodic", "-o", str(out), "--seed", "1", "--snr-db", "40"]) == 0
    printed = capsys.readouterr().out
    true = float(re.search(r"theta = ([-0-9.e]+)", printed).group(1))
    period = re.search(r"periodic:([0-9.]+)", printed).group(1)
    assert main(["separate", str(out), "--basis", "x*sin(5*x)", "--disturbance", f"periodic:{period}"]) == 0
    fitted = capsys.readouterr().out
    est = float(re.search(r"=\s+([-0-9.e]+)\s+±", fitted).group(1))
    assert est == pytest.approx(true, rel=5e-3)


def test_simulate_2d_npz(tmp_path):
    out = tmp_path / "heat.npz"
    assert main(["simulate", "heat2d", "-o", str(out)]) == 0
    d = np.load(out)
    assert d["z"].shape == (d["y"].size, d["x"].size)
    np.testing.assert_allclose(d["z"], d["physics"] + d["disturbance"] + d["noise"], atol=1e-12)
    G = d["disturbance"]
    np.testing.assert_allclose(G, G[::-1, :], atol=1e-12)
    np.testing.assert_allclose(G, G[:, ::-1], atol=1e-12)


def test_simulate_errors(tmp_path, capsys):
    assert main(["simulate", "heat2d", "-o", str(tmp_path / "h.csv")]) == 1
    err = capsys.readouterr().err
    assert "Error: --output" in err and "write it to a .npz file" in err
    assert main(["simulate", "figure2", "-o", str(tmp_path / "a.csv"), "--truth", str(tmp_path / "a.csv")]) == 1
    assert "is the same file as --output" in capsys.readouterr().err
    assert main(["simulate", "figure2", "-o", str(tmp_path / "nodir" / "a.csv")]) == 1
    assert "does not exist; create it first" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        main(["simulate", "nope", "-o", str(tmp_path / "a.csv")])
    assert e.value.code == 2


def test_help_does_not_import_torch_or_scipy():
    code = ("import sys; from odnn_sep.cli import build_parser; build_parser(); "
            "print('torch' in sys.modules, 'odnn_sep.signals.explicit' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["False", "False"]
