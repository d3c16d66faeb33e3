"""Records without noise (a simulation compared with a simulation): rounding is not evidence.

Before the record's resolution was counted in every sum of squares, a noise-free free fall was
given a time delay, a noise-free cooling curve with radiation got a second body, a step of 3e-15
and a drift on top, and a constant column had radiation named with a held-out gain of 1e300.
"""
import numpy as np
import pytest

from odnn_sep.errors import InputError
from odnn_sep.mismatch import explain, make_model
from odnn_sep.mismatch.resolution import resolution


def _names(res):
    return [c.effect for c in res.named], [d.get("effect") for d in res.disturbances]


def test_noise_free_null_names_nothing():
    t = np.linspace(0, 0.6, 120)
    y = make_model("freefall", {"g": 9.81, "h0": 2.0}).predict(t)
    res = explain("freefall", t, y)
    assert _names(res) == ([], [])
    assert res.failed == []
    assert any("numerical resolution" in n for n in res.notes)
    # the noise level reported is the resolution, not the rounding of the fit
    assert res.noise_sigma == pytest.approx(resolution(y))


def test_noise_free_effect_is_named_alone():
    t = np.linspace(0, 300, 300)
    m = make_model("cooling", {"h": 0.01}).with_effect("radiation", {"r_rad": 0.003})
    res = explain("cooling", t, m.predict(t))
    assert _names(res) == (["radiation"], [])
    assert res.verdict.fit.params["r_rad"] == pytest.approx(0.003, rel=1e-4)


def test_constant_record_is_refused():
    t = np.arange(200) * 0.1
    with pytest.raises(InputError, match="constant"):
        explain("cooling", t, np.full(200, 20.0))


def test_cli_constant_record_one_line(tmp_path, capsys):
    from odnn_sep.cli import main

    f = tmp_path / "c.csv"
    f.write_text("t,T\n" + "".join(f"{i * 0.1},20\n" for i in range(50)))
    assert main(["mismatch", str(f), "--model", "cooling", "--quiet"]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "constant" in err[0]


def test_nanometre_oscillator_is_analysed_in_its_own_unit():
    # integrated to 1e-11 absolute and stepped by 1e-5, a motion of 1e-9 had every effect fit "fail"
    # and a cubic stiffness of 5e17 per m^2 s^2 never left 0; analysed as y / 1e-9 (valuescale.py)
    # the record gives the verdict and parameters of the same record in nanometres
    t = np.linspace(0, 20, 400)
    m = make_model("oscillator", {"k": 4.0, "c": 0.1, "x0": 1.0}).with_effect("cubic_stiffness", {"beta": 0.5})
    y = m.predict(t) + 0.01 * np.random.default_rng(1).normal(size=t.size)
    nm, metres = explain("oscillator", t, y), explain("oscillator", t, y * 1e-9)
    assert _names(nm) == _names(metres) == (["cubic_stiffness"], [])
    assert metres.final_fit.params["beta"] * 1e-18 == pytest.approx(nm.final_fit.params["beta"], rel=1e-3)
    assert metres.final_fit.params["x0"] * 1e9 == pytest.approx(nm.final_fit.params["x0"], rel=1e-3)
    lo, hi = metres.final_intervals["beta"]
    assert (lo * 1e-18, hi * 1e-18) == pytest.approx(nm.final_intervals["beta"], rel=1e-3)
    assert metres.noise_sigma == pytest.approx(1e-9 * nm.noise_sigma, rel=1e-3)
    assert any("values analysed as y / 1e-09" in n for n in metres.notes)
