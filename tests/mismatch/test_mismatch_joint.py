"""Several series fitted jointly (joint.py, series_io.py, joint_command.py)."""
import json
import subprocess
import sys

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.errors import InputError
from odnn_sep.mismatch.joint import MAX_SERIES, explain_joint, joint_estimates, joint_model
from odnn_sep.mismatch.model import make_model

T_AMB = 21.5
H = (0.010, 0.015, 0.020, 0.025, 0.030)


def _mugs(noise=0.05, seed=0, radiation=0.0, n=60):
    rng = np.random.default_rng(seed)
    out = {}
    for i, h in enumerate(H):
        t = np.linspace(0, 300, n) + 3.0 * i          # each mug on its own clock
        m = make_model("cooling", {"h": h, "T_ambient": T_AMB, "T0": 90.0 - 4 * i})
        if radiation:
            m = m.with_effect("radiation", {"r_rad": radiation})
        out[f"mug{i + 1}"] = (t, m.predict(t) + noise * rng.normal(size=n))
    return out


def test_five_mugs_one_room():
    res = explain_joint("cooling", _mugs())
    assert res.effects == []
    est = joint_estimates(res)
    v, lo, hi = est["shared"]["T_ambient"]
    assert lo < T_AMB < hi and hi - lo < 0.5
    for i, h in enumerate(H):
        v, lo, hi = est["series"][f"mug{i + 1}"]["h"]
        assert lo < h < hi and abs(v - h) < 0.05 * h


def test_shared_radiation_is_named_once():
    s = dict(list(_mugs(radiation=0.006, seed=1, n=30).items())[:3])
    res = explain_joint("cooling", s, effects=["radiation", "two_body_heat"])
    assert res.effects[:1] == ["radiation"]
    assert abs(res.final_fit.params["r_rad"] - 0.006) < 0.002


def test_shared_override_and_its_errors():
    m, t, y = joint_model("cooling", _mugs(), shared=["T_ambient", "h"])
    assert "h" in m.free and "h_mug1" not in m.free
    with pytest.raises(InputError, match="shared parameter 'T_amb' is not a parameter of 'cooling'"):
        joint_model("cooling", _mugs(), shared=["T_amb"])
    with pytest.raises(InputError, match="joint series are fitted for the presets"):
        joint_model("heat2d", _mugs())


def test_limits_one_line_errors():
    s = _mugs()
    s["short"] = (np.arange(5.0), np.ones(5))
    with pytest.raises(InputError, match="series 'short' has 5 points; each series needs at least 8"):
        joint_model("cooling", s)
    many = {f"m{i}": (np.arange(10.0), np.ones(10)) for i in range(MAX_SERIES + 1)}
    with pytest.raises(InputError, match=f"at most {MAX_SERIES} series"):
        joint_model("cooling", many)
    with pytest.raises(InputError, match="at least 2 series"):
        joint_model("cooling", {"a": s["mug1"]})


def _write_csv(path, series):
    with open(path, "w") as fh:
        fh.write("time,mug,T\n")
        for name, (t, y) in series.items():
            fh.writelines(f"{a:.3f},{name},{b:.5f}\n" for a, b in zip(t, y, strict=True))


def _cli(*argv):
    return main(["mismatch", *argv])


def test_cli_series_column_and_several_files(tmp_path, capsys):
    s = _mugs(n=30)
    path = tmp_path / "mugs.csv"
    _write_csv(path, s)
    rep = tmp_path / "r.json"
    assert _cli(str(path), "--model", "cooling", "--series", "mug", "--effects", "two_body_heat",
                "--report", str(rep)) == 0
    out = capsys.readouterr().out
    assert "Joint fit: shared parameters" in out and "mug5: h = " in out
    d = json.loads(rep.read_text())
    assert set(d["joint"]["series"]) == {f"mug{i}" for i in range(1, 6)}
    files = []
    for name in ("a", "b"):
        files.append(tmp_path / f"{name}.csv")
        _write_csv(files[-1], {name: s[{"a": "mug1", "b": "mug2"}[name]]})
    assert _cli(*map(str, files), "--model", "cooling", "--column", "T", "--effects", "two_body_heat",
                "--quiet") == 0


def test_cli_bad_series_column_one_line(tmp_path, capsys):
    path = tmp_path / "mugs.csv"
    _write_csv(path, _mugs(n=20))
    assert _cli(str(path), "--model", "cooling", "--series", "cup") == 1
    lines = [ln for ln in capsys.readouterr().err.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and "--series 'cup' is not a column" in lines[0]


def test_cli_subprocess_exit_code(tmp_path):
    path = tmp_path / "mugs.csv"
    _write_csv(path, {k: v for k, v in _mugs(n=10).items()})
    r = subprocess.run([sys.executable, "-m", "odnn_sep.cli", "mismatch", str(path), "--model", "cooling",
                        "--series", "mug", "--shared", "T_amb"], capture_output=True, text=True)
    assert r.returncode == 1 and "shared parameter 'T_amb'" in r.stderr


def test_three_releases_of_one_oscillator_share_k_and_c():
    rng = np.random.default_rng(5)
    s = {}
    for i, x0 in enumerate((1.0, 0.6, -0.8)):
        t = np.linspace(0, 15, 200)
        m = make_model("oscillator", {"k": 4.0, "c": 0.08, "x0": x0, "v0": 0.1 * i})
        s[f"run{i}"] = (t, m.predict(t) + 0.01 * rng.normal(size=200))
    res = explain_joint("oscillator", s, effects=["cubic_stiffness"])
    est = joint_estimates(res)
    assert res.effects == []
    for k, v in (("k", 4.0), ("c", 0.08)):
        val, lo, hi = est["shared"][k]
        assert lo < v < hi and abs(val - v) < 0.05 * v
    assert abs(est["series"]["run2"]["x0"][0] + 0.8) < 0.02
