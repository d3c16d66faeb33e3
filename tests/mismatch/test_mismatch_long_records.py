"""Long records are fitted on a bounded, alias-free subsample (odnn_sep/mismatch/long_record.py).

The limit is lowered through its environment variable so that the records stay small and the
tests fast; what is checked is the size actually fitted, the note, and that the subsample's
intervals still cover the truth (not a wall-clock time).
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.mismatch import explain, make_model


@pytest.fixture
def limit_400(monkeypatch):
    monkeypatch.setenv("ODNN_SEP_MAX_FIT_SAMPLES", "400")


def _cooling(n, seed=3, effect=None):
    t = np.linspace(0, 200, n)
    m = make_model("cooling", {"h": 0.02, "T_ambient": 22.0, "T0": 95.0})
    if effect:
        m = m.with_effect(*effect)
    return t, m.predict(t) + 0.1 * np.random.default_rng(seed).normal(size=n)


def test_long_record_is_fitted_on_a_bounded_subsample_that_covers_the_truth(limit_400):
    t, y = _cooling(4000)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain("cooling", t, y)
    assert len(res.y) <= 400 and len(res.t) == len(res.y)
    assert res.t[0] == t[0] and np.all(np.isin(res.t, t))            # real samples, evenly spaced
    assert len(set(np.round(np.diff(res.t), 9))) == 1
    assert res.notes[0].startswith("long record: fitted on one sample in 10 (400 of 4000")
    # the whole record is still compared with the final model: the samples between the fitted ones agree
    assert res.notes[1].startswith("residual RMS over all 4000 samples of the record: ")
    full_rms = float(res.notes[1].split(": ")[1].split(" ")[0])
    assert 0.09 < full_rms < 0.11
    assert res.effects == []
    lo, hi = res.final_intervals["h"]
    assert lo <= 0.02 <= hi


def test_long_record_still_names_its_effect(limit_400):
    t, y = _cooling(4000, seed=5, effect=("radiation", {"r_rad": 0.01}))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain("cooling", t, y)
    assert len(res.y) <= 400 and res.effects[:1] == ["radiation"]


def test_fast_content_keeps_a_denser_subsample_than_the_limit(limit_400):
    # a 45 Hz line at 1 kHz: every 10th sample would fold it to 5 Hz; the step keeps it below Nyquist
    from odnn_sep.mismatch.long_record import content_top, subsample_step
    t = np.arange(4000) / 1000.0
    y = 1 + 0.5 * t + 0.2 * np.sin(2 * np.pi * 45 * t) + 0.01 * np.random.default_rng(0).normal(size=t.size)
    assert abs(content_top(t, y) - 45) < 0.5
    q = subsample_step(t, y)
    assert 1000 / (2 * q) >= 1.5 * 45 and q < 10


def test_content_too_fast_for_any_bounded_subsample_is_a_one_line_error(limit_400, tmp_path, capsys):
    t = np.arange(4000) / 1000.0
    y = 20 + 70 * np.exp(-0.5 * t) + 0.5 * np.sin(2 * np.pi * 300 * t)
    y = y + 0.01 * np.random.default_rng(0).normal(size=t.size)
    path = tmp_path / "fast.csv"
    np.savetxt(path, np.c_[t, y], delimiter=",", header="t,T", comments="")
    report = tmp_path / "r.json"
    assert main(["mismatch", str(path), "--model", "cooling", "--quiet", "--report", str(report)]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--duration" in err and "ODNN_SEP_MAX_FIT_SAMPLES" in err
    assert not report.exists()


def test_cli_notes_the_subsample(limit_400, tmp_path, capsys):
    t, y = _cooling(1200)
    path = tmp_path / "long.csv"
    np.savetxt(path, np.c_[t, y], delimiter=",", header="t,T", comments="")
    assert main(["mismatch", str(path), "--model", "cooling"]) == 0
    assert "fitted on one sample in 3 (400 of 1200" in capsys.readouterr().out


def test_short_records_are_fitted_as_given():
    t, y = _cooling(300)
    res = explain("cooling", t, y)
    assert len(res.y) == 300 and not any(n.startswith("long record") for n in res.notes)


def test_joint_series_share_the_limit(limit_400):
    from odnn_sep.mismatch.joint import explain_joint
    series = {}
    for i, h in enumerate((0.02, 0.035)):
        t = np.linspace(0, 200, 1200)
        y = make_model("cooling", {"h": h, "T_ambient": 22.0, "T0": 95.0 - 10 * i}).predict(t)
        series[f"mug{i}"] = (t, y + 0.1 * np.random.default_rng(i).normal(size=t.size))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain_joint("cooling", series)
    assert len(res.y) <= 400
    assert res.notes[0].startswith("long series: mug0 fitted on one sample in 6 (200 of 1200)")
    lo, hi = res.final_intervals["T_ambient"]
    assert lo <= 22.0 <= hi


def test_noise_free_long_record_is_subsampled_not_refused():
    # a simulation has no noise: its resolution is the floor, so rounding is not read as fast content
    from odnn_sep.mismatch.long_record import subsample_step
    t = np.linspace(0, 20, 20000)
    y = make_model("oscillator", {"k": 4.0, "c": 0.05, "x0": 1.0, "v0": 0.0}).predict(t)
    q = subsample_step(t, y)
    assert 2 <= q and len(t) / q <= 4 * 2000


@pytest.mark.parametrize("n, rate, harmonics, message", [
    (400, 400.0, 5, "at or above the record's Nyquist frequency (200 Hz)"),
    (300, 8000.0, 25, "above the limit of 20 hum harmonics"),
])
def test_hum_harmonics_are_limited_with_a_one_line_error(tmp_path, capsys, n, rate, harmonics, message):
    t = np.arange(n) / rate
    y = np.cos(2 * np.pi * 50 * t) + 0.01 * np.random.default_rng(0).normal(size=n)
    path = tmp_path / "hum.csv"
    np.savetxt(path, np.c_[t, y], delimiter=",", header="t,v", comments="")
    code = main(["mismatch", str(path), "--model", "hum", "--param", f"harmonics={harmonics}", "--param", "f0=50",
                 "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 1 and message in err and len(err.splitlines()) == 1
