"""Pendulum angles in degrees: converted with --units deg, noted when they look like degrees.

Given in degrees, a 34-degree swing with the full sine was read as "the model does not fit" with no
word about the unit: sin(theta) of degrees is not the physics.
"""
import numpy as np
import pytest

from odnn_sep.mismatch import make_model


def _swing_csv(tmp_path):
    t = np.linspace(0, 10, 250)
    m = make_model("pendulum", {"w2": 9.0, "c": 0.05, "theta0": 0.6}).with_effect("large_angle", {"s_angle": 1.0})
    y = np.degrees(m.predict(t))
    y = y + 0.002 * np.abs(y).max() * np.random.default_rng(2).normal(size=t.size)
    f = tmp_path / "swing_deg.csv"
    f.write_text("t,theta\n" + "".join(f"{a},{b}\n" for a, b in zip(t, y, strict=True)))
    return f


def test_degrees_converted_and_large_angle_named(tmp_path, capsys):
    import json

    from odnn_sep.cli import main
    f = _swing_csv(tmp_path)
    rep = tmp_path / "r.json"
    assert main(["mismatch", str(f), "--model", "pendulum", "--units", "deg", "--report", str(rep), "--quiet"]) == 0
    v = json.loads(rep.read_text())["verdict"]
    assert [e["effect"] for e in v["effects"]] == ["large_angle"]
    assert not any("look like degrees" in n for n in v["notes"])


@pytest.mark.parametrize("argv, msg", [(["--model", "oscillator", "--units", "deg"], "no angle physics"),
                                       (["--model", "pendulum", "--param", "L=0.3", "--units", "deg"],
                                        "tangential acceleration"),
                                       (["--model", "pendulum", "--units", "K"], "is for temperatures")])
def test_units_that_do_not_apply_are_refused(tmp_path, capsys, argv, msg):
    from odnn_sep.cli import main
    f = _swing_csv(tmp_path)
    assert main(["mismatch", str(f), *argv]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and msg in err[0]
