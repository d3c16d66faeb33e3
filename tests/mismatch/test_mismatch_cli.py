import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from odnn_sep.cli import main

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"


@pytest.fixture
def cooling_csv(tmp_path):
    t = np.linspace(0, 200, 120)
    rng = np.random.default_rng(0)
    y = 22 + 73 * np.exp(-0.02 * t) + 0.1 * rng.normal(size=t.size)
    p = tmp_path / "cool.csv"
    p.write_text("time,junk,temp\n" + "\n".join(f"{a},x,{b}" for a, b in zip(t, y, strict=True)) + "\n")
    return p


def test_cli_writes_report_and_plot(cooling_csv, tmp_path, capsys):
    rep, fig = tmp_path / "r.json", tmp_path / "p.png"
    rc = main(["mismatch", str(cooling_csv), "--model", "cooling", "--column", "temp", "--param", "h=0.05",
               "--report", str(rep), "--plot", str(fig)])
    assert rc == 0
    d = json.loads(rep.read_text())
    assert set(d) >= {"verdict", "candidates", "calibration", "where", "fit"}
    assert set(d["verdict"]) >= {"effect", "description", "parameters"}
    assert set(d["fit"]) == {"before", "after"}
    assert all(set(c) >= {"effect", "score", "parameters"} for c in d["candidates"])
    assert d["verdict"]["effect"] is None
    assert fig.stat().st_size > 1000
    assert "Verdict:" in capsys.readouterr().out


def test_cli_unknown_model_suggests(cooling_csv, capsys):
    assert main(["mismatch", str(cooling_csv), "--model", "coolin"]) == 1
    assert "Error: unknown model 'coolin'; did you mean 'cooling'?" in capsys.readouterr().err


def test_cli_unknown_param_and_column(cooling_csv, capsys):
    assert main(["mismatch", str(cooling_csv), "--model", "cooling", "--param", "hh=1"]) == 1
    assert "unknown parameter 'hh' for model 'cooling'; did you mean 'h'?" in capsys.readouterr().err
    assert main(["mismatch", str(cooling_csv), "--model", "cooling", "--column", "tmp"]) == 1
    assert "--column 'tmp' is not a column of the CSV; did you mean 'temp'?" in capsys.readouterr().err
    assert main(["mismatch", str(cooling_csv), "--model", "cooling", "--param", "h"]) == 1
    assert "--param expects NAME=VALUE; got 'h'" in capsys.readouterr().err


def test_cli_refuses_output_equal_to_input(cooling_csv, capsys):
    assert main(["mismatch", str(cooling_csv), "--model", "cooling", "--report", str(cooling_csv)]) == 1
    assert "is the input file" in capsys.readouterr().err


def test_cli_bad_extension_and_missing_file(tmp_path, capsys):
    p = tmp_path / "x.txt"
    p.write_text("1,2\n")
    assert main(["mismatch", str(p), "--model", "cooling"]) == 1
    assert "use .csv" in capsys.readouterr().err
    assert main(["mismatch", str(tmp_path / "nope.csv"), "--model", "cooling"]) == 1
    assert "does not exist" in capsys.readouterr().err


def test_cli_npz_heat2d(tmp_path):
    from odnn_sep.mismatch import make_model
    g = np.linspace(0, 1, 24)
    X, Y = np.meshgrid(g, g)
    xy = np.column_stack([X.ravel(), Y.ravel()])
    m = make_model("heat2d", {"sources": "0.3:0.4", "S1": 1.0, "alpha": 0.01})
    z = (m.predict(xy) + 0.02 * np.random.default_rng(0).normal(size=len(xy))).reshape(24, 24)
    p = tmp_path / "f.npz"
    np.savez(p, x=g, y=g, z=z)
    rep = tmp_path / "r.json"
    assert main(["mismatch", str(p), "--model", "heat2d", "--param", "sources=0.3:0.4", "--quiet",
                 "--report", str(rep)]) == 0
    d = json.loads(rep.read_text())
    assert abs(d["calibration"]["parameters"]["S1"]["value"] - 1.0) < 0.05


def test_help_does_not_import_torch():
    code = ("import sys; from odnn_sep.cli import build_parser; build_parser(); "
            "import odnn_sep.mismatch.command; print('torch' in sys.modules, 'scipy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split()[0] == "False"


@pytest.mark.skipif(not (DATA / "cooling_water_wagon").exists(), reason="shared data (cooling_water_wagon) absent")
def test_cli_real_cooling_control_vs_oil(tmp_path):
    """Wagon's mug: the control run misses evaporation; the oil run (evaporation suppressed) much less."""
    d = {}
    for name in ("CoolingWater1_fastR2.csv", "CoolingWater2_fastR2.csv"):
        rep = tmp_path / (name + ".json")
        assert main(["mismatch", str(DATA / "cooling_water_wagon" / name), "--model", "cooling",
                     "--quiet", "--report", str(rep)]) == 0
        d[name] = json.loads(rep.read_text())
    control, oil = d["CoolingWater1_fastR2.csv"], d["CoolingWater2_fastR2.csv"]
    assert control["verdict"]["effect"] == "evaporation"
    assert oil["fit"]["before"]["residual_rms"] < 0.2 * control["fit"]["before"]["residual_rms"]


def test_cli_wav_hum_missing_harmonic(tmp_path):
    import soundfile as sf
    sr = 400
    t = np.arange(2 * sr) / sr
    rng = np.random.default_rng(3)
    y = 0.3 * np.sin(2 * np.pi * 50.02 * t) + 0.02 * np.sin(2 * np.pi * 3 * 50.02 * t + 0.4) \
        + 0.01 * rng.normal(size=t.size)
    p = tmp_path / "hum.wav"
    sf.write(p, y, sr, subtype="FLOAT")
    rep = tmp_path / "r.json"
    assert main(["mismatch", str(p), "--model", "hum", "--param", "f0=50", "--quiet", "--report", str(rep)]) == 0
    d = json.loads(rep.read_text())
    assert d["verdict"]["effect"] == "missing_harmonic"
    assert d["verdict"]["parameters"]["k_h"] == 3.0
    assert abs(d["calibration"]["parameters"]["f0"]["value"] - 50.02) < 0.002
    assert d["input"]["sr"] == sr
