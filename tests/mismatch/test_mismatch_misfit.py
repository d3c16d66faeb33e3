"""A calibration that leaves a residual far above the noise is never reported as "nothing missing", and a
spread the fit could not determine is never printed as a zero-width interval."""
import numpy as np
import pytest

from odnn_sep.mismatch import explain
from odnn_sep.mismatch.report import NOT_DETERMINED, result_dict, summary_text


@pytest.fixture(scope="module")
def misfit_result():
    # a falling body under a chirp no effect of the library (nor a single periodic pickup) describes
    t = np.linspace(0, 1, 300)
    y = 2 - 4.9 * t ** 2 + 0.3 * np.sin(2 * np.pi * (3 * t + 6 * t ** 2))
    return explain("freefall", t, y + 0.01 * np.random.default_rng(0).normal(size=300))


def test_a_fit_far_above_the_noise_is_not_nothing_missing(misfit_result):
    d = result_dict(misfit_result)
    v = d["verdict"]
    assert v["effect"] is None and v["effects"] == []
    assert v["status"] == "model_does_not_fit"
    assert v["misfit"]["rms_over_noise"] > 3 and v["misfit"]["p_value"] < 1e-6
    first = summary_text(misfit_result).splitlines()[0]
    assert first.startswith("Verdict: the model does not fit the data: the residual is ")
    assert "nothing missing" not in first
    assert "no effect in the library explains it" in first and "--param" in first and "time unit" in first


def test_a_good_fit_still_reads_nothing_missing():
    t = np.linspace(0, 100, 300)
    y = 20 + 70 * np.exp(-0.03 * t) + 0.05 * np.random.default_rng(1).normal(size=300)
    d = result_dict(explain("cooling", t, y))
    assert d["verdict"]["status"] == "nothing_missing" and d["verdict"]["misfit"] is None
    assert d["verdict"]["description"].startswith("nothing missing that the data can show")


def test_an_undetermined_spread_is_not_printed_as_zero_width():
    t = np.linspace(0, 100, 300)
    y = 20 + 70 * np.exp(-0.03 * t) + 0.05 * np.random.default_rng(1).normal(size=300)
    res = explain("cooling", t, y)
    res.calibration.fit.stderr["h"] = 0.0        # what a flat Jacobian column gives on noisy data
    text = summary_text(res)
    line = next(s for s in text.splitlines() if s.strip().startswith("h = "))
    assert line.endswith(NOT_DETERMINED) and "± 0" not in line and "95%" not in line
    p = result_dict(res)["calibration"]["parameters"]["h"]
    assert p["stderr"] is None and p["interval95"] is None
    # a spread below the float resolution of the value counts the same
    res.calibration.fit.stderr["h"] = 1e-20
    assert result_dict(res)["calibration"]["parameters"]["h"]["interval95"] is None
    res.calibration.fit.stderr["T0"] = float("nan")
    assert "T0" not in res.calibration.fit.intervals()
