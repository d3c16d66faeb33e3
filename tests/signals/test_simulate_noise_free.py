"""`simulate --snr-db inf` writes noise-free data (the API's make_dataset(snr_db=inf) already did)."""
import json

import numpy as np

from odnn_sep.cli import main


def test_simulate_snr_inf_writes_noise_free_data(tmp_path, capsys):
    out, truth = tmp_path / "fig2.csv", tmp_path / "truth.json"
    assert main(["simulate", "figure2", "-o", str(out), "--truth", str(truth), "--snr-db", "inf", "--seed", "4"]) == 0
    table = np.genfromtxt(out, delimiter=",", names=True)
    assert np.all(table["noise"] == 0) and np.array_equal(table["y"], table["physics"] + table["disturbance"])
    t = json.loads(truth.read_text())
    assert t["noise_sigma"] == 0.0
    # the noise-free record gives theta to rounding
    capsys.readouterr()
    rep = tmp_path / "r.json"
    assert main(["separate", str(out), "--basis", "x**2*sin(5*x)", "--disturbance", "even", "--quiet",
                 "--report", str(rep)]) == 0
    got = json.loads(rep.read_text())["parameters"]["x**2*sin(5*x)"]["value"]
    assert abs(got - t["theta_true"]["theta"]) < 1e-9


def test_simulate_snr_nan_and_minus_inf_are_refused(tmp_path, capsys):
    for bad in ("nan", "-inf"):
        assert main(["simulate", "figure2", "-o", str(tmp_path / "f.csv"), f"--snr-db={bad}"]) != 0
        assert "inf for noise-free data" in capsys.readouterr().err
        assert not (tmp_path / "f.csv").exists()
