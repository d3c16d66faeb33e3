import numpy as np
import pytest

from odnn_sep.errors import InputError
from odnn_sep.mismatch import ModelIntegrationError, explain, make_model, ode_model


def test_unknown_preset_suggests_closest():
    with pytest.raises(InputError, match=r"unknown model 'oscilator'; did you mean 'oscillator'\? "
                                         r"available presets: oscillator, pendulum"):
        make_model("oscilator")


def test_unknown_parameter_suggests_closest():
    with pytest.raises(InputError, match=r"unknown parameter 'T_amb' for model 'cooling'; "
                                         r"did you mean 'T_ambient'\? parameters: T0, T_ambient, h"):
        make_model("cooling", {"T_amb": 20})


def test_non_numeric_parameter():
    with pytest.raises(InputError, match=r"parameter 'k' must be a number; got 'abc'"):
        make_model("oscillator", {"k": "abc"})


def test_length_mismatch():
    with pytest.raises(InputError, match=r"model/data length mismatch: t has 100 samples but y has 99"):
        explain("cooling", np.arange(100.0), np.ones(99))


def test_non_monotonic_time():
    t = np.arange(100.0)
    t[50] = 10.0
    with pytest.raises(InputError, match=r"time must be strictly increasing; t\[50\] = 10 follows t\[49\] = 49"):
        explain("cooling", t, np.ones(100))


def test_too_little_data_for_heldout_split():
    with pytest.raises(InputError, match=r"too little data for the held-out split: 20 samples; need at least 24"):
        explain("cooling", np.arange(20.0), np.linspace(90, 30, 20))


def test_nan_in_data():
    y = np.ones(100)
    y[7] = np.nan
    with pytest.raises(InputError, match=r"y contains 1 NaN value\(s\) \(first at index 7\)"):
        explain("cooling", np.arange(100.0), y)


def test_model_that_fails_to_integrate():
    m = ode_model(lambda t, s, a: [a * s[0] ** 3], {"a": 50.0, "x0": 5.0}, ["x0"])
    with pytest.raises(ModelIntegrationError, match=r"model 'user_ode' failed to integrate with parameters"):
        m.predict(np.linspace(0, 10, 100))


def test_unknown_effect():
    t = np.linspace(0, 100, 200)
    with pytest.raises(InputError, match=r"unknown effect 'radiaton'; did you mean 'radiation'\?"):
        explain("cooling", t, 20 + 70 * np.exp(-0.03 * t), effects=["radiaton"])


def test_bad_sources_spec():
    with pytest.raises(InputError, match=r"sources must be x:y pairs separated by ';'"):
        make_model("heat2d", {"sources": "0.3,0.4"}).predict(np.zeros((4, 2)))


def test_cli_input_disturbance_units_errors(tmp_path, capsys):
    from odnn_sep.cli import main
    t = np.linspace(0, 100, 120)
    p = tmp_path / "c.csv"
    p.write_text("time,temp,heater\n" + "\n".join(f"{a},{20 + 70 * np.exp(-0.03 * a)},{1.0}" for a in t))
    for argv, msg in ((["--input", "heatr"], "heater"), (["--disturbance", "wobble"], "wobble"),
                      (["--input", "temp"], "analysed column")):
        assert main(["mismatch", str(p), "--model", "cooling", *argv]) == 1
        err = capsys.readouterr().err
        assert msg in err and len(err.strip().splitlines()) == 1


def test_folds_option_and_small_data_note(tmp_path, capsys):
    from odnn_sep.cli import main
    t = np.linspace(0, 100, 16)
    y = 20 + 70 * np.exp(-0.03 * t) + 0.1 * np.random.default_rng(0).normal(size=16)
    p = tmp_path / "short.csv"
    p.write_text("time,temp\n" + "\n".join(f"{a},{b}" for a, b in zip(t, y)))
    assert main(["mismatch", str(p), "--model", "cooling", "--folds", "1"]) == 1
    assert "--folds must be between 2 and 20" in capsys.readouterr().err
    assert main(["mismatch", str(p), "--model", "cooling"]) == 1
    assert "--folds 2" in capsys.readouterr().err
    res = explain("cooling", t, y, folds=2)
    assert any("little power" in n for n in res.notes)
